// Maximum-likelihood parameter generation (Tokuda et al., ICASSP 2000): the smooth trajectory that a sequence
// of Gaussians over [static, delta] features makes most likely. It replaces the step-wise "state mean of each
// frame" by a curve whose velocities also match the model, removing the jumps at state changes.
//
//   std::vector<th::animation::MlpgFrame> frames = ...;   // one per output frame: means and precisions
//   Eigen::MatrixXd x = th::animation::generateTrajectory(frames);   // d x T
//
// With W the (2dT x dT) matrix that maps x to [x_t; Δx_t] for every t, and U⁻¹ the block-diagonal precision,
// x = (Wᵀ U⁻¹ W)⁻¹ Wᵀ U⁻¹ μ: a banded symmetric positive-definite system (block bandwidth 2, since Δx_t ties
// x_{t−1} to x_{t+1}), solved in O(T d³).
// Deltas are the ones `deltas` computes (central differences; one-sided at the edges), so a model trained on
// deltas(x) and this generator agree. Central differences never see x_{t+1} − x_t, only x_{t+1} − x_{t−1}, so
// at a sharp change of the means the trajectory can climb in two-frame plateaus (a unit step with equal
// static and delta precisions gives one frame-to-frame step of 0.71); a larger delta precision makes the
// steps smaller, and an acceleration term (the second difference x_{t+1} − 2x_t + x_{t−1}, as speech synthesis
// adds ΔΔ) ties neighbouring frames directly, which removes the plateaus.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace th::animation {

// Δx_t = (x_{t+1} − x_{t−1}) / 2 inside; x_1 − x_0 and x_{T−1} − x_{T−2} at the edges; 0 when T = 1.
// x: d x T, one frame per column. Throws th::Error when T = 0.
Eigen::MatrixXd deltas(const Eigen::MatrixXd& x);

// x_{t+1} − 2x_t + x_{t−1} inside; at each edge its neighbour's; 0 when T < 3. x: d x T.
Eigen::MatrixXd accelerations(const Eigen::MatrixXd& x);

// The Gaussian of one output frame over [x_t; Δx_t; ΔΔx_t]; the parts independent (each full d x d). The
// acceleration part is optional: empty (size 0) leaves it out.
struct MlpgFrame {
  Eigen::VectorXd staticMean;             // d
  Eigen::MatrixXd staticPrecision;        // d x d, symmetric positive definite
  Eigen::VectorXd deltaMean;              // d
  Eigen::MatrixXd deltaPrecision;         // d x d, symmetric positive semi-definite
  Eigen::VectorXd accelerationMean;       // d, or empty
  Eigen::MatrixXd accelerationPrecision;  // d x d, or empty
};

// The most likely trajectory (d x T), d = frames[0].staticMean.size(). Throws th::Error, naming the frame, on
// empty input, inconsistent sizes or non-finite values, and when the system is not positive definite. A zero
// delta precision is fine as long as the static precisions are positive definite.
Eigen::MatrixXd generateTrajectory(const std::vector<MlpgFrame>& frames);

}  // namespace th::animation
