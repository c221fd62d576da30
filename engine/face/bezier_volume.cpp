#include "face/bezier_volume.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace th::face {
namespace {

double binomial(int n, int k) {
  double result = 1.0;
  for (int i = 1; i <= k; ++i) result = result * (n - k + i) / i;
  return result;
}

// Bernstein polynomials of degree n at t, and their derivatives.
void bernstein(int n, double t, double* value, double* derivative) {
  for (int i = 0; i <= n; ++i) {
    value[i] = binomial(n, i) * std::pow(t, i) * std::pow(1.0 - t, n - i);
    // d/dt Bᵢⁿ = n (Bᵢ₋₁ⁿ⁻¹ − Bᵢⁿ⁻¹)
    const double lower = i > 0 ? binomial(n - 1, i - 1) * std::pow(t, i - 1) * std::pow(1.0 - t, n - i) : 0.0;
    const double same = i < n ? binomial(n - 1, i) * std::pow(t, i) * std::pow(1.0 - t, n - 1 - i) : 0.0;
    derivative[i] = n * (lower - same);
  }
}

constexpr int kMaxDegree = 7;
constexpr int kMaxNewtonSteps = 50;
// How far outside [0, 1] Newton's method may wander at the lattice's outer faces on its way to a point.
constexpr double kOuterSlack = 0.25;

}  // namespace

BezierLattice BezierLattice::around(const Eigen::Vector3d& minCorner, const Eigen::Vector3d& maxCorner,
                                    const BezierLatticeOptions& options) {
  if (options.degree < 1 || options.degree > kMaxDegree)
    throw Error("Bézier lattice: degree " + std::to_string(options.degree) + " is outside 1.." +
                std::to_string(kMaxDegree));
  for (int count : options.volumes)
    if (count < 1) throw Error("Bézier lattice: every axis needs at least one volume");
  if (!((maxCorner - minCorner).array() > 0.0).all()) throw Error("Bézier lattice: the box is empty");
  BezierLattice lattice;
  lattice.volumes_ = options.volumes;
  lattice.degree_ = options.degree;
  lattice.bend_ = options.bend;
  lattice.min_ = minCorner;
  lattice.max_ = maxCorner;
  const int n = options.degree;
  const std::array<int, 3> grid{n * options.volumes[0] + 1, n * options.volumes[1] + 1, n * options.volumes[2] + 1};
  lattice.controlPoints_.resize(grid[0] * grid[1] * grid[2], 3);
  for (int k = 0; k < grid[2]; ++k)
    for (int j = 0; j < grid[1]; ++j)
      for (int i = 0; i < grid[0]; ++i) {
        const Eigen::Vector3d fraction(static_cast<double>(i) / (grid[0] - 1), static_cast<double>(j) / (grid[1] - 1),
                                       static_cast<double>(k) / (grid[2] - 1));
        const Eigen::Vector3d onGrid = minCorner + fraction.cwiseProduct(maxCorner - minCorner);
        lattice.controlPoints_.row(lattice.controlIndex(i, j, k)) = lattice.bent(onGrid).transpose();
      }
  return lattice;
}

BezierLattice BezierLattice::enclosing(const Eigen::Matrix3Xd& points, double margin,
                                       const BezierLatticeOptions& options) {
  if (points.cols() == 0) throw Error("Bézier lattice: no points to enclose");
  const Eigen::Vector3d low = points.rowwise().minCoeff();
  const Eigen::Vector3d high = points.rowwise().maxCoeff();
  // The bend is measured from the box's middle in x, which the bend does not change; so unbend every point
  // about it and take the box of those.
  const double middle = 0.5 * (low.x() + high.x());
  double front = -std::numeric_limits<double>::infinity(), back = std::numeric_limits<double>::infinity();
  for (Eigen::Index p = 0; p < points.cols(); ++p) {
    const double x = points(0, p) - middle;
    const double z = points(2, p) + options.bend * x * x;
    front = std::max(front, z);
    back = std::min(back, z);
  }
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(margin);
  return around(Eigen::Vector3d(low.x(), low.y(), back) - pad, Eigen::Vector3d(high.x(), high.y(), front) + pad,
                options);
}

