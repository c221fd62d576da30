#include "hmm/training.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/error.h"
#include "hmm/forward_backward.h"
#include "hmm/state_merging.h"

namespace th::hmm {
namespace {

Eigen::MatrixXd pool(const std::vector<Eigen::MatrixXd>& sequences) {
  Eigen::Index total = 0;
  for (const auto& sequence : sequences) total += sequence.cols();
  Eigen::MatrixXd all(sequences.front().rows(), total);
  Eigen::Index column = 0;
  for (const auto& sequence : sequences) {
    all.middleCols(column, sequence.cols()) = sequence;
    column += sequence.cols();
  }
  return all;
}

// k-means++ seeding (Arthur & Vassilvitskii 2007) and Lloyd iterations over the columns of `points`.
// Returns the cluster of every point; `centres` receives k columns.
std::vector<int> kMeans(const Eigen::MatrixXd& points, int k, int iterations, std::mt19937& random,
                        Eigen::MatrixXd& centres) {
  const Eigen::Index n = points.cols();
  centres.resize(points.rows(), k);
  std::uniform_int_distribution<Eigen::Index> pick(0, n - 1);
  centres.col(0) = points.col(pick(random));
  Eigen::VectorXd nearest = (points.colwise() - centres.col(0)).colwise().squaredNorm().transpose();
  for (int c = 1; c < k; ++c) {
    const double total = nearest.sum();
    Eigen::Index chosen = pick(random);
    if (total > 0.0) {
      std::uniform_real_distribution<double> uniform(0.0, total);
      double target = uniform(random);
      for (chosen = 0; chosen < n - 1 && target > nearest[chosen]; ++chosen) target -= nearest[chosen];
    }
    centres.col(c) = points.col(chosen);
    nearest = nearest.cwiseMin((points.colwise() - centres.col(c)).colwise().squaredNorm().transpose());
  }
  std::vector<int> assignment(static_cast<size_t>(n), 0);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    bool changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index best = 0;
      (centres.colwise() - points.col(i)).colwise().squaredNorm().minCoeff(&best);
      if (assignment[static_cast<size_t>(i)] != static_cast<int>(best)) changed = true;
      assignment[static_cast<size_t>(i)] = static_cast<int>(best);
    }
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(points.rows(), k);
    Eigen::VectorXd counts = Eigen::VectorXd::Zero(k);
    for (Eigen::Index i = 0; i < n; ++i) {
      sums.col(assignment[static_cast<size_t>(i)]) += points.col(i);
      counts[assignment[static_cast<size_t>(i)]] += 1.0;
    }
    for (int c = 0; c < k; ++c) {
      if (counts[c] > 0.0) centres.col(c) = sums.col(c) / counts[c];
    }
    if (!changed && iteration > 0) break;
  }
  return assignment;
}

Gaussian fitGaussian(const Eigen::MatrixXd& points, const Eigen::VectorXd& floor, CovarianceType type) {
  const Eigen::VectorXd mean = points.rowwise().mean();
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(points.rows(), points.rows());
  if (points.cols() > 1) {
    const Eigen::MatrixXd centred = points.colwise() - mean;
    covariance = centred * centred.transpose() / static_cast<double>(points.cols());
  }
  return Gaussian(mean, applyCovarianceFloor(covariance, floor, type), type);
}

Eigen::VectorXd normalised(const Eigen::VectorXd& counts) {
  return counts / counts.sum();
}

Eigen::VectorXd estimate(const EstimationHooks& hooks, Multinomial which, const Eigen::VectorXd& counts,
                         const Eigen::VectorXd& previous, const MStepContext& context) {
  if (!(counts.sum() > 0.0)) return previous;  // no evidence at all: keep what we had
  Eigen::VectorXd theta = hooks.multinomial ? hooks.multinomial(which, counts, previous, context) : normalised(counts);
  if (!theta.allFinite()) throw Error("HMM training: a multinomial estimate is not finite");
  return theta;
}

// Zero entries of π, A and the mixture weights, and the number of states: an M-step that changes these trimmed.
std::pair<int, Eigen::Index> structureOf(const HmmModel& model) {
  Eigen::Index zeros = (model.initial.array() == 0.0).count() + (model.transition.array() == 0.0).count();
  for (const auto& state : model.states) zeros += (state.weights().array() == 0.0).count();
  return {model.numStates(), zeros};
}

