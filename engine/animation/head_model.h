// Head motion from prosody (the first source paper, plus a smooth trajectory and an online version).
//
//   th::animation::HeadModel model = th::animation::trainHeadModel({trainingPart}, {});
//   th::animation::saveHeadModel("models/head.json", model);
//   Eigen::MatrixXd rotations = th::animation::synthesiseHead(model, prosody, voiced, {});   // the trajectory
//
//   th::animation::HeadSynthesiser live(model, {.variant = HeadVariant::kTrajectory, .maxLagFrames = 6});
//   live.acceptProsody(p, voiced);  while (live.numReady() > next) use(live.rotation(next++));
//
// Training (paper, steps 1-3): an HMM of head rotations [pitch, yaw, roll] with one full Gaussian per state,
// trained with Brand's entropic prior from a generous fully connected start; then, with the state posteriors γ
// of the motion training data, every state gets the γ-weighted mean and covariance of the rotation velocities
// (Δ) and accelerations (ΔΔ, for the trajectory) and, over voiced frames only, of the prosody [pitch, energy,
// Δpitch, Δenergy]. The result is one HMM with four independent blocks: "motion" (3), "motion_delta" (3),
// "motion_acceleration" (3) and "prosody" (4), saved in the ordinary model file with the mean pose and the
// amplitude in its "training" object.
// Several speakers: each speaker's rotations are taken about its own mean pose and (normaliseSpeakers) divided
// by its own per-axis spread, so the states hold shapes of motion rather than one speaker's size; synthesis
// multiplies by `amplitude`, the speakers' geometric mean spread (and by the options' amplitude).
// Step 3 (ours): the training motion less its trajectory from the prosody is the motion the voice does not
// explain; its per-axis spread and step are kept, and the trajectory variant adds a random process like it
// (seeded), quieter in pauses: the states alone give a curve far smoother and smaller than real motion.
// Synthesis decodes the prosody block with the shared transitions. Frames without a voice (unvoiced or
// silent) carry no prosody the model learnt: with voicedOnly their emissions are equal for every state, so the
// decoder keeps its state through pauses and the head settles instead of wandering.
//   kStateMeans      the paper: Viterbi states, each frame the state's mean pose (steps at state changes);
//   kTrajectory      ours: the same states, then the maximum-likelihood trajectory of poses, velocities and
//                    accelerations (mlpg.h), which has no jumps, plus the residual motion;
//   kPosteriorMeans  ours: each frame Σⱼ γₜ(j) μⱼ (forward-backward), smooth but damped.
// Online (maxLagFrames ≥ 0): online Viterbi with that maximum lag, or fixed-lag smoothing for posterior means;
// the trajectory waits trajectoryLookaheadFrames more and solves over a window of past frames.
// Thread contract: models are values; a HeadSynthesiser belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "animation/head_data.h"
#include "hmm/hmm_model.h"
#include "hmm/training.h"

