#include "hmm/state_merging.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace th::hmm {
namespace {

// Pooled zeroth, first and second moments of one mixture component (second: d x d lower, or d x 1 diagonal).
struct Moments {
  double count = 0.0;
  Eigen::VectorXd first;
  Eigen::MatrixXd second;
};

Moments momentsOf(const SufficientStatistics& statistics, int state, int component) {
  const auto j = static_cast<size_t>(state);
  return {statistics.componentCounts[j][component], statistics.firstMoments[j].col(component),
          statistics.secondMoments[j][static_cast<size_t>(component)]};
}

Moments pooled(const Moments& a, const Moments& b) {
  return {a.count + b.count, a.first + b.first, a.second + b.second};
}

// Σ = (second − Γ μμᵀ) / (Γ + Z_Σ), floored.
Eigen::MatrixXd covarianceOf(const Moments& moments, const Eigen::VectorXd& floor, CovarianceType type,
                             double priorWeight) {
  const Eigen::VectorXd mean = moments.first / moments.count;
  const double divisor = moments.count + priorWeight;
  Eigen::MatrixXd covariance;
  if (type == CovarianceType::kFull) {
    covariance =
        (Eigen::MatrixXd(moments.second.selfadjointView<Eigen::Lower>()) - moments.count * mean * mean.transpose()) /
        divisor;
  } else {
    covariance = ((moments.second.col(0) - moments.count * mean.cwiseAbs2()) / divisor).asDiagonal();
  }
  return applyCovarianceFloor(covariance, floor, type);
}

double logDeterminant(const Eigen::MatrixXd& covariance) {
  return Gaussian(Eigen::VectorXd::Zero(covariance.rows()), covariance, CovarianceType::kFull).logDeterminant();
}

// For each component of state a, the component of b it pools with: nearest means, each used once (greedy).
std::vector<int> pairComponents(const HmmModel& model, int a, int b) {
  const auto& first = model.states[static_cast<size_t>(a)].components();
  const auto& second = model.states[static_cast<size_t>(b)].components();
  std::vector<int> partner(first.size(), -1);
  std::vector<bool> taken(second.size(), false);
  for (size_t round = 0; round < first.size(); ++round) {
    double best = std::numeric_limits<double>::infinity();
    size_t bestA = 0;
    size_t bestB = 0;
    for (size_t i = 0; i < first.size(); ++i) {
      if (partner[i] >= 0) continue;
      for (size_t k = 0; k < second.size(); ++k) {
        if (taken[k]) continue;
        const double distance = (first[i].mean() - second[k].mean()).squaredNorm();
        if (distance < best) {
          best = distance;
          bestA = i;
          bestB = k;
        }
      }
    }
    partner[bestA] = static_cast<int>(bestB);
    taken[bestB] = true;
  }
  return partner;
}

// ½ Γ log|Σ| of a component's own covariance, from its moments (no prior, tiny floor): the emission cost term.
double emissionCost(const Moments& moments, CovarianceType type, const Eigen::VectorXd& floor) {
  if (moments.count <= 0.0) return 0.0;
  return 0.5 * moments.count * logDeterminant(covarianceOf(moments, floor, type, 0.0));
}

}  // namespace

