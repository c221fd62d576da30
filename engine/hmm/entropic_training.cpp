#include "hmm/entropic_training.h"

#include <algorithm>

#include "core/error.h"
#include "hmm/entropic.h"

namespace th::hmm {
namespace {

constexpr double kDeadOccupancy = 1e-9;  // expected frames

}  // namespace

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
    for (Eigen::Index b = 0; b < kept; ++b)
      transition(a, b) = model.transition(keep[static_cast<size_t>(a)], keep[static_cast<size_t>(b)]);
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
  initial = initial.sum() > 0.0 ? Eigen::VectorXd(initial / initial.sum())
                                : Eigen::VectorXd::Constant(kept, 1.0 / static_cast<double>(kept));
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

double EntropicPrior::weightAt(int iteration) const {
  if (iteration < warmupIterations) return 0.0;
  if (rampIterations <= 0) return multinomialWeight;
  const double progress = static_cast<double>(iteration - warmupIterations + 1) / rampIterations;
  return multinomialWeight * std::min(1.0, progress);
}

EstimationHooks entropicHooks(const EntropicPrior& prior) {
  EstimationHooks hooks;
  hooks.multinomial = [prior](Multinomial which, const Eigen::VectorXd& counts, const Eigen::VectorXd& previous,
                              const MStepContext& context) {
    const double z = prior.weightAt(context.iteration);
    Eigen::VectorXd evidence = counts;
    Eigen::VectorXd current = previous;
    // Trimming compares first-order gradients, which only predict the effect of removing a parameter near a
    // stationary point: never from the initial model itself (measured: from the fully connected k-means start
    // it removes what the next iterations would need). trainHmm retries, then undoes, a trimming step that
    // lowers the log posterior. π is not trimmed: a model decodes streams that start anywhere, and a start
    // state trimmed away would make them impossible from there. (States that only π keeps alive die when no
    // frame visits them; see afterMStep.)
    const bool mayTrim = prior.trim && context.mayTrim && which != Multinomial::kInitial && context.iteration >= 1 &&
                         previous.size() == counts.size();
    if (mayTrim && trimWeakParameters(current, counts, z, context.trimMargin) > 0) {
      for (Eigen::Index i = 0; i < evidence.size(); ++i) {
        if (current[i] == 0.0) evidence[i] = 0.0;
      }
    }
    // Entries already extinct stay extinct (their count is 0 because θ = 0 made them unreachable).
    const EntropicEstimate estimate = entropicMap(evidence, z);
    // Generalised EM: the W₋₁ stationary point is not always the row's maximum (many weak entries against a
    // large Z), so keep the current row if it scores higher on the same evidence; the posterior cannot fall.
    if (previous.size() == counts.size() &&
        entropicObjective(current, evidence, z) > entropicObjective(estimate.probabilities, evidence, z)) {
      return Eigen::VectorXd(current / current.sum());
    }
    return estimate.probabilities;
  };
  hooks.multinomialLogPrior = [prior](const Eigen::VectorXd& theta, int iteration) {
    return entropicLogPrior(theta, prior.weightAt(iteration));
  };
  hooks.covariancePriorWeight = prior.covarianceWeight;
  // Z = 0 is maximum likelihood exactly: no structural moves then.
  hooks.stateMergeCandidates = prior.trim && prior.multinomialWeight > 0.0 ? prior.mergeCandidates : 0;
  hooks.priorFinalFrom = prior.warmupIterations + std::max(prior.rampIterations - 1, 0);
  hooks.afterMStep = [prior](HmmModel& model, const Eigen::VectorXd& stateOccupancy, const MStepContext& context) {
    if (!prior.trim || !context.mayTrim || prior.weightAt(context.iteration) <= 0.0) return;
    // Descending, so that the occupancy (indexed by the states before any deletion) stays aligned.
    for (int j = model.numStates() - 1; j >= 0 && model.numStates() > 1; --j) {
      // A state that no frame visits (less than a billionth of a frame in all) contributes nothing to the
      // likelihood, only to the prior's cost.
      bool reachable = model.initial[j] > 0.0 && stateOccupancy[j] >= kDeadOccupancy;
      for (int i = 0; i < model.numStates() && !reachable && stateOccupancy[j] >= kDeadOccupancy; ++i) {
        reachable = i != j && model.transition(i, j) > 0.0;
      }
      if (!reachable) deleteState(model, j);
    }
  };
  return hooks;
}

}  // namespace th::hmm
