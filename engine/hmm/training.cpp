#include "hmm/training.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/error.h"
#include "hmm/forward_backward.h"

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

Eigen::VectorXd normalised(const Eigen::VectorXd& counts) { return counts / counts.sum(); }

Eigen::VectorXd estimate(const EstimationHooks& hooks, Multinomial which, const Eigen::VectorXd& counts,
                         const Eigen::VectorXd& previous) {
  if (!(counts.sum() > 0.0)) return previous;  // no evidence at all: keep what we had
  Eigen::VectorXd theta = hooks.multinomial ? hooks.multinomial(which, counts, previous) : normalised(counts);
  if (!theta.allFinite()) throw Error("HMM training: a multinomial estimate is not finite");
  return theta;
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
      const std::vector<int> componentOf = kMeans(points, options.numMixtures, options.kmeansIterations, random, subCentres);
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

double modelLogPrior(const HmmModel& model, const EstimationHooks& hooks) {
  double total = 0.0;
  if (hooks.multinomialLogPrior) {
    total += hooks.multinomialLogPrior(model.initial);
    for (Eigen::Index i = 0; i < model.transition.rows(); ++i) {
      total += hooks.multinomialLogPrior(model.transition.row(i).transpose());
    }
    for (const auto& state : model.states) total += hooks.multinomialLogPrior(state.weights());
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

IterationRecord baumWelchIteration(HmmModel& model, const std::vector<Eigen::MatrixXd>& sequences,
                                   const TrainingOptions& options, const Eigen::VectorXd& varianceFloor,
                                   const EstimationHooks& hooks) {
  const int n = model.numStates();
  const Eigen::Index d = model.dimension();
  IterationRecord record;
  record.liveStates = n;
  record.logPrior = modelLogPrior(model, hooks);

  // E-step: expected counts over all sequences.
  Eigen::VectorXd initialCounts = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd transitionCounts = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd stateOccupancy = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::VectorXd> componentCounts(static_cast<size_t>(n));
  std::vector<Eigen::MatrixXd> firstMoments(static_cast<size_t>(n));
  std::vector<std::vector<Eigen::MatrixXd>> secondMoments(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) {
    const int m = model.states[static_cast<size_t>(j)].numComponents();
    componentCounts[static_cast<size_t>(j)] = Eigen::VectorXd::Zero(m);
    firstMoments[static_cast<size_t>(j)] = Eigen::MatrixXd::Zero(d, m);
    secondMoments[static_cast<size_t>(j)].assign(static_cast<size_t>(m),
                                                 options.covariance == CovarianceType::kFull
                                                     ? Eigen::MatrixXd::Zero(d, d)
                                                     : Eigen::MatrixXd::Zero(d, 1));
  }
  std::vector<Eigen::MatrixXd> componentLog;
  for (const auto& frames : sequences) {
    if (frames.cols() == 0) continue;
    const Eigen::MatrixXd logB = model.emissionLogLikelihoods(frames, &componentLog);
    const Posteriors posteriors = forwardBackward(model, logB);
    record.logLikelihood += posteriors.logLikelihood;
    initialCounts += posteriors.stateGivenAll.col(0);
    transitionCounts += posteriors.transitionCounts;
    stateOccupancy += posteriors.stateGivenAll.rowwise().sum();
    for (int j = 0; j < n; ++j) {
      const Eigen::MatrixXd& terms = componentLog[static_cast<size_t>(j)];
      for (Eigen::Index m = 0; m < terms.rows(); ++m) {
        // γₜ(j, m) = γₜ(j) · wₘ Nₘ(xₜ) / bⱼ(xₜ)
        // Responsibilities below 1e-300 count as 0: they add nothing a double can hold, and subnormal
        // numbers make the products below many times slower.
        const Eigen::VectorXd responsibility =
            (posteriors.stateGivenAll.row(j).array() * (terms.row(m) - logB.row(j)).array().exp())
                .transpose()
                .unaryExpr([](double r) { return r < 1e-300 ? 0.0 : r; });
        componentCounts[static_cast<size_t>(j)][m] += responsibility.sum();
        firstMoments[static_cast<size_t>(j)].col(m) += frames * responsibility;
        if (options.covariance == CovarianceType::kFull) {
          // Σₜ γₜ xₜxₜᵀ as a rank update of the lower triangle with the frames that carry weight: (X·diag(√γ)).
          Eigen::Index used = 0;
          for (Eigen::Index t = 0; t < responsibility.size(); ++t) used += responsibility[t] > 0.0;
          Eigen::MatrixXd weighted(frames.rows(), used);
          for (Eigen::Index t = 0, k = 0; t < responsibility.size(); ++t) {
            if (responsibility[t] > 0.0) weighted.col(k++) = frames.col(t) * std::sqrt(responsibility[t]);
          }
          secondMoments[static_cast<size_t>(j)][static_cast<size_t>(m)].selfadjointView<Eigen::Lower>().rankUpdate(weighted);
        } else {
          secondMoments[static_cast<size_t>(j)][static_cast<size_t>(m)] += frames.cwiseAbs2() * responsibility;
        }
      }
    }
  }

  // M-step.
  model.initial = estimate(hooks, Multinomial::kInitial, initialCounts, model.initial);
  for (int i = 0; i < n; ++i) {
    model.transition.row(i) = estimate(hooks, Multinomial::kTransitionRow, transitionCounts.row(i).transpose(),
                                     model.transition.row(i).transpose()).transpose();
  }
  for (int j = 0; j < n; ++j) {
    const GaussianMixture& old = model.states[static_cast<size_t>(j)];
    const Eigen::VectorXd& counts = componentCounts[static_cast<size_t>(j)];
    const Eigen::VectorXd weights = estimate(hooks, Multinomial::kMixtureWeights, counts, old.weights());
    std::vector<Gaussian> components;
    for (int m = 0; m < old.numComponents(); ++m) {
      const double gamma = counts[m];
      if (gamma < 1e-8) {  // no evidence: keep the old density (its weight is ~0 anyway)
        components.push_back(old.components()[static_cast<size_t>(m)]);
        continue;
      }
      const Eigen::VectorXd mean = firstMoments[static_cast<size_t>(j)].col(m) / gamma;
      // Scatter S = Σₜ γ (x − μ)(x − μ)ᵀ; ML divides by Γ, the entropic prior by Γ + Z_Σ (Brand 1999).
      const double divisor = gamma + hooks.covariancePriorWeight;
      Eigen::MatrixXd covariance;
      if (options.covariance == CovarianceType::kFull) {
        const Eigen::MatrixXd second =
            secondMoments[static_cast<size_t>(j)][static_cast<size_t>(m)].selfadjointView<Eigen::Lower>();
        covariance = (second - gamma * mean * mean.transpose()) / divisor;
      } else {
        covariance = ((secondMoments[static_cast<size_t>(j)][static_cast<size_t>(m)].col(0) - gamma * mean.cwiseAbs2()) / divisor).asDiagonal();
      }
      components.emplace_back(mean, applyCovarianceFloor(covariance, varianceFloor, options.covariance), options.covariance);
    }
    model.states[static_cast<size_t>(j)] = GaussianMixture(weights, std::move(components));
  }
  if (hooks.afterMStep) hooks.afterMStep(model, stateOccupancy);
  model.check();
  return record;
}

TrainingResult trainHmm(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options,
                        const EstimationHooks& hooks) {
  TrainingResult result;
  result.model = initialiseWithKMeans(sequences, options);
  const Eigen::VectorXd floor = varianceFloorFor(sequences, options.varianceFloorFraction);
  double totalFrames = 0.0;
  for (const auto& sequence : sequences) totalFrames += static_cast<double>(sequence.cols());
  for (int iteration = 0; iteration < options.maxIterations; ++iteration) {
    result.history.push_back(baumWelchIteration(result.model, sequences, options, floor, hooks));
    const auto& records = result.history;
    if (records.size() >= 2) {
      const double gain = (records.back().logPosterior() - records[records.size() - 2].logPosterior()) / totalFrames;
      if (std::abs(gain) < options.tolerance) {
        result.converged = true;
        break;
      }
    }
  }
  // The score of the model returned (the history holds each iteration's starting model).
  IterationRecord final;
  final.liveStates = result.model.numStates();
  final.logPrior = modelLogPrior(result.model, hooks);
  for (const auto& frames : sequences) {
    if (frames.cols() > 0) final.logLikelihood += logLikelihood(result.model, result.model.emissionLogLikelihoods(frames));
  }
  result.history.push_back(final);
  return result;
}

}  // namespace th::hmm
