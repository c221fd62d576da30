// Tests of the entropic MAP estimator and of trimming (engine/hmm/entropic.h).
// Facts checked: Lagrangian stationarity and Σθ = 1 to rounding; F(θ*) beats random and nearby points of the
// simplex and a fine grid; Z = 0 is ω/Σω bit for bit; entropy moves the right way; agreement with Boost.Math's
// Lambert W where the direct formula is representable; the large-count regime where it is not; the no-solution
// fallback; degenerate rows; trimming removes exactly what the criterion names.
#include "hmm/entropic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/special_functions/lambert_w.hpp>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

namespace th::hmm {
namespace {

// Counts log-uniform in [low, high]; a `zeroFraction` of them set to 0 (but never all).
Eigen::VectorXd randomCounts(std::mt19937_64& rng, int size, double low, double high, double zeroFraction = 0.0) {
  std::uniform_real_distribution<double> logCount(std::log(low), std::log(high));
  std::bernoulli_distribution isZero(zeroFraction);
  Eigen::VectorXd counts(size);
  for (int i = 0; i < size; ++i) counts[i] = isZero(rng) ? 0.0 : std::exp(logCount(rng));
  if (counts.sum() == 0.0) counts[0] = std::exp(logCount(rng));
  return counts;
}

Eigen::VectorXd dirichletSample(std::mt19937_64& rng, const Eigen::VectorXd& alpha) {
  Eigen::VectorXd x(alpha.size());
  for (Eigen::Index i = 0; i < alpha.size(); ++i) x[i] = std::gamma_distribution<double>(alpha[i], 1.0)(rng);
  return x / x.sum();
}

double entropy(const Eigen::VectorXd& theta) {
  double h = 0.0;
  for (double t : theta) {
    if (t > 0.0) h -= t * std::log(t);
  }
  return h;
}

// F written out again here (not entropicObjective), so the tests do not grade the library with its own formula.
double objective(const Eigen::VectorXd& theta, const Eigen::VectorXd& counts, double z) {
  double f = 0.0;
  for (Eigen::Index i = 0; i < theta.size(); ++i) {
    if (counts[i] > 0.0) f += counts[i] * std::log(theta[i]);
    if (theta[i] > 0.0) f += z * theta[i] * std::log(theta[i]);
  }
  return f;
}

// max over observed i of |ωᵢ/θᵢ + Z(log θᵢ + 1) + λ|, each relative to the largest of its three terms.
double stationarityResidual(const EntropicEstimate& estimate, const Eigen::VectorXd& counts, double z) {
  double worst = 0.0;
  const double lambda = estimate.lagrangeMultiplier.value();
  for (Eigen::Index i = 0; i < counts.size(); ++i) {
    if (counts[i] == 0.0) continue;
    const double likelihoodTerm = counts[i] / estimate.probabilities[i];
    const double priorTerm = z * (std::log(estimate.probabilities[i]) + 1.0);
    const double size = std::max({std::abs(likelihoodTerm), std::abs(priorTerm), std::abs(lambda)});
    worst = std::max(worst, std::abs(likelihoodTerm + priorTerm + lambda) / size);
  }
  return worst;
}

const std::vector<double> kPriorWeights = {0.1, 1.0, 10.0, 1000.0};

TEST(EntropicMap, ZeroPriorIsMaximumLikelihoodBitForBit) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 500; ++trial) {
    const int size = 1 + trial % 100;
    const Eigen::VectorXd counts = randomCounts(rng, size, 1e-8, 1e7, 0.2);
    const EntropicEstimate estimate = entropicMap(counts, 0.0);
    ASSERT_EQ(estimate.outcome, EntropicOutcome::kMaximumLikelihood);
    for (int i = 0; i < size; ++i) EXPECT_EQ(estimate.probabilities[i], counts[i] / counts.sum());
    EXPECT_EQ(estimate.lagrangeMultiplier.value(), -counts.sum());
  }
}