// State merging is tried once EM gains less than this per frame, and a merge is judged after this many EM
// iterations.
constexpr double kMergeTolerance = 1e-3;
constexpr int kMergeSettleIterations = 5;
// Margins of the trimming test for an M-step and its retries; 0: no trimming.
constexpr double kTrimMargins[] = {1.0, 10.0, 100.0, 0.0};

double posteriorOf(const HmmModel& model, double logLikelihood, const EstimationHooks& hooks, int iteration) {
  return logLikelihood + modelLogPrior(model, hooks, iteration);
}

}  // namespace

Eigen::VectorXd varianceFloorFor(const std::vector<Eigen::MatrixXd>& sequences, double fraction) {
  const Eigen::MatrixXd all = pool(sequences);
  const Eigen::VectorXd mean = all.rowwise().mean();
  const Eigen::VectorXd variance = (all.colwise() - mean).cwiseAbs2().rowwise().mean();
  return (fraction * variance).cwiseMax(1e-10);
}

HmmModel initialiseWithKMeans(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options) {
  if (sequences.empty()) throw Error("HMM training: no sequences");
  const Eigen::MatrixXd all = pool(sequences);
  if (all.cols() < options.numStates * options.numMixtures) {
    throw Error("HMM training: fewer frames than states x mixtures");
  }
  const Eigen::VectorXd floor = varianceFloorFor(sequences, options.varianceFloorFraction);
  std::mt19937 random(options.seed);
  Eigen::MatrixXd centres;
  const std::vector<int> stateOf = kMeans(all, options.numStates, options.kmeansIterations, random, centres);

  HmmModel model;
  const int n = options.numStates;
  model.initial = Eigen::VectorXd::Constant(n, 1.0 / n);
  model.transition = Eigen::MatrixXd::Constant(n, n, 1.0 / n);  // a generous, fully connected start
  for (int j = 0; j < n; ++j) {
    std::vector<Eigen::Index> members;
    for (Eigen::Index i = 0; i < all.cols(); ++i) {
      if (stateOf[static_cast<size_t>(i)] == j) members.push_back(i);
    }
    if (static_cast<int>(members.size()) < options.numMixtures) {
      // An empty or tiny cluster: borrow the points nearest its centre.
      const Eigen::VectorXd distance = (all.colwise() - centres.col(j)).colwise().squaredNorm().transpose();
      std::vector<Eigen::Index> order(static_cast<size_t>(all.cols()));
      for (Eigen::Index i = 0; i < all.cols(); ++i) order[static_cast<size_t>(i)] = i;
      const auto needed = static_cast<size_t>(std::max(2, options.numMixtures * 2));
      std::partial_sort(order.begin(), order.begin() + static_cast<long>(needed), order.end(),
                        [&](Eigen::Index a, Eigen::Index b) { return distance[a] < distance[b]; });
      members.assign(order.begin(), order.begin() + static_cast<long>(needed));
    }
    Eigen::MatrixXd points(all.rows(), static_cast<Eigen::Index>(members.size()));
    for (size_t i = 0; i < members.size(); ++i) points.col(static_cast<Eigen::Index>(i)) = all.col(members[i]);
    std::vector<Gaussian> components;
    Eigen::VectorXd weights(options.numMixtures);
    if (options.numMixtures == 1) {
      components.push_back(fitGaussian(points, floor, options.covariance));
      weights[0] = 1.0;
    } else {
      Eigen::MatrixXd subCentres;
      const std::vector<int> componentOf =
          kMeans(points, options.numMixtures, options.kmeansIterations, random, subCentres);
      for (int m = 0; m < options.numMixtures; ++m) {
        std::vector<Eigen::Index> inside;
        for (size_t i = 0; i < componentOf.size(); ++i) {
          if (componentOf[i] == m) inside.push_back(static_cast<Eigen::Index>(i));
        }
        if (inside.empty()) inside.push_back(0);
        Eigen::MatrixXd subset(points.rows(), static_cast<Eigen::Index>(inside.size()));
        for (size_t i = 0; i < inside.size(); ++i) subset.col(static_cast<Eigen::Index>(i)) = points.col(inside[i]);
        components.push_back(fitGaussian(subset, floor, options.covariance));
        weights[m] = static_cast<double>(inside.size());
      }
      weights /= weights.sum();
    }
    model.states.emplace_back(weights, std::move(components));
  }
  model.check();
  return model;
}

