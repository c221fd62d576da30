// MLPG: deltas by hand, trajectories that must equal known curves, optimality of the objective (no random
// perturbation does better, zero gradient), smoothing of a step, agreement with a dense (Wᵀ U⁻¹ W) solve, and
// errors that name the bad frame.
#include "animation/mlpg.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstddef>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"

namespace th::animation {
namespace {

Eigen::MatrixXd randomNormal(std::mt19937& rng, Eigen::Index rows, Eigen::Index cols) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = normal(rng);
  }
  return m;
}

// A random symmetric positive-definite d x d matrix with eigenvalues ≥ 0.5.
Eigen::MatrixXd randomSpd(std::mt19937& rng, Eigen::Index d) {
  const Eigen::MatrixXd a = randomNormal(rng, d, d);
  return a * a.transpose() + 0.5 * Eigen::MatrixXd::Identity(d, d);
}

// Frames with random SPD precisions; means from the given d x T matrices.
std::vector<MlpgFrame> framesWithRandomPrecisions(std::mt19937& rng, const Eigen::MatrixXd& staticMeans,
                                                  const Eigen::MatrixXd& deltaMeans) {
  std::vector<MlpgFrame> frames;
  for (Eigen::Index t = 0; t < staticMeans.cols(); ++t) {
    frames.push_back({staticMeans.col(t),
                      randomSpd(rng, staticMeans.rows()),
                      deltaMeans.col(t),
                      randomSpd(rng, staticMeans.rows()),
                      {},
                      {}});
  }
  return frames;
}

// Σ_t −½ (x_t − μˢ_t)ᵀ Pˢ_t (x_t − μˢ_t) − ½ (Δx_t − μᵈ_t)ᵀ Pᵈ_t (Δx_t − μᵈ_t), straight from the definition.
double objective(const std::vector<MlpgFrame>& frames, const Eigen::MatrixXd& x) {
  const Eigen::MatrixXd dx = deltas(x);
  double sum = 0.0;
  for (Eigen::Index t = 0; t < x.cols(); ++t) {
    const MlpgFrame& frame = frames[static_cast<std::size_t>(t)];
    const Eigen::VectorXd staticResidual = x.col(t) - frame.staticMean;
    const Eigen::VectorXd deltaResidual = dx.col(t) - frame.deltaMean;
    sum -= 0.5 * staticResidual.dot(frame.staticPrecision * staticResidual);
    sum -= 0.5 * deltaResidual.dot(frame.deltaPrecision * deltaResidual);
  }
  return sum;
}

// The two parts of the objective's gradient (d x T each; the gradient is their sum). `deltas` is linear, so
// Δx_t = Σ_k C(t, k) x_k with C(t, k) the delta at t of a unit impulse at k; ∂/∂x_k of the delta term is
// −Σ_t C(t, k) Pᵈ_t (Δx_t − μᵈ_t).
struct GradientParts {
  Eigen::MatrixXd fromStatic;
  Eigen::MatrixXd fromDelta;
};

GradientParts gradientParts(const std::vector<MlpgFrame>& frames, const Eigen::MatrixXd& x) {
  const Eigen::Index numFrames = x.cols();
  Eigen::MatrixXd deltaOperator(numFrames, numFrames);
  for (Eigen::Index k = 0; k < numFrames; ++k) {
    const Eigen::MatrixXd impulse = Eigen::RowVectorXd::Unit(numFrames, k);  // 1 x T
    deltaOperator.col(k) = deltas(impulse).transpose();
  }
  const Eigen::MatrixXd dx = deltas(x);
  Eigen::MatrixXd weightedDeltaResidual(x.rows(), numFrames);
  GradientParts parts{Eigen::MatrixXd(x.rows(), numFrames), Eigen::MatrixXd(x.rows(), numFrames)};
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const MlpgFrame& frame = frames[static_cast<std::size_t>(t)];
    parts.fromStatic.col(t) = -frame.staticPrecision * (x.col(t) - frame.staticMean);
    weightedDeltaResidual.col(t) = frame.deltaPrecision * (dx.col(t) - frame.deltaMean);
  }
  parts.fromDelta = -weightedDeltaResidual * deltaOperator;
  return parts;
}

