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
