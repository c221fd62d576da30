#include "hmm/forward_backward.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace th::hmm {
namespace {

// Scaled emissions: B(j, t) = exp(log bⱼ(xₜ) − maxₖ log bₖ(xₜ)); frameOffset(t) = that maximum.
void scaleEmissions(const Eigen::Ref<const Eigen::MatrixXd>& logEmissions, Eigen::MatrixXd& scaled,
                    Eigen::VectorXd& frameOffset) {
  frameOffset = logEmissions.colwise().maxCoeff().transpose();
  if (!frameOffset.allFinite()) {
    for (Eigen::Index t = 0; t < frameOffset.size(); ++t) {
      if (!std::isfinite(frameOffset[t])) {
        throw Error("HMM: frame " + std::to_string(t) + " has no finite emission likelihood in any state");
      }
    }
  }
  scaled = (logEmissions.rowwise() - frameOffset.transpose()).array().exp();
}

// α, normalised per frame; returns the scales cₜ. Throws if a frame is unreachable.
// A frame's emissions are scaled relative to the best state overall; when every state that can be reached has an
// emission far below it (more than ~745 nats: sharp full-covariance densities on unseen data), the scaled values
// underflow to 0 and the frame would look impossible. Then the frame is rescaled relative to the best reachable
// state instead (and the offset corrected), which is exact: unreachable states contribute nothing either way.
void forwardPass(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions, Eigen::MatrixXd& scaled,
                 Eigen::VectorXd& frameOffset, Eigen::MatrixXd& alpha, Eigen::VectorXd& scales,
                 const Eigen::VectorXd& initial) {
  const Eigen::Index numFrames = scaled.cols();
  alpha.resize(scaled.rows(), numFrames);
  scales.resize(numFrames);
  Eigen::VectorXd predicted;
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    if (t == 0) {
      predicted = initial;
    } else {
      predicted.noalias() = model.transition.transpose() * alpha.col(t - 1);
    }
    alpha.col(t) = predicted.cwiseProduct(scaled.col(t));
    scales[t] = alpha.col(t).sum();
    if (!(scales[t] > 0.0)) {
      double best = -std::numeric_limits<double>::infinity();
      for (Eigen::Index j = 0; j < predicted.size(); ++j) {
        if (predicted[j] > 0.0) best = std::max(best, logEmissions(j, t));
      }
      if (std::isfinite(best)) {
        scaled.col(t) = (logEmissions.col(t).array() - best).min(0.0).exp();
        frameOffset[t] = best;
        alpha.col(t) = predicted.cwiseProduct(scaled.col(t));
        scales[t] = alpha.col(t).sum();
      }
    }
    if (!(scales[t] > 0.0))
      throw Error("HMM: the sequence is impossible under the model at frame " + std::to_string(t));
    alpha.col(t) /= scales[t];
  }
}

}  // namespace

double logLikelihood(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions) {
  if (logEmissions.cols() == 0) return 0.0;
  Eigen::MatrixXd scaled;
  Eigen::VectorXd offsets;
  scaleEmissions(logEmissions, scaled, offsets);
  Eigen::MatrixXd alpha;
  Eigen::VectorXd scales;
  forwardPass(model, logEmissions, scaled, offsets, alpha, scales, model.initial);
  return scales.array().log().sum() + offsets.sum();
}

