// Known answers for the HMM core: densities in closed form, forward-backward and Viterbi against brute-force
// enumeration of every path, online Viterbi against batch, and Baum-Welch's monotone likelihood.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include "core/error.h"
#include "hmm/forward_backward.h"
#include "hmm/sampling.h"
#include "hmm/training.h"
#include "hmm/viterbi.h"
#include "hmm_test_models.h"

namespace th::hmm {
namespace {

TEST(Gaussian, LogDensityMatchesTheClosedForm) {
  Eigen::Vector2d mean(1.0, -2.0);
  Eigen::Matrix2d covariance;
  covariance << 2.0, 0.6, 0.6, 1.0;
  const Gaussian full(mean, covariance, CovarianceType::kFull);
  const Eigen::Vector2d x(0.3, -1.1);
  const Eigen::Vector2d centred = x - mean;
  const double expected = -0.5 * (2.0 * std::log(2.0 * std::numbers::pi) + std::log(covariance.determinant()) +
                                  centred.dot(covariance.inverse() * centred));
  EXPECT_NEAR(full.logDensity(x), expected, 1e-12);

  const Gaussian diagonal(mean, covariance, CovarianceType::kDiagonal);  // uses only the variances
  const double expectedDiagonal = -0.5 * (2.0 * std::log(2.0 * std::numbers::pi) + std::log(2.0) +
                                          centred[0] * centred[0] / 2.0 + centred[1] * centred[1] / 1.0);
  EXPECT_NEAR(diagonal.logDensity(x), expectedDiagonal, 1e-12);

  Eigen::MatrixXd frames(2, 3);
  frames << 0.3, 1.0, 5.0, -1.1, -2.0, 0.0;
  Eigen::VectorXd batch(3);
  full.logDensities(frames, batch);
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(batch[t], full.logDensity(frames.col(t)), 1e-12);
}

TEST(Gaussian, RejectsCovariancesThatAreNotPositiveDefinite) {
  Eigen::Matrix2d singular;
  singular << 1.0, 1.0, 1.0, 1.0;
  EXPECT_THROW(Gaussian(Eigen::Vector2d::Zero(), singular, CovarianceType::kFull), Error);
  EXPECT_THROW(Gaussian(Eigen::Vector2d::Zero(), -Eigen::Matrix2d::Identity(), CovarianceType::kDiagonal), Error);
  // The floor repairs a singular covariance.
  const Eigen::MatrixXd repaired =
      applyCovarianceFloor(singular, Eigen::Vector2d::Constant(1e-3), CovarianceType::kFull);
  EXPECT_NO_THROW(Gaussian(Eigen::Vector2d::Zero(), repaired, CovarianceType::kFull));
}

// The floor is the constrained maximum of a Gaussian's expected log-likelihood −½[Γ log|Σ| + tr(Σ⁻¹S)] over
// {Σ ⪰ D}: feasible, and no other feasible covariance scores higher. (Raising only the diagonal of collinear data
// would not be feasible: the data's null direction would stay near-singular.)
TEST(Gaussian, CovarianceFloorIsTheConstrainedMaximumLikelihoodEstimate) {
  std::mt19937 random(4);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int d = 4;
  const Eigen::VectorXd floor = Eigen::Vector4d(0.5, 0.2, 1.0, 0.3);
  auto objective = [](const Eigen::MatrixXd& sigma, const Eigen::MatrixXd& scatter) {
    const Eigen::LLT<Eigen::MatrixXd> llt(sigma);
    const double logDet = 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
    return -0.5 * (logDet + (llt.solve(scatter)).trace());
  };
  for (int trial = 0; trial < 20; ++trial) {
    // A scatter of rank 2 in 4-D: collinear data.
    const Eigen::MatrixXd a = Eigen::MatrixXd::NullaryExpr(d, 2, [&] { return normal(random); });
    const Eigen::MatrixXd scatter = a * a.transpose();
    const Eigen::MatrixXd floored = applyCovarianceFloor(scatter, floor, CovarianceType::kFull);
    const Eigen::VectorXd margin =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(floored - Eigen::MatrixXd(floor.asDiagonal())).eigenvalues();
    EXPECT_GT(margin.minCoeff(), -1e-12) << "Σ − D must be positive semi-definite";
    const double best = objective(floored, scatter);
    for (int other = 0; other < 50; ++other) {
      const Eigen::MatrixXd b = Eigen::MatrixXd::NullaryExpr(d, d, [&] { return 0.3 * normal(random); });
      const Eigen::MatrixXd feasible = floored + b * b.transpose();  // Σ + PSD stays ⪰ D
      EXPECT_LE(objective(feasible, scatter), best + 1e-12);
    }
    for (double c : {0.0, 0.5, 0.9, 1.1, 2.0}) {  // towards and away from the bound: D + c(Σ − D)
      const Eigen::MatrixXd feasible =
          Eigen::MatrixXd(floor.asDiagonal()) + c * (floored - Eigen::MatrixXd(floor.asDiagonal()));
      EXPECT_LE(objective(feasible, scatter), best + 1e-12) << c;
    }
  }
  // Already above the floor: unchanged.
  const Eigen::Matrix2d wide = (Eigen::Matrix2d() << 2.0, 0.5, 0.5, 1.0).finished();
  EXPECT_EQ(applyCovarianceFloor(wide, Eigen::Vector2d(0.1, 0.1), CovarianceType::kFull), Eigen::MatrixXd(wide));
}

// Every path of a short sequence, enumerated: the definition of the likelihood, the posteriors and the best path.
struct BruteForce {
  double logLikelihood;
  Eigen::MatrixXd gamma;
  std::vector<int> bestPath;
};

BruteForce enumerate(const HmmModel& model, const Eigen::MatrixXd& logB) {
  const int n = model.numStates();
  const int numFrames = static_cast<int>(logB.cols());
  BruteForce result{0.0, Eigen::MatrixXd::Zero(n, numFrames), {}};
  std::vector<int> path(static_cast<size_t>(numFrames), 0);
  double total = 0.0;
  double best = -1.0;
  for (;;) {
    double p = model.initial[path[0]] * std::exp(logB(path[0], 0));
    for (int t = 1; t < numFrames; ++t) {
      p *= model.transition(path[static_cast<size_t>(t - 1)], path[static_cast<size_t>(t)]) *
           std::exp(logB(path[static_cast<size_t>(t)], t));
    }
    total += p;
    for (int t = 0; t < numFrames; ++t) result.gamma(path[static_cast<size_t>(t)], t) += p;
    if (p > best) {
      best = p;
      result.bestPath = path;
    }
    int position = numFrames - 1;
    while (position >= 0 && ++path[static_cast<size_t>(position)] == n) path[static_cast<size_t>(position--)] = 0;
    if (position < 0) break;
  }
  result.logLikelihood = std::log(total);
  result.gamma /= total;
  return result;
}

TEST(ForwardBackward, EqualsEnumerationOfEveryPath) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const HmmModel model = test::randomModel(3, 2, 2, CovarianceType::kFull, seed);
    std::mt19937 random(seed);
    const Sample sample = sampleHmm(model, 7, random);
    const Eigen::MatrixXd logB = model.emissionLogLikelihoods(sample.frames);
    const BruteForce truth = enumerate(model, logB);
    const Posteriors posteriors = forwardBackward(model, logB);
    EXPECT_NEAR(posteriors.logLikelihood, truth.logLikelihood, 1e-10 * std::abs(truth.logLikelihood));
    EXPECT_NEAR(logLikelihood(model, logB), truth.logLikelihood, 1e-10 * std::abs(truth.logLikelihood));
    EXPECT_LT((posteriors.stateGivenAll - truth.gamma).cwiseAbs().maxCoeff(), 1e-10);
    // Expected transitions: T - 1 of them in all, and γ's marginals agree with ξ's.
    EXPECT_NEAR(posteriors.transitionCounts.sum(), 6.0, 1e-10);
    EXPECT_LT((posteriors.transitionCounts.rowwise().sum() - posteriors.stateGivenAll.leftCols(6).rowwise().sum())
                  .cwiseAbs()
                  .maxCoeff(),
              1e-10);
    EXPECT_EQ(viterbi(model, logB).states, truth.bestPath);
  }
}

