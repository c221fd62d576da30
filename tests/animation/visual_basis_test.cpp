// The mouth model's visual basis (PCA then FastICA): it recovers known independent sources from a linear mix,
// its outputs are white on the training data, it reconstructs data of its own subspace exactly, its form is
// canonical and reproducible, standardising makes units irrelevant, stored parts round-trip, bad input is a
// th::Error, and it runs on the real BEAT2 jaw + FLAME expression data.
#include "animation/visual_basis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/data_path.h"
#include "core/error.h"
#include "core/numeric_csv.h"

namespace th::animation {
namespace {

Eigen::MatrixXd randomNormal(std::mt19937& rng, Eigen::Index rows, Eigen::Index cols, double deviation = 1.0) {
  std::normal_distribution<double> normal(0.0, deviation);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = normal(rng);
  }
  return m;
}

// Two independent unit-variance sources, 2 x T: uniform (sub-Gaussian) and Laplace (super-Gaussian).
Eigen::MatrixXd nonGaussianSources(std::mt19937& rng, Eigen::Index numFrames) {
  std::uniform_real_distribution<double> uniform(-std::sqrt(3.0), std::sqrt(3.0));
  // Laplace: the difference of two exponentials of rate √2 has variance 2 / 2 = 1.
  std::exponential_distribution<double> exponential(std::sqrt(2.0));
  Eigen::MatrixXd s(2, numFrames);
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    s(0, t) = uniform(rng);
    s(1, t) = exponential(rng) - exponential(rng);
  }
  return s;
}

struct MixedData {
  Eigen::MatrixXd sources;  // 2 x T
  Eigen::MatrixXd x;        // d x T
};

// x = offset + A s + noise, A d x 2 random, noise of the given deviation.
MixedData mixedData(unsigned seed, Eigen::Index d, Eigen::Index numFrames, double noise) {
  std::mt19937 rng(seed);
  MixedData data;
  data.sources = nonGaussianSources(rng, numFrames);
  const Eigen::MatrixXd a = randomNormal(rng, d, 2);
  const Eigen::VectorXd offset = randomNormal(rng, d, 1, 5.0);
  data.x = (a * data.sources).colwise() + offset;
  if (noise > 0.0) data.x += randomNormal(rng, d, numFrames, noise);
  return data;
}

double correlation(const Eigen::Ref<const Eigen::RowVectorXd>& a, const Eigen::Ref<const Eigen::RowVectorXd>& b) {
  const Eigen::RowVectorXd ca = a.array() - a.mean();
  const Eigen::RowVectorXd cb = b.array() - b.mean();
  return ca.dot(cb) / std::sqrt(ca.squaredNorm() * cb.squaredNorm());
}

Eigen::MatrixXd covarianceOf(const Eigen::MatrixXd& y) {
  const Eigen::MatrixXd centred = y.colwise() - y.rowwise().mean();
  return centred * centred.transpose() / static_cast<double>(y.cols());
}

double maxAbsDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