namespace th::animation {

struct HeadModelOptions {
  int startStates = 24;                  // a generous, fully connected start
  double entropicWeightPerFrame = 0.05;  // Z = this x training frames
  double covariancePriorWeight = 0.0;
  int warmupIterations = 10;
  int rampIterations = 20;
  int maxIterations = 150;
  unsigned seed = 1;
  bool normaliseSpeakers = true;  // each speaker's motion in units of its own per-axis spread
  // The residual's size from each speaker's trajectory under a model trained without it (one more training
  // per speaker), rather than from the model's own trajectory on its training speech.
  bool residualFromHeldOutSpeakers = true;
};

struct HeadModel {
  hmm::HmmModel hmm;  // blocks motion | motion_delta | motion_acceleration | prosody (older: no acceleration)
  bool hasAcceleration = false;
  Eigen::Vector3d meanPose = Eigen::Vector3d::Zero();   // degrees: the training speakers' mean rest pose
  Eigen::Vector3d amplitude = Eigen::Vector3d::Ones();  // degrees per unit of the motion block
  // The motion the voice does not explain (model units, per axis): its spread and frame-to-frame step.
  Eigen::Vector3d residualStd = Eigen::Vector3d::Zero();
  Eigen::Vector3d residualStepStd = Eigen::Vector3d::Zero();
  std::vector<std::string> speakers;          // trained on
  std::vector<hmm::IterationRecord> history;  // of the motion HMM's training (empty when loaded)
};

HeadModel trainHeadModel(const std::vector<HeadRecording>& parts, const HeadModelOptions& options);

// The ordinary HMM model file; the "training" object holds the mean pose and the options. Errors name the file.
void saveHeadModel(const std::filesystem::path& path, const HeadModel& model, const HeadModelOptions& options);
HeadModel loadHeadModel(const std::filesystem::path& path);

enum class HeadVariant { kStateMeans, kTrajectory, kPosteriorMeans };

// The online decoder's decision lag that live use runs with, frames: on speakers never trained on, lags of 0
// to 12 frames give the same spread, speed, jumps and distribution of motion (docs/head.md), so the live head
// waits for the least that keeps its state decisions steady.
inline constexpr int kLiveHeadLagFrames = 2;

struct HeadSynthesisOptions {
  HeadVariant variant = HeadVariant::kTrajectory;
  int maxLagFrames = -1;                               // < 0: batch (whole input); >= 0: online with this decoding lag
  int trajectoryLookaheadFrames = 3;                   // online trajectory: decided states needed past the output frame
  int trajectoryWindowFrames = 30;                     // online trajectory: past frames in each solve
  double amplitude = 1.0;                              // times the model's amplitude
  Eigen::Vector3d axisGain = Eigen::Vector3d::Ones();  // per axis (pitch, yaw, roll), times that (a head style's)
  Eigen::Vector3d restPose = Eigen::Vector3d::Zero();  // degrees added to every rotation (a head style's)
  double smoothing = 1.0;       // times the velocity and acceleration precisions: above 1, slower and smoother
  bool voicedOnly = true;       // unvoiced and silent frames do not move the decoder
  double variation = 1.0;       // trajectory: times the residual motion (0: the states' smooth curve alone)
  double pauseVariation = 0.4;  // the residual's gain in pauses (eased to after 0.3 s without a voice)
  unsigned seed = 1;            // of the residual motion
  // Above 0: no frame-to-frame step (the norm over the axes, degrees, before the amplitude) is longer than this;
  // a longer one is shortened to it and the rest follows in the next frames. A head style sets it to the
  // person's fast steps (their 99th percentile), so the styled head does not move faster than they do.
  double maxStepDegrees = 0.0;
};

// The most frames a rotation waits for past its own input under these options (batch: unbounded, -1).
int headLookaheadFrames(const HeadSynthesisOptions& options);

// Rotations relative to the rest pose (3 x T, degrees; plus options.restPose) for a prosody sequence (4 x T) and
// its voicing (T: 1 voiced, 0 not; empty: every frame voiced).
Eigen::MatrixXd synthesiseHead(const HeadModel& model, const Eigen::MatrixXd& prosody, const Eigen::RowVectorXd& voiced,
                               const HeadSynthesisOptions& options = {});

// HeadSynthesisOptions::maxStepDegrees's limit on 3 x T rotations, in place (nothing when it is 0).
void limitHeadSteps(Eigen::MatrixXd& rotations, double maxStepDegrees);

class HeadSynthesiser {
 public:
  HeadSynthesiser(const HeadModel& model, const HeadSynthesisOptions& options);
  ~HeadSynthesiser();
  HeadSynthesiser(const HeadSynthesiser&) = delete;
  HeadSynthesiser& operator=(const HeadSynthesiser&) = delete;

  void acceptProsody(const Eigen::Vector4d& prosody, bool voiced);
  void finish();
  int numReady() const;
  Eigen::Vector3d rotation(int frame) const;  // relative to the mean pose (plus options.restPose), degrees
  int lookaheadFrames() const;                // headLookaheadFrames of its options
  // Rotations before `frame` will not be read again: they, and the decoder's states no later frame needs, are
  // freed (an endless stream stays bounded; not the posterior-means variant's smoother).
  void forgetBefore(int frame);
  std::size_t framesHeld() const;
  // P(state | the prosody so far) after the latest acceptProsody(): the forward filter, for a display of the
  // model's belief (the decoder's decisions wait for its lag; this does not).
  const Eigen::VectorXd& filteredPosterior() const;
  int numStates() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The prosody marginal of a head model (A, π and the prosody block), for decoding.
hmm::HmmModel prosodyModel(const HeadModel& model);

// A random walk through the motion HMM (states drawn from π and A), each frame its state's mean pose: the
// baseline that has the model's motion but no voice.
Eigen::MatrixXd randomWalkHead(const HeadModel& model, int numFrames, unsigned seed);

}  // namespace th::animation