int BezierLattice::controlIndex(int i, int j, int k) const {
  const int gridX = degree_ * volumes_[0] + 1;
  const int gridY = degree_ * volumes_[1] + 1;
  return i + gridX * (j + gridY * k);
}

bool BezierLattice::onBoundary(int index) const {
  const int gridX = degree_ * volumes_[0] + 1, gridY = degree_ * volumes_[1] + 1, gridZ = degree_ * volumes_[2] + 1;
  const int i = index % gridX, j = (index / gridX) % gridY, k = index / (gridX * gridY);
  return i == 0 || j == 0 || k == 0 || i == gridX - 1 || j == gridY - 1 || k == gridZ - 1;
}

std::vector<int> BezierLattice::controlPointsOf(int volume) const {
  const int a = volume % volumes_[0];
  const int b = (volume / volumes_[0]) % volumes_[1];
  const int c = volume / (volumes_[0] * volumes_[1]);
  std::vector<int> indices;
  for (int k = 0; k <= degree_; ++k)
    for (int j = 0; j <= degree_; ++j)
      for (int i = 0; i <= degree_; ++i)
        indices.push_back(controlIndex(degree_ * a + i, degree_ * b + j, degree_ * c + k));
  return indices;
}

Eigen::Vector3d BezierLattice::bent(const Eigen::Vector3d& p) const {
  const double x = p.x() - 0.5 * (min_.x() + max_.x());
  return {p.x(), p.y(), p.z() - bend_ * x * x};
}

Eigen::Vector3d BezierLattice::unbent(const Eigen::Vector3d& p) const {
  const double x = p.x() - 0.5 * (min_.x() + max_.x());
  return {p.x(), p.y(), p.z() + bend_ * x * x};
}

std::pair<std::array<int, 3>, Eigen::Vector3d> BezierLattice::affineGuess(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d scaled = (unbent(p) - min_).cwiseQuotient(max_ - min_);
  std::array<int, 3> index{};
  Eigen::Vector3d local;
  for (int d = 0; d < 3; ++d) {
    const double s = scaled[d] * volumes_[static_cast<std::size_t>(d)];
    index[static_cast<std::size_t>(d)] =
        std::clamp(static_cast<int>(std::floor(s)), 0, volumes_[static_cast<std::size_t>(d)] - 1);
    local[d] = s - index[static_cast<std::size_t>(d)];
  }
  return {index, local};
}

Eigen::Vector3d BezierLattice::evaluate(int volume, const Eigen::Vector3d& parameters,
                                        const Eigen::MatrixX3d& controlPoints) const {
  double bu[kMaxDegree + 1], bv[kMaxDegree + 1], bw[kMaxDegree + 1], unused[kMaxDegree + 1];
  bernstein(degree_, parameters.x(), bu, unused);
  bernstein(degree_, parameters.y(), bv, unused);
  bernstein(degree_, parameters.z(), bw, unused);
  const std::vector<int> indices = controlPointsOf(volume);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t next = 0;
  for (int k = 0; k <= degree_; ++k)
    for (int j = 0; j <= degree_; ++j)
      for (int i = 0; i <= degree_; ++i) sum += bu[i] * bv[j] * bw[k] * controlPoints.row(indices[next++]).transpose();
  return sum;
}