Posteriors forwardBackward(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions,
                           const Eigen::VectorXd* firstFrameDistribution) {
  const Eigen::Index numStates = model.numStates();
  const Eigen::Index numFrames = logEmissions.cols();
  if (logEmissions.rows() != numStates) throw Error("HMM: emission matrix does not match the number of states");
  Posteriors result;
  result.transitionCounts = Eigen::MatrixXd::Zero(numStates, numStates);
  if (numFrames == 0) {
    result.stateGivenAll.resize(numStates, 0);
    return result;
  }
  Eigen::MatrixXd scaled;
  Eigen::VectorXd offsets;
  scaleEmissions(logEmissions, scaled, offsets);
  Eigen::MatrixXd alpha;
  Eigen::VectorXd scales;
  forwardPass(model, logEmissions, scaled, offsets, alpha, scales,
              firstFrameDistribution ? *firstFrameDistribution : model.initial);
  result.logLikelihood = scales.array().log().sum() + offsets.sum();

  // β is renormalised to a maximum of 1 at every frame instead of dividing by cₜ₊₁: when trimmed transitions
  // leave a frame explainable only by an unlikely state, cₜ₊₁ can be ~1e-300 and β/cₜ₊₁ would overflow. γ and
  // ξ are then normalised per frame (their scale cancels).
  Eigen::VectorXd beta = Eigen::VectorXd::Ones(numStates);
  result.stateGivenAll.resize(numStates, numFrames);
  result.stateGivenAll.col(numFrames - 1) = alpha.col(numFrames - 1);
  // Every buffer is made once: nothing is allocated per frame.
  Eigen::VectorXd weightedNext(numStates), gamma(numStates);
  Eigen::MatrixXd xi(numStates, numStates);
  for (Eigen::Index t = numFrames - 2; t >= 0; --t) {
    weightedNext = scaled.col(t + 1).cwiseProduct(beta);
    xi.noalias() = alpha.col(t) * weightedNext.transpose();
    xi.array() *= model.transition.array();
    const double xiSum = xi.sum();
    if (xiSum > 0.0) result.transitionCounts += xi / xiSum;
    beta.noalias() = model.transition * weightedNext;
    const double betaMax = beta.maxCoeff();
    if (betaMax > 0.0) beta /= betaMax;
    gamma = alpha.col(t).cwiseProduct(beta);
    const double gammaSum = gamma.sum();
    if (gammaSum > 0.0) {
      result.stateGivenAll.col(t) = gamma / gammaSum;
    } else {
      result.stateGivenAll.col(t) = alpha.col(t);
    }
  }
  return result;
}

}  // namespace th::hmm

namespace th::hmm {

FixedLagSmoother::FixedLagSmoother(const HmmModel& model, int lagFrames) : model_(model), lagFrames_(lagFrames) {
  if (lagFrames < 0) throw Error("fixed-lag smoother: the lag must be >= 0");
}

void FixedLagSmoother::acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& logEmission) {
  if (finished_) throw Error("fixed-lag smoother: acceptFrame after finish");
  const double offset = logEmission.maxCoeff();
  if (!std::isfinite(offset)) throw Error("fixed-lag smoother: a frame has no finite emission likelihood");
  Eigen::VectorXd scaled = (logEmission.array() - offset).exp();
  const bool first = window_.empty() && posteriors_.empty();
  const Eigen::VectorXd predicted =
      first ? model_.initial : Eigen::VectorXd(model_.transition.transpose() * lastAlpha());
  Eigen::VectorXd alpha = predicted.cwiseProduct(scaled);
  double sum = alpha.sum();
  if (!(sum > 0.0)) {
    // Every reachable state's emission underflowed against the best state's: rescale relative to the best
    // reachable one (as forwardPass does; the scale cancels in the posteriors).
    double best = -std::numeric_limits<double>::infinity();
    for (Eigen::Index j = 0; j < predicted.size(); ++j) {
      if (predicted[j] > 0.0) best = std::max(best, logEmission[j]);
    }
    if (std::isfinite(best)) {
      scaled = (logEmission.array() - best).min(0.0).exp();
      alpha = predicted.cwiseProduct(scaled);
      sum = alpha.sum();
    }
  }
  if (!(sum > 0.0)) throw Error("fixed-lag smoother: the stream is impossible under the model");
  alpha /= sum;
  window_.push_back(std::move(alpha));
  scaledEmissions_.push_back(scaled);
  if (static_cast<int>(window_.size()) > lagFrames_) emitOldest(static_cast<Eigen::Index>(window_.size()));
}

const Eigen::VectorXd& FixedLagSmoother::lastAlpha() const {
  return window_.empty() ? lastEmittedAlpha_ : window_.back();
}

void FixedLagSmoother::emitOldest(Eigen::Index windowFrames) {
  // Backward over the window from β = 1 at its newest frame, renormalised each step (only the shape matters).
  Eigen::VectorXd beta = Eigen::VectorXd::Ones(model_.numStates());
  for (Eigen::Index k = windowFrames - 1; k >= 1; --k) {
    beta = model_.transition * scaledEmissions_[static_cast<size_t>(k)].cwiseProduct(beta);
    beta /= beta.maxCoeff();
  }
  Eigen::VectorXd gamma = window_.front().cwiseProduct(beta);
  gamma /= gamma.sum();
  posteriors_.push_back(std::move(gamma));
  lastEmittedAlpha_ = window_.front();
  window_.erase(window_.begin());
  scaledEmissions_.erase(scaledEmissions_.begin());
}

void FixedLagSmoother::finish() {
  if (finished_) return;
  finished_ = true;
  while (!window_.empty()) emitOldest(static_cast<Eigen::Index>(window_.size()));
}

}  // namespace th::hmm