TEST(ForwardBackward, LongSequencesStayInRange) {
  const HmmModel model = test::stickyModel1d(4, 0.95);
  std::mt19937 random(5);
  const Sample sample = sampleHmm(model, 200000, random);
  const Posteriors posteriors = forwardBackward(model, model.emissionLogLikelihoods(sample.frames));
  EXPECT_TRUE(std::isfinite(posteriors.logLikelihood));
  EXPECT_LT((posteriors.stateGivenAll.colwise().sum().array() - 1.0).abs().maxCoeff(), 1e-9);
}

// Sharp densities on unseen data: the only reachable state explains a frame 1000 nats worse than a state that
// cannot be reached. Scaled relative to the best state overall, that frame would underflow to "impossible".
TEST(ForwardBackward, AFrameExplainedOnlyByAFarWorseReachableStateIsStillPossible) {
  HmmModel model = test::stickyModel1d(2, 0.5);
  model.initial << 1.0, 0.0;
  model.transition << 1.0, 0.0, 0.0, 1.0;  // state 1 can never be reached
  Eigen::MatrixXd logB(2, 3);
  logB << -1.0, -1000.0, -2.0,  //
      0.0, 0.0, 0.0;
  EXPECT_NEAR(logLikelihood(model, logB), -1003.0, 1e-9);
  const Posteriors posteriors = forwardBackward(model, logB);
  EXPECT_NEAR(posteriors.logLikelihood, -1003.0, 1e-9);
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(posteriors.stateGivenAll(0, t), 1.0, 1e-12);
  FixedLagSmoother smoother(model, 1);
  for (int t = 0; t < 3; ++t) smoother.acceptFrame(logB.col(t));
  smoother.finish();
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(smoother.posterior(t)[0], 1.0, 1e-12);
  // A frame that truly no reachable state can explain is still refused, in one line.
  logB(0, 1) = -std::numeric_limits<double>::infinity();
  EXPECT_THROW(logLikelihood(model, logB), Error);
}

