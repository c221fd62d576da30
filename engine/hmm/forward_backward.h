// Forward-backward (Rabiner 1989, with per-frame scaling) over one observation sequence.
//
//   th::hmm::Posteriors p = th::hmm::forwardBackward(model, model.emissionLogLikelihoods(frames));
//   p.logLikelihood;          // log P(X | model)
//   p.stateGivenAll(j, t);    // γₜ(j) = P(sₜ = j | X)
//
// Scaling: emissions are exponentiated relative to each frame's best state (bⱼ(xₜ)/maxₖ bₖ(xₜ)), and α is
// renormalised every frame (cₜ); log P(X) = Σₜ (log cₜ + maxₖ log bₖ(xₜ)). This keeps every number in range for
// sequences of any length without log-domain sums in the inner loop.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "core/frame_store.h"
#include "hmm/hmm_model.h"

namespace th::hmm {

struct Posteriors {
  Eigen::MatrixXd stateGivenAll;     // γ (N x T), each column sums to 1
  Eigen::MatrixXd transitionCounts;  // Σₜ ξₜ(i, j) (N x N): expected transitions
  double logLikelihood = 0.0;
};

// logEmissions: N x T from HmmModel::emissionLogLikelihoods. Throws th::Error if the sequence is impossible
// under the model (every path has probability 0).
// `firstFrameDistribution`, if given, replaces π as the distribution of the first frame's state (a window of a
// longer stream starts from the forward variables carried over from the previous window).
Posteriors forwardBackward(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions,
                           const Eigen::VectorXd* firstFrameDistribution = nullptr);

// log P(X | model) by the forward pass alone.
double logLikelihood(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions);

}  // namespace th::hmm

namespace th::hmm {

// Fixed-lag smoothing: the posterior of frame t given frames up to t + lag, as frames stream in.
//
//   th::hmm::FixedLagSmoother smoother(model, /*lagFrames=*/10);
//   smoother.acceptFrame(logEmission);                 // N values: log bⱼ(xₜ)
//   while (smoother.numReady() > next) use(smoother.posterior(next++));
//   smoother.finish();                                 // the last frames, smoothed over what remains
//
// The forward variables are kept for the last lag + 1 frames; each new frame runs the backward recursion over
// that window from β = 1. With a lag at least the sequence length the result equals forwardBackward's γ.
// Thread contract: one thread per instance; the model must outlive the smoother (it is referenced, not copied).
class FixedLagSmoother {
 public:
  FixedLagSmoother(const HmmModel& model, int lagFrames);

  void acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& logEmission);
  void finish();

  int numReady() const { return static_cast<int>(posteriors_.size()); }
  const Eigen::VectorXd& posterior(int frame) const { return posteriors_[static_cast<size_t>(frame)]; }
  // Posteriors before `frame` will not be read again: they are freed (a live stream runs for hours).
  void forgetBefore(int frame) { posteriors_.forgetBefore(static_cast<size_t>(std::max(0, frame))); }

 private:
  void emitOldest(Eigen::Index windowFrames);
  const Eigen::VectorXd& lastAlpha() const;

  const HmmModel& model_;
  int lagFrames_;
  std::vector<Eigen::VectorXd> window_;  // normalised α of the frames not yet emitted

  std::vector<Eigen::VectorXd> scaledEmissions_;
  FrameStore<Eigen::VectorXd> posteriors_;
  Eigen::VectorXd lastEmittedAlpha_;  // α of the newest emitted frame, when the window is empty
  bool finished_ = false;
};

}  // namespace th::hmm