TEST(Mlpg, DeltasMatchHandComputedValues) {
  Eigen::MatrixXd x(2, 4);
  x << 1.0, 4.0, 9.0, 16.0,  //
      0.0, -1.0, 5.0, 2.0;
  Eigen::MatrixXd expected(2, 4);
  expected << 3.0, 4.0, 6.0, 7.0,  // 4−1, (9−1)/2, (16−4)/2, 16−9
      -1.0, 2.5, 1.5, -3.0;        // −1−0, (5−0)/2, (2+1)/2, 2−5
  EXPECT_TRUE(deltas(x).isApprox(expected, 1e-15)) << deltas(x);

  Eigen::MatrixXd two(1, 2);
  two << 2.0, 5.0;
  EXPECT_EQ(deltas(two), Eigen::MatrixXd::Constant(1, 2, 3.0));  // both edges are one-sided: x_1 − x_0

  const Eigen::MatrixXd one = Eigen::MatrixXd::Constant(3, 1, 7.0);
  EXPECT_EQ(deltas(one), Eigen::MatrixXd::Zero(3, 1));
}

TEST(Mlpg, ZeroDeltaPrecisionGivesTheStaticMeans) {
  std::mt19937 rng(1);
  const Eigen::Index d = 3;
  for (const Eigen::Index numFrames : {Eigen::Index{1}, Eigen::Index{2}, Eigen::Index{25}}) {
    const Eigen::MatrixXd staticMeans = randomNormal(rng, d, numFrames);
    std::vector<MlpgFrame> frames = framesWithRandomPrecisions(rng, staticMeans, randomNormal(rng, d, numFrames));
    for (MlpgFrame& frame : frames) frame.deltaPrecision.setZero();
    const Eigen::MatrixXd x = generateTrajectory(frames);
    ASSERT_EQ(x.rows(), d);
    ASSERT_EQ(x.cols(), numFrames);
    EXPECT_LT((x - staticMeans).cwiseAbs().maxCoeff(), 1e-9) << "T = " << numFrames;
  }
}

TEST(Mlpg, ReproducesACurveWhoseDeltasAreTheDeltaMeans) {
  // The curve zeroes both residuals, so it is the maximum whatever the precisions.
  std::mt19937 rng(2);
  for (const auto& [d, numFrames] : {std::pair<Eigen::Index, Eigen::Index>{1, 60}, {3, 2000}}) {
    Eigen::MatrixXd curve(d, numFrames);
    for (Eigen::Index i = 0; i < d; ++i) {
      for (Eigen::Index t = 0; t < numFrames; ++t) {
        curve(i, t) = std::sin(0.13 * static_cast<double>(t) + static_cast<double>(i)) + 0.2 * static_cast<double>(i);
      }
    }
    const std::vector<MlpgFrame> frames = framesWithRandomPrecisions(rng, curve, deltas(curve));
    const Eigen::MatrixXd x = generateTrajectory(frames);
    ASSERT_EQ(x.rows(), d);
    ASSERT_EQ(x.cols(), numFrames);
    EXPECT_LT((x - curve).cwiseAbs().maxCoeff(), 1e-9) << "d = " << d << ", T = " << numFrames;
  }
}

TEST(Mlpg, MaximisesTheObjective) {
  std::mt19937 rng(3);
  const Eigen::Index d = 2;
  const Eigen::Index numFrames = 30;
  const std::vector<MlpgFrame> frames =
      framesWithRandomPrecisions(rng, randomNormal(rng, d, numFrames), randomNormal(rng, d, numFrames));
  const Eigen::MatrixXd best = generateTrajectory(frames);
  const double bestObjective = objective(frames, best);

  // No perturbation, at scales from 1e-3 to 1, does better.
  std::uniform_real_distribution<double> logScale(-3.0, 0.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::MatrixXd perturbed = best + std::pow(10.0, logScale(rng)) * randomNormal(rng, d, numFrames);
    ASSERT_GE(bestObjective, objective(frames, perturbed)) << "trial " << trial;
  }

  // The test's own gradient agrees with central differences (exact for a quadratic up to rounding)...
  const Eigen::MatrixXd somewhere = randomNormal(rng, d, numFrames);
  const GradientParts atSomewhere = gradientParts(frames, somewhere);
  const Eigen::MatrixXd analytic = atSomewhere.fromStatic + atSomewhere.fromDelta;
  const double step = 1e-4;
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    for (Eigen::Index i = 0; i < d; ++i) {
      Eigen::MatrixXd plus = somewhere;
      Eigen::MatrixXd minus = somewhere;
      plus(i, t) += step;
      minus(i, t) -= step;
      const double numeric = (objective(frames, plus) - objective(frames, minus)) / (2.0 * step);
      ASSERT_NEAR(numeric, analytic(i, t), 1e-6 * (1.0 + std::abs(analytic(i, t)))) << "i = " << i << ", t = " << t;
    }
  }

  // ...and at the result the two parts cancel: the gradient is ~0 relative to their size.
  const GradientParts atBest = gradientParts(frames, best);
  const double scale = std::max(atBest.fromStatic.cwiseAbs().maxCoeff(), atBest.fromDelta.cwiseAbs().maxCoeff());
  EXPECT_GT(scale, 0.1);  // the static and delta models disagree, so this is a real trade-off
  EXPECT_LT((atBest.fromStatic + atBest.fromDelta).cwiseAbs().maxCoeff(), 1e-6 * scale);
}