// A sequence that no frame of some state touches (responsibilities exactly 0 for the whole sequence) must add
// nothing to that state's statistics; an empty rank update once raised SIGFPE inside Eigen.
TEST(BaumWelch, ASequenceThatNeverVisitsAStateAddsNothingToIt) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::MatrixXd near = Eigen::MatrixXd::NullaryExpr(80, 400, [&] { return normal(random); });
  const Eigen::MatrixXd far = Eigen::MatrixXd::NullaryExpr(80, 400, [&] { return 1000.0 + normal(random); });
  TrainingOptions options;
  options.numStates = 2;
  options.maxIterations = 5;
  const TrainingResult result = trainHmm({near, far}, options);
  ASSERT_EQ(result.model.numStates(), 2);
  const double a = result.model.states[0].components()[0].mean()[0];
  const double b = result.model.states[1].components()[0].mean()[0];
  EXPECT_NEAR(std::min(a, b), 0.0, 0.3);
  EXPECT_NEAR(std::max(a, b), 1000.0, 0.3);
}

TEST(OnlineViterbi, UnboundedLagEqualsBatch) {
  for (unsigned seed : {11u, 12u}) {
    const HmmModel model = test::randomModel(6, 1, 2, CovarianceType::kFull, seed);
    std::mt19937 random(seed);
    const Sample sample = sampleHmm(model, 20000, random);
    const Eigen::MatrixXd logB = model.emissionLogLikelihoods(sample.frames);
    const ViterbiPath batch = viterbi(model, logB);
    OnlineViterbi online(model, {});
    int decidedWhileStreaming = 0;
    for (Eigen::Index t = 0; t < logB.cols(); ++t) {
      online.acceptFrame(logB.col(t));
      decidedWhileStreaming = online.numDecided();
    }
    EXPECT_GT(decidedWhileStreaming, 19000) << "convergence points come long before the end";
    online.finish();
    ASSERT_EQ(online.numDecided(), 20000);
    std::vector<int> path(20000);
    for (int t = 0; t < 20000; ++t) path[static_cast<size_t>(t)] = online.state(t);
    EXPECT_EQ(path, batch.states);
  }
}

