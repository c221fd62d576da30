// A hidden Markov model with Gaussian-mixture emissions, and the emission log-likelihoods of a sequence.
//
//   th::hmm::HmmModel model = ...;                      // trained, or loaded
//   Eigen::MatrixXd logB = model.emissionLogLikelihoods(frames);   // N x T, frames: d x T
//
// Orientation: transition(i, j) = P(state j at t+1 | state i at t), rows sum to 1; observations are columns.
// Thread contract: a model is a value; once built it is only read, so it is safe to share across threads.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "hmm/gaussian.h"

namespace th::hmm {

// A named, contiguous range of observation dimensions, e.g. {"audio", 0, 121} and {"visual", 121, 2}.
struct ObservationBlock {
  std::string name;
  int begin = 0;
  int size = 0;
};

struct HmmModel {
  Eigen::VectorXd initial;               // π (N), sums to 1
  Eigen::MatrixXd transition;            // A (N x N), rows sum to 1
  std::vector<GaussianMixture> states;   // emission densities
  std::vector<std::string> columnNames;  // what each observation dimension is (may be empty)
  std::vector<ObservationBlock> blocks;  // partition of the dimensions (empty: one unnamed block)

  int numStates() const { return static_cast<int>(states.size()); }
  int dimension() const { return states.empty() ? 0 : states.front().dimension(); }
  CovarianceType covarianceType() const {
    return states.empty() || states.front().components().empty() ? CovarianceType::kFull
                                                                 : states.front().components().front().type();
  }
  // The block with this name; throws th::Error if there is none.
  const ObservationBlock& block(const std::string& name) const;
  // Throws th::Error describing the first inconsistency (shapes, finiteness, stochastic rows).
  void check() const;

  // log bⱼ(xₜ) for every state and frame (N x T). With `componentLogDensities`, also each state's
  // log wₘ + log Nₘ(xₜ) (M x T per state), which the M-step needs.
  Eigen::MatrixXd emissionLogLikelihoods(const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                         std::vector<Eigen::MatrixXd>* componentLogDensities = nullptr) const;
};

}  // namespace th::hmm