TEST(Mlpg, SmoothsAStepIntoAMonotoneRamp) {
  // Static standard deviation 1, delta standard deviation ≈ 0.32. Central differences never see
  // x_{t+1} − x_t, only x_{t+1} − x_{t−1}, so the ramp climbs in two-frame plateaus and its largest single
  // step stays large unless deltas weigh more (measured: 0.71 with equal precisions, 0.30 here).
  const Eigen::Index numFrames = 100;
  std::vector<MlpgFrame> frames;
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const double level = t < 50 ? 0.0 : 1.0;
    frames.push_back({Eigen::VectorXd::Constant(1, level),
                      Eigen::MatrixXd::Identity(1, 1),
                      Eigen::VectorXd::Zero(1),
                      Eigen::MatrixXd::Constant(1, 1, 10.0),
                      {},
                      {}});
  }
  const Eigen::MatrixXd x = generateTrajectory(frames);
  ASSERT_EQ(x.cols(), numFrames);
  const Eigen::RowVectorXd steps = x.rightCols(numFrames - 1) - x.leftCols(numFrames - 1);
  EXPECT_LT(steps.maxCoeff(), 0.5) << x;
  EXPECT_GE(steps.minCoeff(), -1e-12) << x;
  EXPECT_NEAR(x(0, 0), 0.0, 1e-3);  // far from the step the means win
  EXPECT_NEAR(x(0, numFrames - 1), 1.0, 1e-3);
}

// An acceleration term ties neighbouring frames: the two-frame plateaus go, the largest step falls and the
// ramp's steps change smoothly.
TEST(Mlpg, AccelerationsRemoveThePlateaus) {
  const Eigen::Index numFrames = 100;
  std::vector<MlpgFrame> plain;
  std::vector<MlpgFrame> withAcceleration;
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const double level = t < 50 ? 0.0 : 1.0;
    plain.push_back({Eigen::VectorXd::Constant(1, level),
                     Eigen::MatrixXd::Identity(1, 1),
                     Eigen::VectorXd::Zero(1),
                     Eigen::MatrixXd::Constant(1, 1, 1.0),
                     {},
                     {}});
    withAcceleration.push_back(plain.back());
    withAcceleration.back().accelerationMean = Eigen::VectorXd::Zero(1);
    withAcceleration.back().accelerationPrecision = Eigen::MatrixXd::Constant(1, 1, 10.0);
  }
  const auto stepsOf = [&](const Eigen::MatrixXd& x) {
    return Eigen::RowVectorXd(x.rightCols(numFrames - 1) - x.leftCols(numFrames - 1));
  };
  const Eigen::RowVectorXd a = stepsOf(generateTrajectory(plain));
  const Eigen::RowVectorXd b = stepsOf(generateTrajectory(withAcceleration));
  EXPECT_LT(b.maxCoeff(), 0.6 * a.maxCoeff());
  // Plateaus: steps that alternate large and small. Their second difference is what the term penalises.
  const auto zigzag = [&](const Eigen::RowVectorXd& steps) {
    return (steps.tail(steps.size() - 1) - steps.head(steps.size() - 1)).cwiseAbs().maxCoeff();
  };
  EXPECT_LT(zigzag(b), 0.5 * zigzag(a));
  EXPECT_GE(b.minCoeff(), -0.01) << "at most a slight overshoot, as a penalty on acceleration gives";
  // accelerations() is what the generator inverts: a parabola's is constant, the edges take their neighbours'.
  Eigen::MatrixXd parabola(1, 6);
  parabola << 0, 1, 4, 9, 16, 25;
  EXPECT_EQ(accelerations(parabola), Eigen::MatrixXd::Constant(1, 6, 2.0));
  EXPECT_EQ(accelerations(Eigen::MatrixXd::Ones(2, 2)), Eigen::MatrixXd::Zero(2, 2));
}

