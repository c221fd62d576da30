#include "animation/visual_basis.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace th::animation {
namespace {

// A dimension whose standard deviation is below this fraction of its largest magnitude is constant: summing a
// constant row and dividing by T need not give the constant back exactly, so "constant" data can show a
// rounding-level spread that standardising would blow up to unit variance.
constexpr double kConstantRelativeSpread = 1e-12;
// PCA components below this fraction of the largest eigenvalue are rounding noise: whitening them would
// divide by (almost) zero, so fewer than K such components means the data do not span K dimensions.
constexpr double kRankRelativeEigenvalue = 1e-12;

std::string shape(Eigen::Index rows, Eigen::Index cols) {
  return std::to_string(rows) + " x " + std::to_string(cols);
}

// The sign that makes the largest-magnitude entry of v positive (the first such entry on a tie).
double canonicalSign(const Eigen::Ref<const Eigen::VectorXd>& v) {
  Eigen::Index largest = 0;
  for (Eigen::Index i = 1; i < v.size(); ++i) {
    if (std::abs(v[i]) > std::abs(v[largest])) largest = i;
  }
  return v[largest] < 0.0 ? -1.0 : 1.0;
}

// W ← (W Wᵀ)^{-1/2} W (Hyvärinen 1999, symmetric decorrelation): the orthogonal matrix nearest to W. It
// treats every row alike, so no component is privileged as in deflation.
Eigen::MatrixXd symmetricDecorrelation(const Eigen::MatrixXd& w, int iteration) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(w * w.transpose());
  const Eigen::VectorXd& values = eigen.eigenvalues();
  // Ascending, so values[0] is the smallest: a zero means two rows of W became parallel.
  if (eigen.info() != Eigen::Success || !values.allFinite() || !(values[0] > 0.0)) {
    throw Error("visual basis: FastICA degenerated (rows of W became dependent) at iteration " +
                std::to_string(iteration));
  }
  const Eigen::MatrixXd& vectors = eigen.eigenvectors();
  return vectors * values.cwiseSqrt().cwiseInverse().asDiagonal() * vectors.transpose() * w;
}

// Symmetric FastICA on whitened data z (K x T, covariance I): the K x K orthogonal W whose rows maximise the
// logcosh contrast. Fixed point (Hyvärinen 1999, one-unit update for all rows at once):
//   W⁺ = E{g(W z) zᵀ} − diag(E{g'(W z)}) W,   g = tanh, g' = 1 − tanh²,
// then symmetric decorrelation. Converged when no row turned by more than the tolerance allows:
// max_k |1 − |w⁺_k · w_k|| < tolerance (the absolute value because a row may flip sign and still be a fixed
// point).
Eigen::MatrixXd fastIca(const Eigen::MatrixXd& z, const VisualBasisOptions& options) {
  const Eigen::Index k = z.rows();
  const Eigen::Index numFrames = z.cols();
  const double inverseFrames = 1.0 / static_cast<double>(numFrames);

  // A random orthogonal start: Gaussian entries, then the nearest orthogonal matrix.
  std::mt19937 random(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd start(k, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    for (Eigen::Index i = 0; i < k; ++i) start(i, j) = normal(random);
  }
  Eigen::MatrixXd w = symmetricDecorrelation(start, 0);

  Eigen::MatrixXd g(k, numFrames);
  Eigen::VectorXd meanDerivative(k);
  for (int iteration = 1; iteration <= options.maxIterations; ++iteration) {
    g.noalias() = w * z;
    g = g.array().tanh().matrix();
    // Plain loops: GCC 12 reports false -Wnull-dereference inside Eigen reductions over such temporaries.
    for (Eigen::Index row = 0; row < k; ++row) {
      double sum = 0.0;
      for (Eigen::Index t = 0; t < numFrames; ++t) sum += 1.0 - g(row, t) * g(row, t);
      meanDerivative[row] = sum * inverseFrames;
    }
    Eigen::MatrixXd next = (g * z.transpose()) * inverseFrames - meanDerivative.asDiagonal() * w;
    next = symmetricDecorrelation(next, iteration);

    double change = 0.0;
    for (Eigen::Index row = 0; row < k; ++row) {
      change = std::max(change, std::abs(1.0 - std::abs(next.row(row).dot(w.row(row)))));
    }
    w = std::move(next);
    if (change < options.tolerance) return w;
  }
  throw Error("visual basis: FastICA did not converge within " + std::to_string(options.maxIterations) +
              " iterations (tolerance " + std::to_string(options.tolerance) + ")");
}

void checkOptions(const VisualBasisOptions& options, Eigen::Index dimension, Eigen::Index numFrames) {
  const Eigen::Index k = options.components;
  if (k < 1 || k > dimension) {
    throw Error("visual basis: " + std::to_string(k) + " components asked of " + std::to_string(dimension) +
                "-dimensional data (need 1 <= K <= d)");
  }
  if (numFrames < k + 1) {
    throw Error("visual basis: " + std::to_string(numFrames) + " frames are too few for " + std::to_string(k) +
                " components (need at least K + 1 = " + std::to_string(k + 1) + ")");
  }
  if (options.maxIterations < 1) {
    throw Error("visual basis: maxIterations is " + std::to_string(options.maxIterations) + ", need >= 1");
  }
  if (!(options.tolerance > 0.0)) throw Error("visual basis: the FastICA tolerance must be positive");
}

// Each parameter's standard deviation, or 1 where it is constant (kConstantRelativeSpread says why).
Eigen::VectorXd standardisingScales(const Eigen::MatrixXd& data, const Eigen::MatrixXd& centred) {
  const double inverseFrames = 1.0 / static_cast<double>(data.cols());
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(data.rows());
  for (Eigen::Index i = 0; i < data.rows(); ++i) {
    double sumSquares = 0.0;
    double largest = 0.0;
    for (Eigen::Index t = 0; t < data.cols(); ++t) {
      sumSquares += centred(i, t) * centred(i, t);
      largest = std::max(largest, std::abs(data(i, t)));
    }
    const double deviation = std::sqrt(sumSquares * inverseFrames);
    if (deviation > kConstantRelativeSpread * largest) scale[i] = deviation;
  }
  return scale;
}

}  // namespace