void expectVisualBasisError(const std::function<void()>& call, const std::string& mention) {
  try {
    call();
    ADD_FAILURE() << "no th::Error; expected one mentioning \"" << mention << "\"";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("visual basis"), std::string::npos) << message;
    EXPECT_NE(message.find(mention), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}

TEST(VisualBasis, RecoversTwoIndependentNonGaussianSourcesFromALinearMix) {
  const MixedData data = mixedData(11, 6, 5000, 0.05);
  const VisualBasis basis = VisualBasis::fit(data.x, {.components = 2});
  ASSERT_EQ(basis.components(), 2);
  ASSERT_EQ(basis.inputDimension(), 6);
  const Eigen::MatrixXd y = basis.transform(data.x);
  // Up to order and sign: the pairing with the larger total |correlation| must recover both.
  Eigen::Matrix2d c;
  for (Eigen::Index i = 0; i < 2; ++i) {
    for (Eigen::Index j = 0; j < 2; ++j) c(i, j) = std::abs(correlation(y.row(i), data.sources.row(j)));
  }
  const bool straight = c(0, 0) + c(1, 1) >= c(0, 1) + c(1, 0);
  const double first = straight ? c(0, 0) : c(0, 1);
  const double second = straight ? c(1, 1) : c(1, 0);
  EXPECT_GT(first, 0.98) << "component 0 vs its source; all |correlations|:\n" << c;
  EXPECT_GT(second, 0.98) << "component 1 vs its source; all |correlations|:\n" << c;
  EXPECT_GT(basis.explainedVariance(), 0.99) << "two sources and a little noise: two components keep nearly all";
}

TEST(VisualBasis, OutputsHaveZeroMeanAndIdentityCovarianceOnTheTrainingData) {
  const MixedData data = mixedData(12, 6, 5000, 0.05);
  const VisualBasis basis = VisualBasis::fit(data.x);
  const Eigen::MatrixXd y = basis.transform(data.x);
  ASSERT_EQ(y.rows(), 2);
  ASSERT_EQ(y.cols(), 5000);
  EXPECT_LT(y.rowwise().mean().cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(maxAbsDifference(covarianceOf(y), Eigen::Matrix2d::Identity()), 1e-6) << covarianceOf(y);
}

TEST(VisualBasis, ReconstructsDataOfItsSubspaceExactlyAndKeepsAllTheirVariance) {
  // Exactly 2-D data (plus a mean) in 7 dimensions.
  const MixedData exact = mixedData(13, 7, 3000, 0.0);
  const VisualBasis basis = VisualBasis::fit(exact.x);
  EXPECT_NEAR(basis.explainedVariance(), 1.0, 1e-9);
  EXPECT_LT(maxAbsDifference(basis.reconstruct(basis.transform(exact.x)), exact.x), 1e-8);
  // mixing is the inverse of unmixing within the subspace.
  EXPECT_LT(maxAbsDifference(basis.unmixing() * basis.mixing(), Eigen::Matrix2d::Identity()), 1e-12);

  // With noise in every dimension, K = 2 keeps less than everything and the reconstruction is not exact.
  const MixedData noisy = mixedData(13, 7, 3000, 0.2);
  const VisualBasis noisyBasis = VisualBasis::fit(noisy.x);
  EXPECT_LT(noisyBasis.explainedVariance(), 0.999);
  EXPECT_GT(noisyBasis.explainedVariance(), 0.5);
  EXPECT_GT(maxAbsDifference(noisyBasis.reconstruct(noisyBasis.transform(noisy.x)), noisy.x), 0.1);
}

TEST(VisualBasis, IsDeterministicAndCanonical) {
  const MixedData data = mixedData(14, 6, 5000, 0.05);
  const VisualBasis a = VisualBasis::fit(data.x);
  const VisualBasis b = VisualBasis::fit(data.x);
  EXPECT_EQ(a.unmixing(), b.unmixing());
  EXPECT_EQ(a.mixing(), b.mixing());
  EXPECT_EQ(a.mean(), b.mean());
  EXPECT_EQ(a.scale(), b.scale());
  EXPECT_EQ(a.explainedVariance(), b.explainedVariance());

  for (Eigen::Index k = 0; k < a.mixing().cols(); ++k) {
    Eigen::Index largest = 0;
    a.mixing().col(k).cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(a.mixing()(largest, k), 0.0) << "component " << k << ": its largest-magnitude mixing entry";
    if (k > 0) {
      EXPECT_GE(a.mixing().col(k - 1).squaredNorm(), a.mixing().col(k).squaredNorm()) << "order at " << k;
    }
  }
  EXPECT_GT(a.mixing().col(0).squaredNorm(), 1.01 * a.mixing().col(1).squaredNorm())
      << "this data set's two components differ in size, so the order is a real decision";

  // Another random start reaches the same optimum, and the canonical form makes it the same matrices.
  const VisualBasis otherSeed = VisualBasis::fit(data.x, {.seed = 12345});
  EXPECT_LT(maxAbsDifference(otherSeed.unmixing(), a.unmixing()), 1e-4);
  EXPECT_LT(maxAbsDifference(otherSeed.mixing(), a.mixing()), 1e-4);
}

TEST(VisualBasis, StandardisingMakesTheUnitsOfADimensionIrrelevant) {
  const MixedData data = mixedData(15, 6, 4000, 0.05);
  Eigen::MatrixXd rescaled = data.x;
  rescaled.row(2) *= 1000.0;
  const Eigen::MatrixXd y = VisualBasis::fit(data.x).transform(data.x);
  const Eigen::MatrixXd yRescaled = VisualBasis::fit(rescaled).transform(rescaled);
  EXPECT_LT(maxAbsDifference(y, yRescaled), 1e-6);

  // Without standardising, the dimension in "milli-units" dominates PCA and the output changes.
  const VisualBasisOptions raw{.standardise = false};
  const VisualBasis rawBasis = VisualBasis::fit(rescaled, raw);
  EXPECT_EQ(rawBasis.scale(), Eigen::VectorXd::Ones(6));
  EXPECT_GT(maxAbsDifference(VisualBasis::fit(data.x, raw).transform(data.x), rawBasis.transform(rescaled)), 0.1);

  // A constant dimension gets scale 1 and changes nothing.
  Eigen::MatrixXd withConstant(7, data.x.cols());
  withConstant.topRows(6) = data.x;
  withConstant.row(6).setConstant(0.1);
  const VisualBasis constantBasis = VisualBasis::fit(withConstant);
  EXPECT_EQ(constantBasis.scale()[6], 1.0);
  EXPECT_LT(maxAbsDifference(constantBasis.transform(withConstant), y), 1e-6);
}

TEST(VisualBasis, FromPartsRoundTripsAndRejectsBadParts) {
  const MixedData data = mixedData(16, 6, 2000, 0.05);
  const VisualBasis basis = VisualBasis::fit(data.x);
  const VisualBasis copy =
      VisualBasis::fromParts(basis.mean(), basis.scale(), basis.unmixing(), basis.mixing(), basis.explainedVariance());
  EXPECT_EQ(copy.transform(data.x), basis.transform(data.x));
  EXPECT_EQ(copy.reconstruct(basis.transform(data.x)), basis.reconstruct(basis.transform(data.x)));
  EXPECT_EQ(copy.explainedVariance(), basis.explainedVariance());

  const auto rebuild = [&](Eigen::VectorXd mean, Eigen::VectorXd scale, Eigen::MatrixXd unmixing,
                           Eigen::MatrixXd mixing, double explained) {
    return [=] { VisualBasis::fromParts(mean, scale, unmixing, mixing, explained); };
  };
  const Eigen::VectorXd& m = basis.mean();
  const Eigen::VectorXd& s = basis.scale();
  const Eigen::MatrixXd& u = basis.unmixing();
  const Eigen::MatrixXd& a = basis.mixing();
  const double e = basis.explainedVariance();
  expectVisualBasisError(rebuild(Eigen::VectorXd(), Eigen::VectorXd(), u, a, e), "mean is empty");
  expectVisualBasisError(rebuild(m, Eigen::VectorXd::Ones(5), u, a, e), "scale has 5 entries");
  expectVisualBasisError(rebuild(m, s, u.leftCols(5), a, e), "unmixing is 2 x 5");
  expectVisualBasisError(rebuild(m, s, u, a.topRows(5), e), "mixing is 5 x 2");
  expectVisualBasisError(rebuild(m, s, u, a.leftCols(1), e), "mixing is 6 x 1");
  Eigen::MatrixXd nanUnmixing = u;
  nanUnmixing(1, 3) = std::numeric_limits<double>::quiet_NaN();
  expectVisualBasisError(rebuild(m, s, nanUnmixing, a, e), "NaN");
  Eigen::VectorXd nanMean = m;
  nanMean[0] = std::numeric_limits<double>::infinity();
  expectVisualBasisError(rebuild(nanMean, s, u, a, e), "NaN");
  Eigen::VectorXd zeroScale = s;
  zeroScale[4] = 0.0;
  expectVisualBasisError(rebuild(m, zeroScale, u, a, e), "scale has an entry <= 0");
  expectVisualBasisError(rebuild(m, s, u, a, 1.5), "outside [0, 1]");
  expectVisualBasisError(rebuild(m, s, u, 2.0 * a, e), "do not belong together");
}

TEST(VisualBasis, RejectsBadInputWithOneLineErrors) {
  const MixedData data = mixedData(17, 6, 2000, 0.05);
  expectVisualBasisError([&] { VisualBasis::fit(data.x.leftCols(2), {.components = 2}); }, "2 frames are too few");
  EXPECT_NO_THROW(VisualBasis::fit(data.x.leftCols(3), {.components = 2, .maxIterations = 100000}))
      << "K + 1 frames are enough";
  expectVisualBasisError([&] { VisualBasis::fit(data.x, {.components = 0}); }, "0 components");
  expectVisualBasisError([&] { VisualBasis::fit(data.x, {.components = 7}); }, "7 components asked of 6-dimensional");
  Eigen::MatrixXd withNan = data.x;
  withNan(3, 1500) = std::numeric_limits<double>::quiet_NaN();
  expectVisualBasisError([&] { VisualBasis::fit(withNan); }, "NaN");
  expectVisualBasisError([&] { VisualBasis::fit(data.x, {.maxIterations = 1}); },
                         "did not converge within 1 iterations");
  // One-dimensional data cannot be whitened to two components.
  const Eigen::MatrixXd line = Eigen::VectorXd::LinSpaced(6, 1.0, 6.0) * data.sources.row(0);
  expectVisualBasisError([&] { VisualBasis::fit(line); }, "span fewer than 2 dimensions");
}

// The real data: jaw opening (degrees) and the 100 FLAME expression coefficients of the BEAT2 take, 30 fps.
Eigen::MatrixXd beat2Visual() {
  const NumericTable expression = readNumericCsv(sharedDataPath("beat2/2_scott_0_1_1_flame_expr_30fps.csv"));
  const NumericTable pose = readNumericCsv(sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"));
  EXPECT_EQ(expression.columns.size(), 100u);
  EXPECT_EQ(expression.rows.size(), pose.rows.size()) << "the two CSVs are the same take, frame for frame";
  const size_t jaw = static_cast<size_t>(pose.column("jaw_aa_x_deg"));
  const Eigen::Index numFrames = static_cast<Eigen::Index>(std::min(expression.rows.size(), pose.rows.size()));
  Eigen::MatrixXd x(1 + static_cast<Eigen::Index>(expression.columns.size()), numFrames);
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const auto& row = expression.rows[static_cast<size_t>(t)];
    x(0, t) = pose.rows[static_cast<size_t>(t)][jaw];
    for (size_t e = 0; e < row.size(); ++e) x(static_cast<Eigen::Index>(e) + 1, t) = row[e];
  }
  return x;
}

TEST(VisualBasis, FitsTheBeat2JawAndExpressionData) {
  const Eigen::MatrixXd x = beat2Visual();
  ASSERT_EQ(x.rows(), 101);
  ASSERT_EQ(x.cols(), 1906);
  const VisualBasis basis = VisualBasis::fit(x, {.components = 2});
  const Eigen::MatrixXd y = basis.transform(x);
  ASSERT_TRUE(y.allFinite());
  EXPECT_LT(maxAbsDifference(covarianceOf(y), Eigen::Matrix2d::Identity()), 1e-6) << covarianceOf(y);
  EXPECT_GT(basis.explainedVariance(), 0.0);
  EXPECT_LT(basis.explainedVariance(), 1.0);
  std::printf("[ INFO     ] BEAT2 101 x %d (jaw + 100 FLAME): K = 2 PCA keeps %.4f of the standardised variance\n",
              static_cast<int>(x.cols()), basis.explainedVariance());
  for (Eigen::Index k = 0; k < 2; ++k) {
    std::printf("[ INFO     ] component %d: correlation with jaw opening %+.4f, |mixing column|^2 %.3f\n",
                static_cast<int>(k), correlation(y.row(k), x.row(0)), basis.mixing().col(k).squaredNorm());
  }
}

}  // namespace
}  // namespace th::animation