TEST(Mlpg, AgreesWithADenseSolveOfTheNormalEquations) {
  std::mt19937 rng(4);
  const Eigen::Index d = 2;
  const Eigen::Index numFrames = 6;
  const std::vector<MlpgFrame> frames =
      framesWithRandomPrecisions(rng, randomNormal(rng, d, numFrames), randomNormal(rng, d, numFrames));

  // W maps x = [x_0; …; x_{T−1}] to [x_0; Δx_0; x_1; Δx_1; …], with the delta windows written out by hand.
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(d, d);
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(2 * d * numFrames, d * numFrames);
  Eigen::MatrixXd precision = Eigen::MatrixXd::Zero(2 * d * numFrames, 2 * d * numFrames);  // U⁻¹
  Eigen::VectorXd mean(2 * d * numFrames);
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const MlpgFrame& frame = frames[static_cast<std::size_t>(t)];
    const Eigen::Index staticRow = 2 * d * t;
    const Eigen::Index deltaRow = staticRow + d;
    w.block(staticRow, d * t, d, d) = identity;
    if (t == 0) {
      w.block(deltaRow, 0, d, d) = -identity;
      w.block(deltaRow, d, d, d) = identity;
    } else if (t == numFrames - 1) {
      w.block(deltaRow, d * (t - 1), d, d) = -identity;
      w.block(deltaRow, d * t, d, d) = identity;
    } else {
      w.block(deltaRow, d * (t - 1), d, d) = -0.5 * identity;
      w.block(deltaRow, d * (t + 1), d, d) = 0.5 * identity;
    }
    precision.block(staticRow, staticRow, d, d) = frame.staticPrecision;
    precision.block(deltaRow, deltaRow, d, d) = frame.deltaPrecision;
    mean.segment(staticRow, d) = frame.staticMean;
    mean.segment(deltaRow, d) = frame.deltaMean;
  }
  const Eigen::MatrixXd normal = w.transpose() * precision * w;
  const Eigen::VectorXd stacked = normal.ldlt().solve(w.transpose() * precision * mean);
  const Eigen::MatrixXd expected = stacked.reshaped(d, numFrames);

  const Eigen::MatrixXd x = generateTrajectory(frames);
  ASSERT_EQ(x.rows(), d);
  ASSERT_EQ(x.cols(), numFrames);
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-10) << x << "\n\n" << expected;
}

void expectErrorContaining(const std::function<void()>& call, const std::string& fragment) {
  try {
    call();
    ADD_FAILURE() << "no th::Error; expected one containing \"" << fragment << "\"";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

TEST(Mlpg, RejectsBadInputNamingTheFrame) {
  expectErrorContaining([] { generateTrajectory({}); }, "frame");
  expectErrorContaining([] { deltas(Eigen::MatrixXd(2, 0)); }, "frame");

  std::mt19937 rng(5);
  const Eigen::Index d = 3;
  const Eigen::Index numFrames = 10;
  const std::vector<MlpgFrame> good =
      framesWithRandomPrecisions(rng, randomNormal(rng, d, numFrames), randomNormal(rng, d, numFrames));
  ASSERT_NO_THROW(generateTrajectory(good));

  auto withFrame = [&good](std::size_t index, const std::function<void(MlpgFrame&)>& spoil) {
    std::vector<MlpgFrame> frames = good;
    spoil(frames[index]);
    return frames;
  };
  const auto wrongDeltaPrecision = withFrame(7, [](MlpgFrame& f) { f.deltaPrecision = Eigen::MatrixXd::Ones(2, 3); });
  expectErrorContaining([&] { generateTrajectory(wrongDeltaPrecision); },
                        "MLPG: frame 7 has a delta precision of 2 x 3, expected 3 x 3");
  const auto wrongStaticMean = withFrame(4, [](MlpgFrame& f) { f.staticMean = Eigen::VectorXd::Zero(2); });
  expectErrorContaining([&] { generateTrajectory(wrongStaticMean); }, "frame 4");
  const auto wrongDeltaMean = withFrame(9, [](MlpgFrame& f) { f.deltaMean = Eigen::VectorXd::Zero(4); });
  expectErrorContaining([&] { generateTrajectory(wrongDeltaMean); }, "frame 9");
  const auto wrongStaticPrecision = withFrame(1, [](MlpgFrame& f) { f.staticPrecision.resize(3, 2); });
  expectErrorContaining([&] { generateTrajectory(wrongStaticPrecision); }, "frame 1");
  const auto notFinite = withFrame(2, [](MlpgFrame& f) { f.staticPrecision(1, 1) = std::nan(""); });
  expectErrorContaining([&] { generateTrajectory(notFinite); }, "frame 2");

  // Sizes are fine but no trajectory is most likely: all precisions zero, or a negative-definite one.
  std::vector<MlpgFrame> flat = good;
  for (MlpgFrame& frame : flat) {
    frame.staticPrecision.setZero();
    frame.deltaPrecision.setZero();
  }
  expectErrorContaining([&] { generateTrajectory(flat); }, "positive definite");
  const auto negative = withFrame(3, [](MlpgFrame& f) { f.staticPrecision = -100.0 * f.staticPrecision; });
  expectErrorContaining([&] { generateTrajectory(negative); }, "positive definite");
}

}  // namespace
}  // namespace th::animation
