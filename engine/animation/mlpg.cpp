#include "animation/mlpg.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <string>

#include "core/error.h"

namespace th::animation {
namespace {

// One term of Δx_t = Σ weight · x_frame. Every frame's window has exactly two taps (the centre weight is 0);
// `deltas` and the normal equations both read them from here, so the generator inverts exactly what `deltas`
// computes.
struct DeltaTap {
  Eigen::Index frame;
  double weight;
};

// Needs numFrames ≥ 2 (with one frame every delta is 0 and there are no taps).
std::array<DeltaTap, 2> deltaTaps(Eigen::Index t, Eigen::Index numFrames) {
  if (t == 0) return {{{0, -1.0}, {1, 1.0}}};
  if (t == numFrames - 1) return {{{t - 1, -1.0}, {t, 1.0}}};
  return {{{t - 1, -0.5}, {t + 1, 0.5}}};
}

// ΔΔx_t = x_{t+1} − 2x_t + x_{t−1}; the edges take their neighbour's window. Needs numFrames ≥ 3.
std::array<DeltaTap, 3> accelerationTaps(Eigen::Index t, Eigen::Index numFrames) {
  const Eigen::Index centre = std::clamp<Eigen::Index>(t, 1, numFrames - 2);
  return {{{centre - 1, 1.0}, {centre, -2.0}, {centre + 1, 1.0}}};
}

// Adds the normal-equation terms of one linear window (Σ_k c_k x_k ~ N(mean, precision⁻¹)).
template <std::size_t N>
void addWindow(std::vector<Eigen::Triplet<double>>& triplets, Eigen::VectorXd& rhs, Eigen::Index d,
               const std::array<DeltaTap, N>& taps, const Eigen::MatrixXd& precision, const Eigen::VectorXd& mean);

std::string framePrefix(std::size_t frame) {
  return "MLPG: frame " + std::to_string(frame) + " has ";
}

void checkVector(const Eigen::VectorXd& vector, Eigen::Index dimension, std::size_t frame, const char* what) {
  if (vector.size() != dimension) {
    throw Error(framePrefix(frame) + "a " + what + " of size " + std::to_string(vector.size()) + ", expected " +
                std::to_string(dimension));
  }
  if (!vector.allFinite()) throw Error(framePrefix(frame) + "a non-finite " + what);
}

void checkMatrix(const Eigen::MatrixXd& matrix, Eigen::Index dimension, std::size_t frame, const char* what) {
  if (matrix.rows() != dimension || matrix.cols() != dimension) {
    throw Error(framePrefix(frame) + "a " + what + " of " + std::to_string(matrix.rows()) + " x " +
                std::to_string(matrix.cols()) + ", expected " + std::to_string(dimension) + " x " +
                std::to_string(dimension));
  }
  if (!matrix.allFinite()) throw Error(framePrefix(frame) + "a non-finite " + what);
}

// Adds `block` at block position (rowBlock, colBlock) of the dT x dT system, lower triangle only: the solver
// below reads nothing else, and this halves the triplets.
void addLowerBlock(std::vector<Eigen::Triplet<double>>& triplets, Eigen::Index rowBlock, Eigen::Index colBlock,
                   const Eigen::MatrixXd& block) {
  const Eigen::Index d = block.rows();
  for (Eigen::Index j = 0; j < d; ++j) {
    const Eigen::Index col = colBlock * d + j;
    for (Eigen::Index i = 0; i < d; ++i) {
      const Eigen::Index row = rowBlock * d + i;
      if (row >= col) triplets.emplace_back(static_cast<int>(row), static_cast<int>(col), block(i, j));
    }
  }
}

template <std::size_t N>
void addWindow(std::vector<Eigen::Triplet<double>>& triplets, Eigen::VectorXd& rhs, Eigen::Index d,
               const std::array<DeltaTap, N>& taps, const Eigen::MatrixXd& precision, const Eigen::VectorXd& mean) {
  const Eigen::MatrixXd symmetric = 0.5 * (precision + precision.transpose());
  const Eigen::VectorXd weightedMean = symmetric * mean;
  for (const DeltaTap& row : taps) {
    rhs.segment(row.frame * d, d) += row.weight * weightedMean;
    for (const DeltaTap& col : taps) {
      if (row.frame < col.frame) continue;  // upper triangle
      addLowerBlock(triplets, row.frame, col.frame, row.weight * col.weight * symmetric);
    }
  }
}

}  // namespace

Eigen::MatrixXd deltas(const Eigen::MatrixXd& x) {
  const Eigen::Index numFrames = x.cols();
  if (numFrames == 0) throw Error("MLPG: deltas of a sequence with no frames");
  Eigen::MatrixXd result = Eigen::MatrixXd::Zero(x.rows(), numFrames);
  if (numFrames == 1) return result;
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    for (const DeltaTap& tap : deltaTaps(t, numFrames)) result.col(t) += tap.weight * x.col(tap.frame);
  }
  return result;
}