// Over random rows (sizes 2..50, counts 1e-3..1e5, some zeros), every solved row satisfies
// ωᵢ/θᵢ + Z(log θᵢ + 1) + λ = 0 to 1e-9 of its terms and Σθ = 1 to 1e-12; unobserved entries stay 0.
TEST(EntropicMap, StationaryForPositiveAndNegativePriorWeights) {
  std::mt19937_64 rng(2);
  std::uniform_int_distribution<int> size(2, 50);
  for (double sign : {1.0, -1.0}) {
    for (double magnitude : kPriorWeights) {
      const double z = sign * magnitude;
      double worstResidual = 0.0;
      double worstSumError = 0.0;
      int solved = 0;
      int fallbacks = 0;
      const int numTrials = 400;
      for (int trial = 0; trial < numTrials; ++trial) {
        const Eigen::VectorXd counts = randomCounts(rng, size(rng), 1e-3, 1e5, 0.1);
        const EntropicEstimate estimate = entropicMap(counts, z);
        ASSERT_TRUE(estimate.probabilities.allFinite());
        EXPECT_NEAR(estimate.probabilities.sum(), 1.0, 1e-12);
        worstSumError = std::max(worstSumError, std::abs(estimate.probabilities.sum() - 1.0));
        for (Eigen::Index i = 0; i < counts.size(); ++i) {
          if (counts[i] == 0.0) {
            EXPECT_EQ(estimate.probabilities[i], 0.0);
          } else {
            EXPECT_GT(estimate.probabilities[i], 0.0);
          }
        }
        if (estimate.outcome == EntropicOutcome::kNoW1Solution) {
          ++fallbacks;
          continue;
        }
        ASSERT_EQ(estimate.outcome, EntropicOutcome::kStationary);
        ++solved;
        const double residual = stationarityResidual(estimate, counts, z);
        EXPECT_LT(residual, 1e-9) << "Z=" << z << " trial " << trial;
        worstResidual = std::max(worstResidual, residual);
      }
      std::cout << "Z=" << z << ": " << solved << " solved, " << fallbacks
                << " without a W-1 solution; worst stationarity residual " << worstResidual << ", worst |sum-1| "
                << worstSumError << '\n';
      if (z < 0.0) {
        EXPECT_EQ(fallbacks, 0);  // the W₀ branch always has a solution
      }
      if (z <= 10.0) {
        EXPECT_GT(solved, numTrials / 2);
      }
    }
  }
}

// The library's θ against θᵢ = −(ωᵢ/Z) / W(−(ωᵢ/Z)·e^(1+λ/Z)) with Boost.Math's W₋₁ (Z > 0) and W₀ (Z < 0), in a
// range where that direct formula is representable (moderate counts).
TEST(EntropicMap, AgreesWithBoostLambertWWhereTheDirectFormulaIsRepresentable) {
  std::mt19937_64 rng(3);
  for (double z : {0.5, 2.0, 20.0, -0.5, -2.0, -20.0}) {
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::VectorXd counts = randomCounts(rng, 2 + trial % 10, 0.5, 20.0);
      const EntropicEstimate estimate = entropicMap(counts, z);
      if (estimate.outcome == EntropicOutcome::kNoW1Solution) continue;
      ASSERT_EQ(estimate.outcome, EntropicOutcome::kStationary);
      const double lambda = estimate.lagrangeMultiplier.value();
      for (Eigen::Index i = 0; i < counts.size(); ++i) {
        const double argument = -(counts[i] / z) * std::exp(1.0 + lambda / z);
        double w;
        if (z > 0.0) {
          // Rounding can put the largest entry a hair past the branch point −1/e.
          w = boost::math::lambert_wm1(std::max(argument, -std::exp(-1.0)));
        } else {
          w = boost::math::lambert_w0(argument);
        }
        const double expected = -(counts[i] / z) / w;
        EXPECT_NEAR(estimate.probabilities[i], expected, 1e-7 * expected) << "Z=" << z << " i=" << i;
      }
    }
  }
}

