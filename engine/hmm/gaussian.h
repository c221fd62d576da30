// Gaussian densities with full or diagonal covariance, and Gaussian mixtures, evaluated in the log domain.
//
//   th::hmm::Gaussian g(mean, covariance, th::hmm::CovarianceType::kFull);   // throws if not positive definite
//   double logP = g.logDensity(x);
//   Eigen::VectorXd logPs(frames.cols());
//   g.logDensities(frames, logPs);            // frames: d x T, one observation per column
//
// Full covariance is factored once (Cholesky, Σ = L Lᵀ): log N(x) = −½(d log 2π + log|Σ| + ‖L⁻¹(x − μ)‖²).
// Diagonal covariance keeps only the variances. Matrices hold one observation per column throughout engine/hmm.
// Thread contract: immutable after construction; safe to share across threads.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace th::hmm {

enum class CovarianceType { kFull, kDiagonal };

class Gaussian {
 public:
  Gaussian() = default;
  // For kDiagonal only the diagonal of `covariance` is used. Throws th::Error if it is not positive definite.
  Gaussian(Eigen::VectorXd mean, const Eigen::MatrixXd& covariance, CovarianceType type);

  int dimension() const { return static_cast<int>(mean_.size()); }
  CovarianceType type() const { return type_; }
  const Eigen::VectorXd& mean() const { return mean_; }
  // The full matrix (diagonal for kDiagonal).
  const Eigen::MatrixXd& covariance() const { return covariance_; }
  double logDeterminant() const { return logDeterminant_; }

  double logDensity(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  // One value per column of `frames` (d x T) into `out` (T).
  void logDensities(const Eigen::Ref<const Eigen::MatrixXd>& frames, Eigen::Ref<Eigen::VectorXd> out) const;

 private:
  Eigen::VectorXd mean_;
  Eigen::MatrixXd covariance_;
  CovarianceType type_ = CovarianceType::kFull;
  Eigen::MatrixXd choleskyLower_;     // kFull: L with Σ = L Lᵀ
  Eigen::VectorXd inverseVariances_;  // kDiagonal
  double logDeterminant_ = 0.0;
  double logNormaliser_ = 0.0;  // −½(d log 2π + log|Σ|)
};

// Σₘ wₘ N(x; μₘ, Σₘ). Weights are non-negative and sum to 1; zero-weight components are allowed (trimmed).
class GaussianMixture {
 public:
  GaussianMixture() = default;
  GaussianMixture(Eigen::VectorXd weights, std::vector<Gaussian> components);

  int numComponents() const { return static_cast<int>(components_.size()); }
  int dimension() const { return components_.empty() ? 0 : components_.front().dimension(); }
  const Eigen::VectorXd& weights() const { return weights_; }
  const std::vector<Gaussian>& components() const { return components_; }

  double logDensity(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  // componentLogDensities (M x T): log wₘ + log Nₘ(xₜ); out (T): their log-sum-exp per column.
  void logDensities(const Eigen::Ref<const Eigen::MatrixXd>& frames, Eigen::Ref<Eigen::VectorXd> out,
                    Eigen::MatrixXd* componentLogDensities = nullptr) const;

 private:
  Eigen::VectorXd weights_;
  std::vector<Gaussian> components_;
};

// log Σ exp(values), stable; −∞ if all are −∞.
double logSumExp(const Eigen::Ref<const Eigen::VectorXd>& values);

// The covariance nearest in likelihood to `covariance` with Σ ⪰ diag(floor): diagonal, each variance raised to
// its floor; full, the eigenvalues of D^(-1/2) Σ D^(-1/2) raised to 1 (the exact constrained ML estimate, so EM
// with the floor never loses likelihood; collinear data get a proper floor in every direction).
Eigen::MatrixXd applyCovarianceFloor(const Eigen::MatrixXd& covariance, const Eigen::VectorXd& floor,
                                     CovarianceType type);

}  // namespace th::hmm