double modelLogPrior(const HmmModel& model, const EstimationHooks& hooks, int iteration) {
  double total = 0.0;
  if (hooks.multinomialLogPrior) {
    total += hooks.multinomialLogPrior(model.initial, iteration);
    for (Eigen::Index i = 0; i < model.transition.rows(); ++i) {
      total += hooks.multinomialLogPrior(model.transition.row(i).transpose(), iteration);
    }
    for (const auto& state : model.states) total += hooks.multinomialLogPrior(state.weights(), iteration);
  }
  if (hooks.covariancePriorWeight != 0.0) {
    // −Z_Σ · H(N) with H = ½ (d log(2πe) + log|Σ|), for every component in use.
    for (const auto& state : model.states) {
      for (int m = 0; m < state.numComponents(); ++m) {
        if (state.weights()[m] <= 0.0) continue;
        const Gaussian& g = state.components()[static_cast<size_t>(m)];
        total -= 0.5 * hooks.covariancePriorWeight *
                 (g.dimension() * std::log(2.0 * std::numbers::pi * std::numbers::e) + g.logDeterminant());
      }
    }
  }
  return total;
}

SufficientStatistics expectationStep(const HmmModel& model, const std::vector<Eigen::MatrixXd>& sequences) {
  const int n = model.numStates();
  const Eigen::Index d = model.dimension();
  const bool full = model.covarianceType() == CovarianceType::kFull;
  SufficientStatistics statistics;
  statistics.initialCounts = Eigen::VectorXd::Zero(n);
  statistics.transitionCounts = Eigen::MatrixXd::Zero(n, n);
  statistics.stateOccupancy = Eigen::VectorXd::Zero(n);
  statistics.componentCounts.resize(static_cast<size_t>(n));
  statistics.firstMoments.resize(static_cast<size_t>(n));
  statistics.secondMoments.resize(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) {
    const int m = model.states[static_cast<size_t>(j)].numComponents();
    statistics.componentCounts[static_cast<size_t>(j)] = Eigen::VectorXd::Zero(m);
    statistics.firstMoments[static_cast<size_t>(j)] = Eigen::MatrixXd::Zero(d, m);
    statistics.secondMoments[static_cast<size_t>(j)].assign(
        static_cast<size_t>(m), full ? Eigen::MatrixXd::Zero(d, d) : Eigen::MatrixXd::Zero(d, 1));
  }
  std::vector<Eigen::MatrixXd> componentLog;
  Eigen::VectorXd responsibility;  // a component's γₜ(j, m) over a sequence, made once per sequence length
  for (const auto& frames : sequences) {
    if (frames.cols() == 0) continue;
    const Eigen::MatrixXd logB = model.emissionLogLikelihoods(frames, &componentLog);
    const Posteriors posteriors = forwardBackward(model, logB);
    statistics.logLikelihood += posteriors.logLikelihood;
    statistics.initialCounts += posteriors.stateGivenAll.col(0);
    statistics.transitionCounts += posteriors.transitionCounts;
    statistics.stateOccupancy += posteriors.stateGivenAll.rowwise().sum();
    for (int j = 0; j < n; ++j) {
      const Eigen::MatrixXd& terms = componentLog[static_cast<size_t>(j)];
      for (Eigen::Index m = 0; m < terms.rows(); ++m) {
        // γₜ(j, m) = γₜ(j) · wₘ Nₘ(xₜ) / bⱼ(xₜ)
        // Responsibilities below 1e-300 count as 0: they add nothing a double can hold, and subnormal
        // numbers make the products below many times slower.
        responsibility = (posteriors.stateGivenAll.row(j).array() * (terms.row(m) - logB.row(j)).array().exp())
                             .transpose()
                             .unaryExpr([](double r) { return r < 1e-300 ? 0.0 : r; });
        statistics.componentCounts[static_cast<size_t>(j)][m] += responsibility.sum();
        statistics.firstMoments[static_cast<size_t>(j)].col(m) += frames * responsibility;
        Eigen::MatrixXd& second = statistics.secondMoments[static_cast<size_t>(j)][static_cast<size_t>(m)];
        if (full) {
          // Σₜ γₜ xₜxₜᵀ as a rank update of the lower triangle with the frames that carry weight: (X·diag(√γ)).
          Eigen::Index used = 0;
          for (Eigen::Index t = 0; t < responsibility.size(); ++t) used += responsibility[t] > 0.0;
          // No frame of this sequence in this component: nothing to add (and Eigen's blocking heuristic divides
          // by the inner dimension, so a d x 0 rank update would raise SIGFPE).
          if (used == 0) continue;
          Eigen::MatrixXd weighted(frames.rows(), used);
          for (Eigen::Index t = 0, k = 0; t < responsibility.size(); ++t) {
            if (responsibility[t] > 0.0) weighted.col(k++) = frames.col(t) * std::sqrt(responsibility[t]);
          }
          second.selfadjointView<Eigen::Lower>().rankUpdate(weighted);
        } else {
          second += frames.cwiseAbs2() * responsibility;
        }
      }
    }
  }
  return statistics;
}