// F(θ*) ≥ F at 10 000 Dirichlet points of the face spanned by the observed entries (flat, sparse and
// concentrated around θ*), and at θ* ± t(eᵢ − eⱼ) for every pair.
TEST(EntropicMap, ScoresHigherThanRandomAndNearbyPointsOfTheSimplex) {
  std::mt19937_64 rng(4);
  int numCompared = 0;
  for (double z : {0.1, 1.0, 10.0, 1000.0, -1.0, -10.0}) {
    for (int trial = 0; trial < 8; ++trial) {
      const int size = 2 + 3 * trial;
      const Eigen::VectorXd counts = randomCounts(rng, size, 1e-3, 1e5);
      const EntropicEstimate estimate = entropicMap(counts, z);
      if (estimate.outcome == EntropicOutcome::kNoW1Solution) continue;
      const Eigen::VectorXd& best = estimate.probabilities;
      const double bestScore = objective(best, counts, z);
      EXPECT_NEAR(estimate.objective, bestScore, 1e-12 * std::abs(bestScore));
      const double tolerance = 1e-12 * std::abs(bestScore);
      for (int sample = 0; sample < 10000; ++sample) {
        Eigen::VectorXd alpha;
        switch (sample % 3) {
          case 0:
            alpha = Eigen::VectorXd::Ones(size);
            break;
          case 1:
            alpha = Eigen::VectorXd::Constant(size, 0.2);
            break;
          default:
            alpha = 1000.0 * best.array() + 1e-3;
            break;
        }
        const Eigen::VectorXd theta = dirichletSample(rng, alpha);
        if ((theta.array() <= 0.0).any()) continue;  // a gamma draw underflowed: F = −∞ there anyway
        ASSERT_LE(objective(theta, counts, z), bestScore + tolerance) << "Z=" << z << " trial " << trial;
        ++numCompared;
      }
      for (int i = 0; i < size; ++i) {
        for (int j = 0; j < size; ++j) {
          if (i == j) continue;
          Eigen::VectorXd theta = best;
          const double step = 1e-3 * std::min(best[i], best[j]);
          theta[i] += step;
          theta[j] -= step;
          EXPECT_LE(objective(theta, counts, z), bestScore + tolerance) << "Z=" << z << " i=" << i << " j=" << j;
        }
      }
    }
  }
  EXPECT_GT(numCompared, 300000);
}

// Two and three entries: a fine grid over the whole simplex finds nothing better, and its best point is next to θ*.
TEST(EntropicMap, BeatsAFineGridOnSmallRows) {
  struct Case {
    std::vector<double> counts;
    double z;
  };
  const std::vector<Case> cases = {{{10.0, 10.0}, 15.0},   {{30.0, 1.0}, 20.0}, {{3.0, 7.0}, 1.0},
                                   {{3.0, 7.0}, -5.0},     {{500.0, 2.0}, 1.0}, {{5.0, 2.0, 1.0}, 3.0},
                                   {{5.0, 2.0, 1.0}, -3.0}};
  for (const Case& c : cases) {
    const Eigen::VectorXd counts = Eigen::Map<const Eigen::VectorXd>(c.counts.data(), Eigen::Index(c.counts.size()));
    const EntropicEstimate estimate = entropicMap(counts, c.z);
    ASSERT_EQ(estimate.outcome, EntropicOutcome::kStationary);
    const double bestScore = objective(estimate.probabilities, counts, c.z);
    const int steps = counts.size() == 2 ? 200000 : 2000;
    double gridBest = -std::numeric_limits<double>::infinity();
    Eigen::VectorXd gridArgmax = Eigen::VectorXd::Zero(counts.size());
    Eigen::VectorXd theta = Eigen::VectorXd::Zero(counts.size());
    for (int a = 1; a < steps; ++a) {
      for (int b = counts.size() == 2 ? steps - a : 1; b <= steps - a; ++b) {
        theta[0] = a / double(steps);
        theta[1] = b / double(steps);
        if (counts.size() == 3) {
          if (a + b >= steps) continue;
          theta[2] = (steps - a - b) / double(steps);
        }
        const double score = objective(theta, counts, c.z);
        if (score > gridBest) {
          gridBest = score;
          gridArgmax = theta;
        }
      }
    }
    EXPECT_GE(bestScore, gridBest) << "Z=" << c.z;
    EXPECT_LT((gridArgmax - estimate.probabilities).cwiseAbs().maxCoeff(), 1.0 / steps) << "Z=" << c.z;
  }
}

