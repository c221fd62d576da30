// Re-training the audio part of a joint audio-visual HMM on speech-only recordings of other speakers
// (Terissi & Gómez 2008, stage 2): the mouth model keeps its visual behaviour and learns new voices.
//
//   th::hmm::AudioRetrainingResult r = th::hmm::retrainAudio(jointModel, audioSequences /* d_a x T each */, {});
//   r.model;                  // same π, A, weights, visual means and covariances; new audio means/covariances
//   r.repairedComponents;     // how many joint covariances needed their audio-visual block shrunk
//
// The audio-only marginal model (same π, A, mixture weights) is re-estimated by Baum-Welch with π, A and the
// weights held fixed; then each joint covariance is rebuilt from the new Σᵃ and the old Σᵃᵛ, Σᵛ. That matrix
// need not be positive definite (the old cross-covariance may not fit the new audio spread); if it is not, Σᵃᵛ
// is shrunk by factors of 0.9 until the Schur complement Σᵛ − Σᵛᵃ(Σᵃ)⁻¹Σᵃᵛ is positive definite.
// Thread contract: pure function.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "hmm/hmm_model.h"

namespace th::hmm {

struct AudioRetrainingOptions {
  std::string audioBlock = "audio";
  std::string visualBlock = "visual";
  int iterations = 10;
  double varianceFloorFraction = 1e-3;
};

struct AudioRetrainingResult {
  HmmModel model;
  int repairedComponents = 0;
  std::vector<double> logLikelihoods;  // of the audio data under the audio marginal, before each iteration
};

AudioRetrainingResult retrainAudio(const HmmModel& jointModel, const std::vector<Eigen::MatrixXd>& audioSequences,
                                   const AudioRetrainingOptions& options);

// Joint covariance from blocks, shrinking the cross-covariance until positive definite. Returns the shrink
// factor applied (1 = none). `audio` and `visual` index the joint dimensions.
double assembleJointCovariance(const Eigen::MatrixXd& audioCovariance, const Eigen::MatrixXd& crossAudioVisual,
                               const Eigen::MatrixXd& visualCovariance, const ObservationBlock& audio,
                               const ObservationBlock& visual, Eigen::MatrixXd& joint);

}  // namespace th::hmm