VisualBasis VisualBasis::fit(const Eigen::MatrixXd& data, const VisualBasisOptions& options) {
  const Eigen::Index d = data.rows();
  const Eigen::Index numFrames = data.cols();
  checkOptions(options, d, numFrames);
  if (!data.allFinite()) throw Error("visual basis: the data contain NaN or infinite values");
  const Eigen::Index k = options.components;
  const double inverseFrames = 1.0 / static_cast<double>(numFrames);

  VisualBasis basis;
  basis.mean_ = data.rowwise().mean();
  Eigen::MatrixXd centred = data.colwise() - basis.mean_;
  basis.scale_ = Eigen::VectorXd::Ones(d);
  if (options.standardise) {
    basis.scale_ = standardisingScales(data, centred);
    centred = basis.scale_.cwiseInverse().asDiagonal() * centred;
  }

  // PCA: eigenpairs of the covariance of x̃, ascending; the K largest are the last K.
  const Eigen::MatrixXd covariance = (centred * centred.transpose()) * inverseFrames;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance);
  if (eigen.info() != Eigen::Success) {
    throw Error("visual basis: the eigen-decomposition of the covariance failed");
  }
  const Eigen::VectorXd& allValues = eigen.eigenvalues();
  const double largestValue = allValues[d - 1];
  Eigen::VectorXd values(k);
  Eigen::MatrixXd vectors(d, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    values[j] = allValues[d - 1 - j];
    vectors.col(j) = eigen.eigenvectors().col(d - 1 - j);
    // Eigenvectors have no sign of their own; fixing it makes FastICA's input, and so its path, reproducible.
    vectors.col(j) *= canonicalSign(vectors.col(j));
  }
  if (!(largestValue > 0.0) || !(values[k - 1] > kRankRelativeEigenvalue * largestValue)) {
    throw Error("visual basis: the data span fewer than " + std::to_string(k) + " dimensions (PCA eigenvalue " +
                std::to_string(k) + " is " + std::to_string(values[k - 1]) + " of largest " +
                std::to_string(largestValue) + ")");
  }
  double total = 0.0;  // the trace: the total variance of x̃, free of the eigen-solver's rounding
  for (Eigen::Index i = 0; i < d; ++i) total += covariance(i, i);
  double kept = 0.0;
  for (Eigen::Index j = 0; j < k; ++j) kept += values[j];
  basis.explainedVariance_ = std::min(1.0, kept / total);

  // Whitening z = Λ^{-1/2} Vᵀ x̃ (cov(z) = I), then the ICA rotation W.
  const Eigen::VectorXd inverseRoot = values.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd whitening = inverseRoot.asDiagonal() * vectors.transpose();  // K x d
  const Eigen::MatrixXd z = whitening * centred;
  const Eigen::MatrixXd w = fastIca(z, options);
  const Eigen::MatrixXd unmixing = w * whitening;                                            // W Λ^{-1/2} Vᵀ
  const Eigen::MatrixXd mixing = vectors * values.cwiseSqrt().asDiagonal() * w.transpose();  // V Λ^{1/2} Wᵀ

  // Canonical form: by decreasing ‖mixing column‖² (each y_k has unit variance and they are uncorrelated, so
  // that is the variance component k contributes to x̃), ties by index; then signs.
  std::vector<Eigen::Index> order(static_cast<std::size_t>(k));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::vector<double> contribution(static_cast<std::size_t>(k));
  for (Eigen::Index j = 0; j < k; ++j) {
    contribution[static_cast<std::size_t>(j)] = mixing.col(j).squaredNorm();
  }
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    return contribution[static_cast<std::size_t>(a)] > contribution[static_cast<std::size_t>(b)];
  });
  basis.unmixing_.resize(k, d);
  basis.mixing_.resize(d, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Eigen::Index from = order[static_cast<std::size_t>(j)];
    const double sign = canonicalSign(mixing.col(from));
    basis.mixing_.col(j) = sign * mixing.col(from);
    basis.unmixing_.row(j) = sign * unmixing.row(from);
  }
  return basis;
}

