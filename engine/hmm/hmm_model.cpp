#include "hmm/hmm_model.h"

#include <cmath>

#include "core/error.h"

namespace th::hmm {

void HmmModel::check() const {
  const auto n = static_cast<Eigen::Index>(states.size());
  if (n == 0) throw Error("HMM: no states");
  if (initial.size() != n) throw Error("HMM: initial probabilities do not match the number of states");
  if (transition.rows() != n || transition.cols() != n) throw Error("HMM: transition matrix is not N x N");
  if (!initial.allFinite() || !transition.allFinite()) throw Error("HMM: probabilities are not finite");
  if ((initial.array() < 0.0).any() || std::abs(initial.sum() - 1.0) > 1e-6) {
    throw Error("HMM: initial probabilities must be non-negative and sum to 1");
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if ((transition.row(i).array() < 0.0).any() || std::abs(transition.row(i).sum() - 1.0) > 1e-6) {
      throw Error("HMM: transition row " + std::to_string(i) + " must be non-negative and sum to 1");
    }
  }
  for (const auto& state : states) {
    if (state.dimension() != dimension()) throw Error("HMM: states differ in observation dimension");
  }
  if (!columnNames.empty() && static_cast<int>(columnNames.size()) != dimension()) {
    throw Error("HMM: column names do not match the observation dimension");
  }
  int next = 0;
  for (const auto& b : blocks) {
    if (b.begin != next || b.size <= 0) throw Error("HMM: observation blocks must tile the dimensions in order");
    next += b.size;
  }
  if (!blocks.empty() && next != dimension()) throw Error("HMM: observation blocks do not cover every dimension");
}

const ObservationBlock& HmmModel::block(const std::string& name) const {
  for (const auto& b : blocks) {
    if (b.name == name) return b;
  }
  throw Error("HMM: the model has no observation block named '" + name + "'");
}

Eigen::MatrixXd HmmModel::emissionLogLikelihoods(const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                                 std::vector<Eigen::MatrixXd>* componentLogDensities) const {
  if (frames.rows() != dimension()) throw Error("HMM: observations have the wrong dimension");
  Eigen::MatrixXd logB(numStates(), frames.cols());
  Eigen::VectorXd row(frames.cols());
  if (componentLogDensities) componentLogDensities->resize(static_cast<size_t>(numStates()));
  for (int j = 0; j < numStates(); ++j) {
    states[static_cast<size_t>(j)].logDensities(
        frames, row, componentLogDensities ? &(*componentLogDensities)[static_cast<size_t>(j)] : nullptr);
    logB.row(j) = row.transpose();
  }
  return logB;
}

}  // namespace th::hmm