// If θ* is the maximum, F(θ*) ≥ F(θ_ML) and L(θ_ML) ≥ L(θ*) give Z·H(θ*) ≤ Z·H(θ_ML): lower entropy for Z > 0,
// higher for Z < 0.
TEST(EntropicMap, EntropyFallsForPositiveAndRisesForNegativePriorWeight) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> size(2, 50);
  for (double z : {0.1, 1.0, 10.0, 1000.0, -0.1, -1.0, -10.0, -1000.0}) {
    int strictlyMoved = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::VectorXd counts = randomCounts(rng, size(rng), 1e-3, 1e5, 0.1);
      const EntropicEstimate estimate = entropicMap(counts, z);
      if (estimate.outcome != EntropicOutcome::kStationary) continue;
      const double mapEntropy = entropy(estimate.probabilities);
      const double mlEntropy = entropy(counts / counts.sum());
      if (z > 0.0) {
        EXPECT_LE(mapEntropy, mlEntropy + 1e-12) << "Z=" << z;
      } else {
        EXPECT_GE(mapEntropy, mlEntropy - 1e-12) << "Z=" << z;
      }
      if (std::abs(mapEntropy - mlEntropy) > 1e-9) ++strictlyMoved;
    }
    EXPECT_GT(strictlyMoved, 50) << "Z=" << z;
  }
}

// Counts in the thousands with Z = 1: λ ≈ −Σω, e^(1+λ/Z) underflows to 0 and the direct formula has nothing left
// to work with. The log-space solve stays finite and stationary, close to (but not at) maximum likelihood.
TEST(EntropicMap, LargeCountsWhereTheDirectFormulaUnderflows) {
  std::mt19937_64 rng(6);
  for (double z : {1.0, 0.1, -1.0}) {
    for (int trial = 0; trial < 50; ++trial) {
      const int size = 2 + trial;
      const Eigen::VectorXd counts =
          trial % 2 == 0 ? randomCounts(rng, size, 1000.0, 9000.0) : randomCounts(rng, size, 1e5, 1e7);
      const EntropicEstimate estimate = entropicMap(counts, z);
      ASSERT_EQ(estimate.outcome, EntropicOutcome::kStationary);
      ASSERT_TRUE(estimate.probabilities.allFinite());
      const double lambda = estimate.lagrangeMultiplier.value();
      if (z > 0.0) {
        EXPECT_EQ(std::exp(1.0 + lambda / z), 0.0);  // the regime is real
      }
      EXPECT_LT(stationarityResidual(estimate, counts, z), 1e-9);
      EXPECT_NEAR(estimate.probabilities.sum(), 1.0, 1e-12);
      const Eigen::VectorXd ml = counts / counts.sum();
      EXPECT_LT((estimate.probabilities - ml).cwiseAbs().maxCoeff(), 1e-2);
      if (z > 0.0) {
        EXPECT_LT(entropy(estimate.probabilities), entropy(ml));
      } else {
        EXPECT_GT(entropy(estimate.probabilities), entropy(ml));
      }
    }
  }
}