Eigen::MatrixXd accelerations(const Eigen::MatrixXd& x) {
  const Eigen::Index numFrames = x.cols();
  Eigen::MatrixXd result = Eigen::MatrixXd::Zero(x.rows(), numFrames);
  if (numFrames < 3) return result;
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    for (const DeltaTap& tap : accelerationTaps(t, numFrames)) result.col(t) += tap.weight * x.col(tap.frame);
  }
  return result;
}

Eigen::MatrixXd generateTrajectory(const std::vector<MlpgFrame>& frames) {
  if (frames.empty()) throw Error("MLPG: no frames to generate a trajectory from");
  const Eigen::Index d = frames.front().staticMean.size();
  if (d == 0) throw Error("MLPG: frame 0 has an empty static mean");
  for (std::size_t t = 0; t < frames.size(); ++t) {
    const MlpgFrame& frame = frames[t];
    checkVector(frame.staticMean, d, t, "static mean");
    checkMatrix(frame.staticPrecision, d, t, "static precision");
    checkVector(frame.deltaMean, d, t, "delta mean");
    checkMatrix(frame.deltaPrecision, d, t, "delta precision");
    if (frame.accelerationMean.size() > 0 || frame.accelerationPrecision.size() > 0) {
      checkVector(frame.accelerationMean, d, t, "acceleration mean");
      checkMatrix(frame.accelerationPrecision, d, t, "acceleration precision");
    }
  }
  const auto numFrames = static_cast<Eigen::Index>(frames.size());
  const Eigen::Index size = d * numFrames;
  // Each block row couples at most 5 frames (t−2 … t+2), so the lower triangle has fewer than 5·d·size
  // entries; Eigen's default sparse index is int.
  if (static_cast<double>(size) * 5.0 * static_cast<double>(d) > std::numeric_limits<int>::max()) {
    throw Error("MLPG: " + std::to_string(numFrames) + " frames of dimension " + std::to_string(d) +
                " are too many for one solve; generate in windows");
  }

  // Normal equations of Tokuda et al. (2000) for a given state sequence, (Wᵀ U⁻¹ W) x = Wᵀ U⁻¹ μ, summed
  // frame by frame: frame t adds Pˢ_t to block (t, t) and Pˢ_t μˢ_t to block t; its delta
  // Δx_t = Σ_k c_{t,k} x_k adds c_{t,k} c_{t,l} Pᵈ_t to block (k, l) and c_{t,k} Pᵈ_t μᵈ_t to block k.
  // Only the symmetric part of a precision enters the objective, so that is what is used.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(5 * d * d * numFrames));
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(size);
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const MlpgFrame& frame = frames[static_cast<std::size_t>(t)];
    const Eigen::MatrixXd staticPrecision = 0.5 * (frame.staticPrecision + frame.staticPrecision.transpose());
    addLowerBlock(triplets, t, t, staticPrecision);
    rhs.segment(t * d, d) += staticPrecision * frame.staticMean;
    if (numFrames == 1) continue;  // Δx_0 ≡ 0: the delta term is a constant
    addWindow(triplets, rhs, d, deltaTaps(t, numFrames), frame.deltaPrecision, frame.deltaMean);
    if (numFrames >= 3 && frame.accelerationPrecision.size() > 0) {
      addWindow(triplets, rhs, d, accelerationTaps(t, numFrames), frame.accelerationPrecision, frame.accelerationMean);
    }
  }
  Eigen::SparseMatrix<double> system(size, size);
  system.setFromTriplets(triplets.begin(), triplets.end());  // sums the entries that frames share

  // Natural ordering: the matrix is banded (half-bandwidth < 3d) and the LDLᵀ factor of a banded matrix stays
  // inside the band, so factorisation and solve cost O(T d³); a fill-reducing ordering cannot do better.
  using Solver = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>>;
  const Solver solver(system);
  // LDLᵀ succeeds on indefinite matrices too (it only fails on an exact zero pivot), but then the solution is
  // a saddle point, not the most likely trajectory: demand positive pivots.
  if (solver.info() != Eigen::Success || !(solver.vectorD().array() > 0.0).all()) {
    throw Error("MLPG: the normal equations are not positive definite (are the precisions positive definite?)");
  }
  Eigen::VectorXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) throw Error("MLPG: solving the normal equations failed");
  // x stacks x_0, …, x_{T−1}, so its column-major d x T view has x_t in column t.
  return Eigen::Map<const Eigen::MatrixXd>(x.data(), d, numFrames);
}

}  // namespace th::animation
