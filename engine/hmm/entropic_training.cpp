#include "hmm/entropic_training.h"

#include "core/error.h"
#include "hmm/entropic.h"

namespace th::hmm {

void deleteState(HmmModel& model, int state) {
  const int n = model.numStates();
  if (n <= 1) throw Error("HMM: cannot delete the last state");
  std::vector<Eigen::Index> keep;
  for (int j = 0; j < n; ++j) {
    if (j != state) keep.push_back(j);
  }
  const auto kept = static_cast<Eigen::Index>(keep.size());
  Eigen::MatrixXd transition(kept, kept);
  Eigen::VectorXd initial(kept);
  for (Eigen::Index a = 0; a < kept; ++a) {
    initial[a] = model.initial[keep[static_cast<size_t>(a)]];
    for (Eigen::Index b = 0; b < kept; ++b) transition(a, b) = model.transition(keep[static_cast<size_t>(a)], keep[static_cast<size_t>(b)]);
  }
  for (Eigen::Index a = 0; a < kept; ++a) {
    const double sum = transition.row(a).sum();
    // A row that only led to the deleted state keeps the chain alive by staying put.
    if (sum > 0.0) {
      transition.row(a) /= sum;
    } else {
      transition.row(a).setZero();
      transition(a, a) = 1.0;
    }
  }
  initial = initial.sum() > 0.0 ? Eigen::VectorXd(initial / initial.sum()) : Eigen::VectorXd::Constant(kept, 1.0 / static_cast<double>(kept));
  model.initial = initial;
  model.transition = transition;
  model.states.erase(model.states.begin() + state);
}

int countTransitions(const HmmModel& model, double threshold) {
  int count = 0;
  for (Eigen::Index i = 0; i < model.transition.rows(); ++i) {
    for (Eigen::Index j = 0; j < model.transition.cols(); ++j) count += model.transition(i, j) > threshold;
  }
  return count;
}

EstimationHooks entropicHooks(const EntropicPrior& prior) {
  EstimationHooks hooks;
  const double z = prior.multinomialWeight;
  const bool trim = prior.trim;
  hooks.multinomial = [z, trim](const Eigen::VectorXd& counts, const Eigen::VectorXd& previous) {
    Eigen::VectorXd evidence = counts;
    if (trim && previous.size() == counts.size()) {
      Eigen::VectorXd current = previous;
      if (trimWeakParameters(current, counts, z) > 0) {
        for (Eigen::Index i = 0; i < evidence.size(); ++i) {
          if (current[i] == 0.0) evidence[i] = 0.0;
        }
      }
    }
    // Entries already extinct stay extinct (their count is 0 because θ = 0 made them unreachable).
    return entropicMap(evidence, z).probabilities;
  };
  hooks.multinomialLogPrior = [z](const Eigen::VectorXd& theta) { return entropicLogPrior(theta, z); };
  hooks.covariancePriorWeight = prior.covarianceWeight;
  if (trim) {
    hooks.afterMStep = [](HmmModel& model, const Eigen::VectorXd&) {
      for (int j = model.numStates() - 1; j >= 0 && model.numStates() > 1; --j) {
        bool reachable = model.initial[j] > 0.0;
        for (int i = 0; i < model.numStates() && !reachable; ++i) reachable = i != j && model.transition(i, j) > 0.0;
        if (!reachable) deleteState(model, j);
      }
    };
  }
  return hooks;
}

}  // namespace th::hmm