// Tiny counts against a huge Z: Σθ(λ_max) < 1, checked independently with Boost's W₋₁ at λ_max, so there is no
// W₋₁ solution; the result is the ML row and says so. Scaling the counts up gives the prior something to act on.
TEST(EntropicMap, NoW1SolutionFallsBackToMaximumLikelihood) {
  const Eigen::VectorXd counts = (Eigen::VectorXd(4) << 0.01, 0.02, 0.005, 0.0).finished();
  const double z = 1000.0;
  // λ_max = minᵢ −Z(2 + log(ωᵢ/Z)) puts the largest count at the branch point, where θ is largest.
  double lambdaMax = std::numeric_limits<double>::infinity();
  for (double count : counts) {
    if (count > 0.0) lambdaMax = std::min(lambdaMax, -z * (2.0 + std::log(count / z)));
  }
  double sumAtLambdaMax = 0.0;
  for (double count : counts) {
    if (count == 0.0) continue;
    const double argument = std::max(-(count / z) * std::exp(1.0 + lambdaMax / z), -std::exp(-1.0));
    sumAtLambdaMax += -(count / z) / boost::math::lambert_wm1(argument);
  }
  ASSERT_LT(sumAtLambdaMax, 1.0);

  const EntropicEstimate estimate = entropicMap(counts, z);
  EXPECT_EQ(estimate.outcome, EntropicOutcome::kNoW1Solution);
  EXPECT_FALSE(estimate.lagrangeMultiplier.has_value());
  for (Eigen::Index i = 0; i < counts.size(); ++i) EXPECT_EQ(estimate.probabilities[i], counts[i] / counts.sum());
  EXPECT_EQ(estimate.objective, entropicObjective(estimate.probabilities, counts, z));

  const Eigen::VectorXd moreCounts = 1e5 * counts;
  EXPECT_EQ(entropicMap(moreCounts, z).outcome, EntropicOutcome::kStationary);
}

TEST(EntropicMap, AllZeroCountsGiveUniform) {
  for (int size : {1, 2, 7, 100}) {
    for (double z : {0.0, 1.0, -1.0, 1000.0}) {
      const EntropicEstimate estimate = entropicMap(Eigen::VectorXd::Zero(size), z);
      EXPECT_EQ(estimate.outcome, EntropicOutcome::kNoCounts);
      EXPECT_FALSE(estimate.lagrangeMultiplier.has_value());
      for (double theta : estimate.probabilities) EXPECT_EQ(theta, 1.0 / size);
    }
  }
}

TEST(EntropicMap, OneObservedEntryIsAVertex) {
  for (double z : {1e-3, 1.0, 1000.0, -1.0, -1000.0}) {
    const Eigen::VectorXd counts = (Eigen::VectorXd(5) << 0.0, 0.0, 3.5, 0.0, 0.0).finished();
    const EntropicEstimate estimate = entropicMap(counts, z);
    EXPECT_EQ(estimate.outcome, EntropicOutcome::kStationary);
    EXPECT_EQ(estimate.probabilities, (Eigen::VectorXd(5) << 0.0, 0.0, 1.0, 0.0, 0.0).finished());
    EXPECT_LT(stationarityResidual(estimate, counts, z), 1e-15);
    const EntropicEstimate single = entropicMap(Eigen::VectorXd::Constant(1, 1e-8), z);
    EXPECT_EQ(single.probabilities[0], 1.0);
  }
}

// Lengths 1..100, counts 1e-8..1e7 together, Z from negligible to enormous and of both signs: always a finite
// point of the simplex.
TEST(EntropicMap, ExtremeInputsStayFinite) {
  std::mt19937_64 rng(7);
  for (double z : {1e-30, 1e-6, 0.01, 1.0, 1e3, 1e6, 1e30, -1e-30, -0.01, -1.0, -1e3, -1e6, -1e30}) {
    for (int size = 1; size <= 100; size += 3) {
      const Eigen::VectorXd counts = randomCounts(rng, size, 1e-8, 1e7, 0.1);
      const EntropicEstimate estimate = entropicMap(counts, z);
      ASSERT_TRUE(estimate.probabilities.allFinite()) << "Z=" << z << " size " << size;
      ASSERT_TRUE((estimate.probabilities.array() >= 0.0).all());
      EXPECT_NEAR(estimate.probabilities.sum(), 1.0, 1e-12);
      EXPECT_FALSE(std::isnan(estimate.objective));
      if (estimate.outcome == EntropicOutcome::kStationary) {
        EXPECT_LT(stationarityResidual(estimate, counts, z), 1e-9) << "Z=" << z << " size " << size;
      }
    }
  }
}

