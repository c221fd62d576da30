// The second source paper's measures of a visual estimate (Terissi & Gómez): average mean squared error ε,
// normalised by the truth's variance per component, and average correlation coefficient ρ.
//
//   double epsilon = th::animation::averageMse(estimate, truth);        // K x T each
//   double rho = th::animation::averageCorrelation(estimate, truth);
//
// ε = (1/TK) Σₖ (1/σ²ₖ) Σₜ (o'ₜₖ − oₜₖ)²  (the mean prediction scores 1);
// ρ = (1/TK) Σₜ Σₖ (oₜₖ − μₖ)(o'ₜₖ − μ'ₖ) / (σₖ σ'ₖ)  (the mean over components of Pearson's r; 0 for a
// constant estimate). Means and deviations are over the T frames evaluated.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>

namespace th::animation {

double averageMse(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth);
double averageCorrelation(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth);

}  // namespace th::animation