VisualBasis VisualBasis::fromParts(Eigen::VectorXd mean, Eigen::VectorXd scale, Eigen::MatrixXd unmixing,
                                   Eigen::MatrixXd mixing, double explainedVariance) {
  const Eigen::Index d = mean.size();
  const Eigen::Index k = unmixing.rows();
  if (d < 1) throw Error("visual basis: the stored mean is empty");
  if (scale.size() != d) {
    throw Error("visual basis: the stored scale has " + std::to_string(scale.size()) + " entries, the mean " +
                std::to_string(d));
  }
  if (k < 1 || k > d || unmixing.cols() != d) {
    throw Error("visual basis: the stored unmixing is " + shape(unmixing.rows(), unmixing.cols()) + ", expected K x " +
                std::to_string(d) + " with 1 <= K <= " + std::to_string(d));
  }
  if (mixing.rows() != d || mixing.cols() != k) {
    throw Error("visual basis: the stored mixing is " + shape(mixing.rows(), mixing.cols()) + ", expected " +
                shape(d, k));
  }
  if (!mean.allFinite() || !scale.allFinite() || !unmixing.allFinite() || !mixing.allFinite() ||
      !std::isfinite(explainedVariance)) {
    throw Error("visual basis: the stored parts contain NaN or infinite values");
  }
  if (!(scale.minCoeff() > 0.0)) throw Error("visual basis: the stored scale has an entry <= 0");
  if (explainedVariance < 0.0 || explainedVariance > 1.0) {
    throw Error("visual basis: the stored explained variance " + std::to_string(explainedVariance) +
                " is outside [0, 1]");
  }
  const Eigen::MatrixXd product = unmixing * mixing;
  double offIdentity = 0.0;
  for (Eigen::Index j = 0; j < k; ++j) {
    for (Eigen::Index i = 0; i < k; ++i) {
      offIdentity = std::max(offIdentity, std::abs(product(i, j) - (i == j ? 1.0 : 0.0)));
    }
  }
  if (offIdentity > 1e-6) {
    throw Error("visual basis: the stored unmixing and mixing do not belong together (unmixing · mixing is " +
                std::to_string(offIdentity) + " from the identity)");
  }
  VisualBasis basis;
  basis.mean_ = std::move(mean);
  basis.scale_ = std::move(scale);
  basis.unmixing_ = std::move(unmixing);
  basis.mixing_ = std::move(mixing);
  basis.explainedVariance_ = explainedVariance;
  return basis;
}

Eigen::MatrixXd VisualBasis::transform(const Eigen::MatrixXd& x) const {
  assert(x.rows() == mean_.size() && "visual basis: transform needs d x T input");
  return unmixing_ * (scale_.cwiseInverse().asDiagonal() * (x.colwise() - mean_));
}

Eigen::MatrixXd VisualBasis::reconstruct(const Eigen::MatrixXd& y) const {
  assert(y.rows() == unmixing_.rows() && "visual basis: reconstruct needs K x T input");
  return (scale_.asDiagonal() * (mixing_ * y)).colwise() + mean_;
}

}  // namespace th::animation