void maximisationStep(HmmModel& model, const SufficientStatistics& statistics, const Eigen::VectorXd& varianceFloor,
                      const EstimationHooks& hooks, const MStepContext& context) {
  const int n = model.numStates();
  const CovarianceType type = model.covarianceType();
  model.initial = estimate(hooks, Multinomial::kInitial, statistics.initialCounts, model.initial, context);
  for (int i = 0; i < n; ++i) {
    model.transition.row(i) =
        estimate(hooks, Multinomial::kTransitionRow, statistics.transitionCounts.row(i).transpose(),
                 model.transition.row(i).transpose(), context)
            .transpose();
  }
  for (int j = 0; j < n; ++j) {
    const GaussianMixture& old = model.states[static_cast<size_t>(j)];
    const Eigen::VectorXd& counts = statistics.componentCounts[static_cast<size_t>(j)];
    const Eigen::VectorXd weights = estimate(hooks, Multinomial::kMixtureWeights, counts, old.weights(), context);
    std::vector<Gaussian> components;
    for (int m = 0; m < old.numComponents(); ++m) {
      const double gamma = counts[m];
      if (gamma < 1e-8) {  // no evidence: keep the old density (its weight is ~0 anyway)
        components.push_back(old.components()[static_cast<size_t>(m)]);
        continue;
      }
      const Eigen::VectorXd mean = statistics.firstMoments[static_cast<size_t>(j)].col(m) / gamma;
      const Eigen::MatrixXd& second = statistics.secondMoments[static_cast<size_t>(j)][static_cast<size_t>(m)];
      // Scatter S = Σₜ γ (x − μ)(x − μ)ᵀ; ML divides by Γ, the entropic prior by Γ + Z_Σ (Brand 1999).
      const double divisor = gamma + hooks.covariancePriorWeight;
      Eigen::MatrixXd covariance;
      if (type == CovarianceType::kFull) {
        covariance =
            (Eigen::MatrixXd(second.selfadjointView<Eigen::Lower>()) - gamma * mean * mean.transpose()) / divisor;
      } else {
        covariance = ((second.col(0) - gamma * mean.cwiseAbs2()) / divisor).asDiagonal();
      }
      components.emplace_back(mean, applyCovarianceFloor(covariance, varianceFloor, type), type);
    }
    model.states[static_cast<size_t>(j)] = GaussianMixture(weights, std::move(components));
  }
  if (hooks.afterMStep) hooks.afterMStep(model, statistics.stateOccupancy, context);
  model.check();
}

IterationRecord baumWelchIteration(HmmModel& model, const std::vector<Eigen::MatrixXd>& sequences,
                                   const Eigen::VectorXd& varianceFloor, const EstimationHooks& hooks,
                                   const MStepContext& context) {
  const SufficientStatistics statistics = expectationStep(model, sequences);
  IterationRecord record;
  record.liveStates = model.numStates();
  record.logLikelihood = statistics.logLikelihood;
  record.logPrior = modelLogPrior(model, hooks, context.iteration);
  maximisationStep(model, statistics, varianceFloor, hooks, context);
  return record;
}