TEST(EntropicMap, RejectsBadInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(entropicMap(Eigen::VectorXd(0), 1.0), std::invalid_argument);
  EXPECT_THROW(entropicMap((Eigen::VectorXd(2) << 1.0, -1.0).finished(), 1.0), std::invalid_argument);
  EXPECT_THROW(entropicMap((Eigen::VectorXd(2) << 1.0, nan).finished(), 1.0), std::invalid_argument);
  EXPECT_THROW(entropicMap((Eigen::VectorXd(2) << 1.0, inf).finished(), 1.0), std::invalid_argument);
  EXPECT_THROW(entropicMap((Eigen::VectorXd(2) << 1e308, 1e308).finished(), 1.0), std::invalid_argument);
  EXPECT_THROW(entropicMap((Eigen::VectorXd(2) << 1.0, 2.0).finished(), nan), std::invalid_argument);
  EXPECT_THROW(entropicMap((Eigen::VectorXd(2) << 1.0, 2.0).finished(), inf), std::invalid_argument);
}

TEST(EntropicLogPrior, IsZTimesNegativeEntropy) {
  const Eigen::VectorXd theta = (Eigen::VectorXd(4) << 0.5, 0.25, 0.25, 0.0).finished();
  EXPECT_DOUBLE_EQ(entropicLogPrior(theta, 2.0), -2.0 * 1.5 * std::log(2.0));
  EXPECT_EQ(entropicLogPrior(theta, 0.0), 0.0);
}

// The criterion written out independently: −Z(log θᵢ + 1) > ωᵢ/θᵢ.
bool meetsCriterion(double theta, double count, double z) {
  return theta > 0.0 && -z * (std::log(theta) + 1.0) > count / theta;
}

TEST(EntropicTrimming, RemovesExactlyTheEntriesThatMeetTheCriterion) {
  std::mt19937_64 rng(8);
  int numTrimmed = 0;
  int numKept = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int size = 2 + trial % 40;
    const double z = std::vector<double>{0.1, 1.0, 10.0, 100.0}[trial % 4];
    Eigen::VectorXd theta = dirichletSample(rng, Eigen::VectorXd::Constant(size, 0.3));
    const Eigen::VectorXd counts = randomCounts(rng, size, 1e-6, 10.0, 0.2);
    const Eigen::VectorXd before = theta;
    std::vector<bool> expected(size);
    int numExpected = 0;
    int numPositive = 0;
    for (int i = 0; i < size; ++i) {
      expected[i] = meetsCriterion(before[i], counts[i], z);
      numExpected += expected[i];
      numPositive += before[i] > 0.0;
    }
    if (numExpected == numPositive) {
      Eigen::Index largest;
      before.maxCoeff(&largest);
      expected[largest] = false;
      --numExpected;
    }
    const int reported = trimWeakParameters(theta, counts, z);
    EXPECT_EQ(reported, numExpected);
    if (numExpected == 0) {
      EXPECT_EQ(theta, before);  // untouched, bit for bit
      continue;
    }
    const double keptMass = (before.array() * (1.0 - Eigen::ArrayXd::NullaryExpr(
                                                         size, [&](Eigen::Index i) { return double(expected[i]); })))
                                .sum();
    for (int i = 0; i < size; ++i) {
      if (expected[i]) {
        EXPECT_EQ(theta[i], 0.0);
        ++numTrimmed;
      } else {
        EXPECT_NEAR(theta[i], before[i] / keptMass, 1e-15);
        numKept += before[i] > 0.0;
      }
    }
    EXPECT_NEAR(theta.sum(), 1.0, 1e-14);
    EXPECT_GT((theta.array() > 0.0).count(), 0);
  }
  EXPECT_GT(numTrimmed, 1000);  // the test exercised both sides
  EXPECT_GT(numKept, 1000);
}