Embedding BezierLattice::embed(const Eigen::Matrix3Xd& points) const {
  Embedding embedding;
  std::vector<Eigen::Triplet<double>> entries;
  const int n = degree_;
  const double scale = (max_ - min_).norm();
  std::vector<Eigen::Vector3d> parameters;
  for (Eigen::Index p = 0; p < points.cols(); ++p) {
    const Eigen::Vector3d target = points.col(p);
    const Eigen::Vector3d relative = (unbent(target) - min_).cwiseQuotient(max_ - min_);
    if ((relative.array() < 0.0).any() || (relative.array() > 1.0).any()) continue;  // outside the lattice
    auto [index, u] = affineGuess(target);
    bool converged = false;
    for (int step = 0; step < kMaxNewtonSteps && !converged; ++step) {
      double bu[3][kMaxDegree + 1], du[3][kMaxDegree + 1];
      for (int d = 0; d < 3; ++d) bernstein(n, u[d], bu[d], du[d]);
      const int volume = index[0] + volumes_[0] * (index[1] + volumes_[1] * index[2]);
      const std::vector<int> indices = controlPointsOf(volume);
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();
      std::size_t next = 0;
      for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
          for (int i = 0; i <= n; ++i) {
            const Eigen::Vector3d point = controlPoints_.row(indices[next++]).transpose();
            x += bu[0][i] * bu[1][j] * bu[2][k] * point;
            jacobian.col(0) += du[0][i] * bu[1][j] * bu[2][k] * point;
            jacobian.col(1) += bu[0][i] * du[1][j] * bu[2][k] * point;
            jacobian.col(2) += bu[0][i] * bu[1][j] * du[2][k] * point;
          }
      const Eigen::Vector3d error = x - target;
      if (error.norm() < 1e-12 * scale) {
        converged = true;
        break;
      }
      u -= jacobian.partialPivLu().solve(error);
      // Moved out of this volume: continue in the neighbour (its coordinates are shifted by one).
      for (int d = 0; d < 3; ++d) {
        auto& i = index[static_cast<std::size_t>(d)];
        const int count = volumes_[static_cast<std::size_t>(d)];
        if (u[d] < 0.0 && i > 0) {
          --i;
          u[d] += 1.0;
        } else if (u[d] > 1.0 && i < count - 1) {
          ++i;
          u[d] -= 1.0;
        }
        u[d] = std::clamp(u[d], -kOuterSlack, 1.0 + kOuterSlack);
      }
    }
    const int volume = index[0] + volumes_[0] * (index[1] + volumes_[1] * index[2]);
    // Beyond the lattice's outer faces (the unbent box is only a first guess of them) the polynomials would
    // extrapolate, and a field there would grow instead of fading: such points are outside.
    if (converged && ((u.array() < -1e-9).any() || (u.array() > 1.0 + 1e-9).any())) continue;
    const double residual = (evaluate(volume, u) - target).norm();
    if (!converged && residual > 1e-9 * scale)
      throw Error("Bézier lattice: Newton's method did not find point " + std::to_string(p) + " (residual " +
                  std::to_string(residual) + "); is the lattice folded?");
    embedding.largestResidual = std::max(embedding.largestResidual, residual);
    const int row = static_cast<int>(embedding.points.size());
    embedding.points.push_back(static_cast<int>(p));
    embedding.volume.push_back(volume);
    parameters.push_back(u);
    double bu[3][kMaxDegree + 1], unused[kMaxDegree + 1];
    for (int d = 0; d < 3; ++d) bernstein(n, u[d], bu[d], unused);
    const std::vector<int> indices = controlPointsOf(volume);
    std::size_t next = 0;
    for (int k = 0; k <= n; ++k)
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) entries.emplace_back(row, indices[next++], bu[0][i] * bu[1][j] * bu[2][k]);
  }
  embedding.parameters.resize(3, static_cast<Eigen::Index>(parameters.size()));
  for (std::size_t i = 0; i < parameters.size(); ++i)
    embedding.parameters.col(static_cast<Eigen::Index>(i)) = parameters[i];
  embedding.basis.resize(static_cast<Eigen::Index>(embedding.points.size()), numControlPoints());
  embedding.basis.setFromTriplets(entries.begin(), entries.end());
  return embedding;
}

}  // namespace th::face