namespace {

// The most similar pairs of states tried in turn, each merge judged after a few EM iterations without trimming (the
// other parameters need them to adapt: measured, right after the merge most profitable merges still score lower),
// against the unmerged model after as many. The first that scores higher is kept (model, statistics, `after` and the
// record updated): true; false when none does.
bool mergeIfBetter(HmmModel& model, SufficientStatistics& statistics, const std::vector<Eigen::MatrixXd>& sequences,
                   const Eigen::VectorXd& floor, const EstimationHooks& hooks, int iteration, double& after,
                   IterationRecord& record) {
  auto settle = [&](HmmModel& settling, SufficientStatistics& settlingStatistics) {
    for (int step = 0; step < kMergeSettleIterations; ++step) {
      maximisationStep(settling, settlingStatistics, floor, hooks, {.iteration = iteration, .mayTrim = false});
      settlingStatistics = expectationStep(settling, sequences);
    }
    return posteriorOf(settling, settlingStatistics.logLikelihood, hooks, iteration);
  };
  HmmModel unmerged = model;
  SufficientStatistics unmergedStatistics = statistics;
  const double threshold = std::max(after, settle(unmerged, unmergedStatistics));
  for (const auto& [a, b] : mergeCandidates(model, statistics, hooks.stateMergeCandidates)) {
    HmmModel merged = mergeStates(model, statistics, a, b, floor, hooks.covariancePriorWeight);
    SufficientStatistics mergedStatistics = expectationStep(merged, sequences);
    const double mergedPosterior = settle(merged, mergedStatistics);
    if (mergedPosterior > threshold) {
      record.stepGain += mergedPosterior - after;
      after = mergedPosterior;
      model = std::move(merged);
      statistics = std::move(mergedStatistics);
      ++record.statesMerged;
      return true;
    }
  }
  return false;
}

}  // namespace

TrainingResult trainHmm(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options,
                        const EstimationHooks& hooks) {
  TrainingResult result;
  HmmModel model = initialiseWithKMeans(sequences, options);
  const Eigen::VectorXd floor = varianceFloorFor(sequences, options.varianceFloorFraction);
  double totalFrames = 0.0;
  for (const auto& sequence : sequences) totalFrames += static_cast<double>(sequence.cols());
  SufficientStatistics statistics = expectationStep(model, sequences);
  bool mergesExhausted = false;  // every candidate failed and the structure has not changed since
  for (int iteration = 0; iteration < options.maxIterations; ++iteration) {
    IterationRecord record;
    record.liveStates = model.numStates();
    record.logLikelihood = statistics.logLikelihood;
    record.logPrior = modelLogPrior(model, hooks, iteration);
    const double before = record.logPosterior();

    // Trimming is judged on first-order gradients and can lose more likelihood than it gains in prior (a rare
    // transition that was the only good path, say). Then the step is retried with a wider margin, and at
    // last without trimming, which cannot lower the log posterior.
    HmmModel candidate;
    SufficientStatistics candidateStatistics;
    double after = 0.0;
    for (const double margin : kTrimMargins) {
      const bool mayTrim = margin > 0.0;
      candidate = model;
      maximisationStep(candidate, statistics, floor, hooks,
                       {.iteration = iteration, .mayTrim = mayTrim, .trimMargin = margin});
      candidateStatistics = expectationStep(candidate, sequences);
      after = posteriorOf(candidate, candidateStatistics.logLikelihood, hooks, iteration);
      if (!mayTrim || after >= before || structureOf(candidate) == structureOf(model)) break;
      ++record.trimRetries;
    }
    if (structureOf(candidate) != structureOf(model)) mergesExhausted = false;
    model = std::move(candidate);
    statistics = std::move(candidateStatistics);
    const bool priorSettled = iteration >= hooks.priorFinalFrom;
    record.stepGain = after - before;
    // At the final prior, once EM gains little, try merging the most similar pairs of states.
    const bool settled = priorSettled && std::abs(record.stepGain) / totalFrames < kMergeTolerance;
    if (settled && !mergesExhausted && hooks.stateMergeCandidates > 0 && model.numStates() > 1) {
      mergesExhausted = !mergeIfBetter(model, statistics, sequences, floor, hooks, iteration, after, record);
    }
    result.history.push_back(record);
    // Converged when the step gained (almost) nothing, the prior no longer changes and no merge was kept.
    if (priorSettled && record.statesMerged == 0 && std::abs(record.stepGain) / totalFrames < options.tolerance) {
      result.converged = true;
      break;
    }
  }
  // The score of the model returned (the history holds each iteration's starting model).
  IterationRecord final;
  final.liveStates = model.numStates();
  final.logLikelihood = statistics.logLikelihood;
  final.logPrior = modelLogPrior(model, hooks, static_cast<int>(result.history.size()));
  result.history.push_back(final);
  result.model = std::move(model);
  return result;
}

}  // namespace th::hmm