TEST(EntropicTrimming, NeverEmptiesARow) {
  // Ten entries of 0.1 (< 1/e) and no counts: each one meets the criterion; the first of the equal largest stays.
  Eigen::VectorXd theta = Eigen::VectorXd::Constant(10, 0.1);
  EXPECT_EQ(trimWeakParameters(theta, Eigen::VectorXd::Zero(10), 1.0), 9);
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(10);
  expected[0] = 1.0;
  EXPECT_EQ(theta, expected);
  // A single surviving entry is never trimmed, whatever Z.
  EXPECT_EQ(trimWeakParameters(theta, Eigen::VectorXd::Zero(10), 1e9), 0);
  EXPECT_EQ(theta, expected);
  // The largest is kept even when it is not first.
  Eigen::VectorXd uneven = (Eigen::VectorXd(3) << 0.1, 0.3, 0.2).finished();
  EXPECT_EQ(trimWeakParameters(uneven, Eigen::VectorXd::Zero(3), 5.0), 2);
  EXPECT_EQ(uneven, (Eigen::VectorXd(3) << 0.0, 1.0, 0.0).finished());
}

TEST(EntropicTrimming, NonPositivePriorWeightTrimsNothing) {
  const Eigen::VectorXd before = (Eigen::VectorXd(4) << 0.7, 0.2, 0.0999, 0.0001).finished();
  for (double z : {0.0, -1.0, -1e6}) {
    Eigen::VectorXd theta = before;
    EXPECT_EQ(trimWeakParameters(theta, Eigen::VectorXd::Zero(4), z), 0);
    EXPECT_EQ(theta, before);
  }
}

TEST(EntropicTrimming, WorksOnAMatrixRow) {
  Eigen::MatrixXd transitions(2, 3);
  transitions << 0.5, 0.3, 0.2,  //
      0.9, 0.09, 0.01;
  const Eigen::VectorXd counts = (Eigen::VectorXd(3) << 90.0, 9.0, 1e-3).finished();
  // Entry (1, 2): −Z(log 0.01 + 1) = 3.6 Z against ω/θ = 0.1, so Z = 1 trims it; the others have ω/θ = 100.
  EXPECT_EQ(trimWeakParameters(transitions.row(1), counts, 1.0), 1);
  EXPECT_EQ(transitions(1, 2), 0.0);
  EXPECT_NEAR(transitions(1, 0), 0.9 / 0.99, 1e-15);
  EXPECT_NEAR(transitions.row(1).sum(), 1.0, 1e-15);
  EXPECT_EQ(transitions(0, 2), 0.2);
}

// At an exact stationary point of the same counts the criterion is λ > 0 for every entry alike: all-or-nothing.
// Twenty equal counts of 0.06·Z: the stationary point is uniform with λ > 0, and trimming leaves one entry.
TEST(EntropicTrimming, AtAStationaryPointOfTheSameCountsItIsAllOrNothing) {
  const double z = 100.0;
  const Eigen::VectorXd counts = Eigen::VectorXd::Constant(20, 0.06 * z);
  EntropicEstimate estimate = entropicMap(counts, z);
  ASSERT_EQ(estimate.outcome, EntropicOutcome::kStationary);
  EXPECT_GT(estimate.lagrangeMultiplier.value(), 0.0);
  EXPECT_EQ(trimWeakParameters(estimate.probabilities, counts, z), 19);

  const Eigen::VectorXd strongCounts = Eigen::VectorXd::Constant(20, 10.0 * z);
  estimate = entropicMap(strongCounts, z);
  EXPECT_LT(estimate.lagrangeMultiplier.value(), 0.0);
  EXPECT_EQ(trimWeakParameters(estimate.probabilities, strongCounts, z), 0);
}

TEST(EntropicTrimming, RejectsBadInput) {
  Eigen::VectorXd theta = (Eigen::VectorXd(2) << 0.5, 0.5).finished();
  EXPECT_THROW(trimWeakParameters(theta, Eigen::VectorXd::Zero(3), 1.0), std::invalid_argument);
  Eigen::VectorXd empty = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(trimWeakParameters(empty, Eigen::VectorXd::Zero(2), 1.0), std::invalid_argument);
  Eigen::VectorXd negative = (Eigen::VectorXd(2) << 1.5, -0.5).finished();
  EXPECT_THROW(trimWeakParameters(negative, Eigen::VectorXd::Zero(2), 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace th::hmm