TEST(OnlineViterbi, MaximumLagIsNeverExceededAndAgreementGrowsWithIt) {
  const HmmModel model = test::randomModel(6, 1, 2, CovarianceType::kFull, 21);
  std::mt19937 random(21);
  const Sample sample = sampleHmm(model, 5000, random);
  const Eigen::MatrixXd logB = model.emissionLogLikelihoods(sample.frames);
  const ViterbiPath batch = viterbi(model, logB);
  double previousAgreement = 0.0;
  for (int maxLag : {0, 1, 2, 3, 5, 10, 20, 30, -1}) {
    OnlineViterbi online(model, {.maxLagFrames = maxLag});
    for (Eigen::Index t = 0; t < logB.cols(); ++t) {
      online.acceptFrame(logB.col(t));
      if (maxLag >= 0) {
        ASSERT_GE(online.numDecided(), static_cast<int>(t) + 1 - maxLag) << "lag " << maxLag << " at frame " << t;
      }
    }
    online.finish();
    int agree = 0;
    double lagSum = 0.0;
    for (int t = 0; t < 5000; ++t) {
      agree += online.state(t) == batch.states[static_cast<size_t>(t)];
      lagSum += online.decisionLag(t);
    }
    const double agreement = agree / 5000.0;
    std::printf("[ INFO     ] max lag %3d: agreement with batch %.4f, mean actual lag %.2f frames\n", maxLag, agreement,
                lagSum / 5000.0);
    EXPECT_GE(agreement, previousAgreement - 0.01) << "lag " << maxLag;
    previousAgreement = agreement;
  }
  EXPECT_EQ(previousAgreement, 1.0) << "an unbounded lag equals batch";
}

TEST(BaumWelch, LikelihoodNeverDecreasesAndRecoversTheMeans) {
  const HmmModel truth = test::stickyModel1d(3, 0.9);
  std::mt19937 random(3);
  std::vector<Eigen::MatrixXd> sequences;
  for (int s = 0; s < 4; ++s) sequences.push_back(sampleHmm(truth, 1500, random).frames);
  for (CovarianceType type : {CovarianceType::kFull, CovarianceType::kDiagonal}) {
    TrainingOptions options;
    options.numStates = 3;
    options.numMixtures = 2;
    options.covariance = type;
    options.maxIterations = 60;
    const TrainingResult result = trainHmm(sequences, options);
    for (size_t i = 1; i < result.history.size(); ++i) {
      EXPECT_GE(result.history[i].logLikelihood, result.history[i - 1].logLikelihood - 1e-6) << "iteration " << i;
    }
    // The three states sit near 0, 3 and 6 (in some order), and stay sticky.
    std::vector<double> means;
    for (const auto& state : result.model.states) {
      double mean = 0.0;
      for (int m = 0; m < state.numComponents(); ++m)
        mean += state.weights()[m] * state.components()[static_cast<size_t>(m)].mean()[0];
      means.push_back(mean);
    }
    std::sort(means.begin(), means.end());
    EXPECT_NEAR(means[0], 0.0, 0.15);
    EXPECT_NEAR(means[1], 3.0, 0.15);
    EXPECT_NEAR(means[2], 6.0, 0.15);
    EXPECT_GT(result.model.transition.diagonal().minCoeff(), 0.85);
  }
}

}  // namespace
}  // namespace th::hmm

namespace th::hmm {
namespace {

TEST(FixedLagSmoother, EqualsForwardBackwardWithALongLagAndImprovesWithTheLag) {
  const HmmModel model = test::randomModel(5, 2, 2, CovarianceType::kFull, 41);
  std::mt19937 random(41);
  const Sample sample = sampleHmm(model, 600, random);
  const Eigen::MatrixXd logB = model.emissionLogLikelihoods(sample.frames);
  const Posteriors batch = forwardBackward(model, logB);
  double previousError = 1e300;
  for (int lag : {0, 1, 3, 10, 600}) {
    FixedLagSmoother smoother(model, lag);
    for (Eigen::Index t = 0; t < logB.cols(); ++t) {
      smoother.acceptFrame(logB.col(t));
      ASSERT_EQ(smoother.numReady(), std::max(0, static_cast<int>(t) + 1 - lag));
    }
    smoother.finish();
    ASSERT_EQ(smoother.numReady(), 600);
    double error = 0.0;
    for (int t = 0; t < 600; ++t) error += (smoother.posterior(t) - batch.stateGivenAll.col(t)).cwiseAbs().sum();
    error /= 600.0;
    EXPECT_LE(error, previousError + 1e-12) << "lag " << lag;
    previousError = error;
    if (lag >= 600) {
      EXPECT_LT(error, 1e-10);
    }
  }
}

}  // namespace
}  // namespace th::hmm
