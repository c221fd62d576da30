#include "hmm/gaussian.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"

namespace th::hmm {

Gaussian::Gaussian(Eigen::VectorXd mean, const Eigen::MatrixXd& covariance, CovarianceType type)
    : mean_(std::move(mean)), type_(type) {
  const auto d = mean_.size();
  if (covariance.rows() != d || covariance.cols() != d) throw Error("Gaussian: covariance shape does not match mean");
  if (!mean_.allFinite() || !covariance.allFinite()) throw Error("Gaussian: mean or covariance is not finite");
  if (type == CovarianceType::kDiagonal) {
    const Eigen::VectorXd variances = covariance.diagonal();
    if ((variances.array() <= 0.0).any()) throw Error("Gaussian: variances must be positive");
    covariance_ = variances.asDiagonal();
    inverseVariances_ = variances.cwiseInverse();
    logDeterminant_ = variances.array().log().sum();
  } else {
    covariance_ = 0.5 * (covariance + covariance.transpose());
    Eigen::LLT<Eigen::MatrixXd> cholesky(covariance_);
    if (cholesky.info() != Eigen::Success) throw Error("Gaussian: covariance is not positive definite");
    choleskyLower_ = cholesky.matrixL();
    logDeterminant_ = 2.0 * choleskyLower_.diagonal().array().log().sum();
  }
  if (!std::isfinite(logDeterminant_)) throw Error("Gaussian: covariance is singular");
  logNormaliser_ = -0.5 * (static_cast<double>(d) * std::log(2.0 * std::numbers::pi) + logDeterminant_);
}

double Gaussian::logDensity(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const Eigen::VectorXd centred = x - mean_;
  double mahalanobis = 0.0;
  if (type_ == CovarianceType::kDiagonal) {
    mahalanobis = centred.cwiseAbs2().dot(inverseVariances_);
  } else {
    mahalanobis = choleskyLower_.triangularView<Eigen::Lower>().solve(centred).squaredNorm();
  }
  return logNormaliser_ - 0.5 * mahalanobis;
}

void Gaussian::logDensities(const Eigen::Ref<const Eigen::MatrixXd>& frames, Eigen::Ref<Eigen::VectorXd> out) const {
  // A block of frames at a time: the centred copy stays small enough for the cache, and one buffer serves the
  // whole sequence instead of a copy of all of it.
  constexpr Eigen::Index kBlockFrames = 128;
  const Eigen::Index numFrames = frames.cols();
  Eigen::MatrixXd centred(frames.rows(), std::min(kBlockFrames, numFrames));
  for (Eigen::Index start = 0; start < numFrames; start += kBlockFrames) {
    const Eigen::Index count = std::min(kBlockFrames, numFrames - start);
    auto block = centred.leftCols(count);
    block = frames.middleCols(start, count).colwise() - mean_;
    if (type_ == CovarianceType::kDiagonal) {
      out.segment(start, count) = (inverseVariances_.transpose() * block.cwiseAbs2()).transpose();
    } else {
      // One triangular solve for the block's frames: the columns of L⁻¹(X − μ).
      choleskyLower_.triangularView<Eigen::Lower>().solveInPlace(block);
      out.segment(start, count) = block.colwise().squaredNorm().transpose();
    }
  }
  out = (logNormaliser_ - 0.5 * out.array()).matrix();
}

GaussianMixture::GaussianMixture(Eigen::VectorXd weights, std::vector<Gaussian> components)
    : weights_(std::move(weights)), components_(std::move(components)) {
  if (components_.empty()) throw Error("mixture: no components");
  if (weights_.size() != static_cast<Eigen::Index>(components_.size()))
    throw Error("mixture: weights do not match components");
  if (!weights_.allFinite() || (weights_.array() < 0.0).any() || std::abs(weights_.sum() - 1.0) > 1e-6) {
    throw Error("mixture: weights must be non-negative and sum to 1");
  }
  for (const auto& component : components_) {
    if (component.dimension() != components_.front().dimension())
      throw Error("mixture: components differ in dimension");
  }
}

double logSumExp(const Eigen::Ref<const Eigen::VectorXd>& values) {
  const double top = values.maxCoeff();
  if (!std::isfinite(top)) return top;
  return top + std::log((values.array() - top).exp().sum());
}

double GaussianMixture::logDensity(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Eigen::VectorXd terms(numComponents());
  for (int m = 0; m < numComponents(); ++m) {
    terms[m] = weights_[m] > 0.0 ? std::log(weights_[m]) + components_[static_cast<size_t>(m)].logDensity(x)
                                 : -std::numeric_limits<double>::infinity();
  }
  return logSumExp(terms);
}

void GaussianMixture::logDensities(const Eigen::Ref<const Eigen::MatrixXd>& frames, Eigen::Ref<Eigen::VectorXd> out,
                                   Eigen::MatrixXd* componentLogDensities) const {
  const auto numFrames = frames.cols();
  if (numComponents() == 1 && !componentLogDensities) {
    components_.front().logDensities(frames, out);
    return;
  }
  Eigen::MatrixXd local;
  Eigen::MatrixXd& terms = componentLogDensities ? *componentLogDensities : local;
  terms.resize(numComponents(), numFrames);
  Eigen::VectorXd column(numFrames);
  for (int m = 0; m < numComponents(); ++m) {
    if (weights_[m] > 0.0) {
      components_[static_cast<size_t>(m)].logDensities(frames, column);
      terms.row(m) = (column.array() + std::log(weights_[m])).transpose();
    } else {
      terms.row(m).setConstant(-std::numeric_limits<double>::infinity());
    }
  }
  for (Eigen::Index t = 0; t < numFrames; ++t) out[t] = logSumExp(terms.col(t));
}

Eigen::MatrixXd applyCovarianceFloor(const Eigen::MatrixXd& covariance, const Eigen::VectorXd& floor,
                                     CovarianceType type) {
  if (type == CovarianceType::kDiagonal) {
    return Eigen::MatrixXd(covariance.diagonal().cwiseMax(floor).asDiagonal());
  }
  const Eigen::MatrixXd symmetric = 0.5 * (covariance + covariance.transpose());
  const Eigen::MatrixXd excess = symmetric - Eigen::MatrixXd(floor.asDiagonal());
  if (Eigen::LLT<Eigen::MatrixXd>(excess).info() == Eigen::Success) return symmetric;  // already Σ ≻ D
  // In coordinates where the floor D is the identity, raise every eigenvalue below 1 to 1. This is the maximum
  // of the Gaussian's expected log-likelihood over {Σ ⪰ D} (the objective is invariant under the change of
  // coordinates up to a constant, and with an identity bound the optimum clamps the eigenvalues), so EM with the
  // floor stays monotone. Raising only the diagonal would leave collinear data near-singular.
  const Eigen::VectorXd scale = floor.cwiseSqrt();
  const Eigen::MatrixXd whitened = scale.cwiseInverse().asDiagonal() * symmetric * scale.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(whitened);
  if (eigen.info() != Eigen::Success) throw Error("covariance floor: the eigen-decomposition failed (not finite?)");
  const Eigen::VectorXd clamped = eigen.eigenvalues().cwiseMax(1.0);
  const Eigen::MatrixXd restored = eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
  Eigen::MatrixXd floored = scale.asDiagonal() * restored * scale.asDiagonal();
  return 0.5 * (floored + floored.transpose());
}

}  // namespace th::hmm