std::vector<std::pair<int, int>> mergeCandidates(const HmmModel& model, const SufficientStatistics& statistics,
                                                 int count) {
  const int n = model.numStates();
  const CovarianceType type = model.covarianceType();
  const Eigen::VectorXd floor = Eigen::VectorXd::Constant(model.dimension(), 1e-12);
  std::vector<std::pair<double, std::pair<int, int>>> scored;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (model.states[static_cast<size_t>(a)].numComponents() != model.states[static_cast<size_t>(b)].numComponents())
        continue;
      const std::vector<int> partner = pairComponents(model, a, b);
      double cost = 0.0;
      for (size_t m = 0; m < partner.size(); ++m) {
        const Moments first = momentsOf(statistics, a, static_cast<int>(m));
        const Moments second = momentsOf(statistics, b, partner[m]);
        cost += emissionCost(pooled(first, second), type, floor) - emissionCost(first, type, floor) -
                emissionCost(second, type, floor);
      }
      scored.push_back({cost, {a, b}});
    }
  }
  const auto kept = std::min(scored.size(), static_cast<size_t>(std::max(count, 0)));
  std::partial_sort(scored.begin(), scored.begin() + static_cast<long>(kept), scored.end());
  std::vector<std::pair<int, int>> pairs;
  for (size_t i = 0; i < kept; ++i) pairs.push_back(scored[i].second);
  return pairs;
}

HmmModel mergeStates(const HmmModel& model, const SufficientStatistics& statistics, int a, int b,
                     const Eigen::VectorXd& varianceFloor, double covariancePriorWeight) {
  const int n = model.numStates();
  if (a == b || a < 0 || b < 0 || a >= n || b >= n) {
    throw Error("HMM: cannot merge states " + std::to_string(a) + " and " + std::to_string(b));
  }
  if (a > b) std::swap(a, b);
  const CovarianceType type = model.covarianceType();
  HmmModel merged = model;

  // Incoming: whatever entered a or b now enters the merged state. Outgoing: the pooled expected counts (the
  // pooled rows if neither state was visited), with a ↔ b transitions becoming self-transitions.
  merged.initial[a] += merged.initial[b];
  merged.transition.col(a) += merged.transition.col(b);
  Eigen::VectorXd outgoing = (statistics.transitionCounts.row(a) + statistics.transitionCounts.row(b)).transpose();
  if (!(outgoing.sum() > 0.0)) outgoing = (model.transition.row(a) + model.transition.row(b)).transpose();
  outgoing[a] += outgoing[b];
  outgoing[b] = 0.0;
  merged.transition.row(a) = (outgoing / outgoing.sum()).transpose();

  const std::vector<int> partner = pairComponents(model, a, b);
  const int numComponents = static_cast<int>(partner.size());
  Eigen::VectorXd weights(numComponents);
  std::vector<Gaussian> components;
  for (int m = 0; m < numComponents; ++m) {
    const Moments moments =
        pooled(momentsOf(statistics, a, m), momentsOf(statistics, b, partner[static_cast<size_t>(m)]));
    weights[m] = moments.count;
    if (moments.count < 1e-8) {
      components.push_back(model.states[static_cast<size_t>(a)].components()[static_cast<size_t>(m)]);
      continue;
    }
    components.emplace_back(moments.first / moments.count,
                            covarianceOf(moments, varianceFloor, type, covariancePriorWeight), type);
  }
  weights =
      weights.sum() > 0.0 ? Eigen::VectorXd(weights / weights.sum()) : model.states[static_cast<size_t>(a)].weights();
  merged.states[static_cast<size_t>(a)] = GaussianMixture(weights, std::move(components));

  // Drop b (its row, column and entry of π); the column was folded into a, so rows still sum to 1.
  std::vector<Eigen::Index> keep;
  for (int j = 0; j < n; ++j) {
    if (j != b) keep.push_back(j);
  }
  const auto kept = static_cast<Eigen::Index>(keep.size());
  Eigen::MatrixXd transition(kept, kept);
  Eigen::VectorXd initial(kept);
  for (Eigen::Index r = 0; r < kept; ++r) {
    initial[r] = merged.initial[keep[static_cast<size_t>(r)]];
    for (Eigen::Index c = 0; c < kept; ++c)
      transition(r, c) = merged.transition(keep[static_cast<size_t>(r)], keep[static_cast<size_t>(c)]);
  }
  merged.initial = initial;
  merged.transition = transition;
  merged.states.erase(merged.states.begin() + b);
  merged.check();
  return merged;
}

}  // namespace th::hmm
