// The visual basis of the mouth model (Terissi & Gómez): K independent components "of ICA after PCA" over the
// visual parameters of a frame (here jaw opening + 100 FLAME expression coefficients at 30 fps; K = 2).
//
//   Eigen::MatrixXd visual = ...;                    // d x T, one frame per column
//   auto basis = th::animation::VisualBasis::fit(visual, {.components = 2});
//   Eigen::MatrixXd y = basis.transform(visual);     // K x T: zero mean, unit variance, independent
//   Eigen::MatrixXd back = basis.reconstruct(y);     // d x T: the part of `visual` the K components keep
//
// Spaces. With x̃ = (x − mean) ./ scale (centred, and with standardise every dimension at unit variance, so
// degrees and coefficients weigh alike):
//   y = unmixing · x̃,            unmixing = W Λ^{-1/2} Vᵀ   (K x d; acts on x̃, not on x)
//   x̃ ≈ mixing · y,              mixing   = V Λ^{1/2} Wᵀ    (d x K; the pseudo-inverse of unmixing)
// where V Λ Vᵀ are the K largest eigenpairs of the covariance of x̃ (PCA; Λ^{-1/2} Vᵀ whitens) and W is the
// K x K rotation symmetric FastICA finds on the whitened data (Hyvärinen 1999, "Fast and robust fixed-point
// algorithms for independent component analysis", IEEE TNN 10(3)): his fixed-point update with the logcosh
// contrast G(u) = log cosh u, so g = tanh, g' = 1 − tanh², for all rows at once, each step followed by the
// symmetric decorrelation W ← (W Wᵀ)^{-1/2} W.
// Variances and covariances divide by T (not T − 1): on the training data, y has mean 0 and covariance I.
// ICA leaves order and sign open; we fix them so that fits are comparable: components by decreasing
// ‖mixing column‖² (the variance each contributes to x̃), each signed so its largest-magnitude mixing entry
// is positive. Same data and seed give bit-identical matrices.
// Thread contract: a VisualBasis is an immutable value; const methods are safe from any thread.
#pragma once

#include <Eigen/Core>

namespace th::animation {

struct VisualBasisOptions {
  int components = 2;        // K
  bool standardise = true;   // scale every input dimension to unit variance before PCA (so degrees and
                             // coefficients weigh alike); constant dimensions get scale 1
  int maxIterations = 1000;  // FastICA
  double tolerance = 1e-10;  // FastICA convergence: max |1 − |diag(W_new W_oldᵀ)||
  unsigned seed = 1;         // FastICA's random start
};

class VisualBasis {
 public:
  // Empty (d = K = 0), so a model struct can hold one before it is fitted or loaded; use fit or fromParts.
  VisualBasis() = default;

  // data: d x T, one frame per column. Throws th::Error ("visual basis: ...") for fewer than K + 1 frames,
  // K < 1 or K > d, non-finite data, data that span fewer than K dimensions, and when FastICA does not
  // converge within maxIterations.
  static VisualBasis fit(const Eigen::MatrixXd& data, const VisualBasisOptions& options = {});

  // Rebuilds a basis from stored parts (a model file). Checks that the shapes agree (mean and scale d,
  // unmixing K x d, mixing d x K, 1 ≤ K ≤ d), that everything is finite, scale positive, explainedVariance in
  // [0, 1], and that unmixing · mixing is the identity to 1e-6 (the two belong together); throws th::Error.
  static VisualBasis fromParts(Eigen::VectorXd mean, Eigen::VectorXd scale, Eigen::MatrixXd unmixing,
                               Eigen::MatrixXd mixing, double explainedVariance);

  Eigen::MatrixXd transform(const Eigen::MatrixXd& x) const;  // d x T -> K x T; asserts x has d rows
  // K x T -> d x T: mean + scale .* (mixing · y); asserts y has K rows.
  Eigen::MatrixXd reconstruct(const Eigen::MatrixXd& y) const;

  int inputDimension() const { return static_cast<int>(mean_.size()); }
  int components() const { return static_cast<int>(unmixing_.rows()); }
  const Eigen::VectorXd& mean() const { return mean_; }          // d
  const Eigen::VectorXd& scale() const { return scale_; }        // d; all 1 without standardise
  const Eigen::MatrixXd& unmixing() const { return unmixing_; }  // K x d, acts on x̃ = (x − mean) ./ scale
  const Eigen::MatrixXd& mixing() const { return mixing_; }      // d x K, gives x̃
  // The fraction of the variance of x̃ (the trace of its covariance) that the K PCA components keep.
  double explainedVariance() const { return explainedVariance_; }

 private:
  Eigen::VectorXd mean_;
  Eigen::VectorXd scale_;
  Eigen::MatrixXd unmixing_;
  Eigen::MatrixXd mixing_;
  double explainedVariance_ = 0.0;
};

}  // namespace th::animation
