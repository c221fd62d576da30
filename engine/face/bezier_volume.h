// Piecewise Bézier volumes (PBVD, Tao & Huang): a lattice of connected tensor-product Bernstein volumes around
// the face, and the vertices embedded in it, so that a deformation of the lattice moves the mesh linearly.
//
//   th::face::BezierLattice lattice = th::face::BezierLattice::around(minCorner, maxCorner, {});
//   th::face::Embedding embedded = lattice.embed(mesh.positions);          // once: Newton inversion
//   Eigen::MatrixX3d moved = embedded.basis * (lattice.controlPoints() + displacement);   // V = B·P
//
// Volume (a, b, c) of an nx x ny x nz lattice of degree n uses the control points with indices
// n·a … n·a + n (and likewise in y and z) of one global grid of (n·nx + 1)(n·ny + 1)(n·nz + 1) points, so
// neighbouring volumes share their boundary points: the map is continuous (C0) across boundaries and a
// deformation cannot crack the mesh there. Within a volume, x(u, v, w) = Σ Bᵢ(u) Bⱼ(v) Bₖ(w) Pᵢⱼₖ with the
// Bernstein polynomials Bᵢ of degree n.
// The control points start on a grid that is bent backwards at the sides (z −= bend·(x − x_centre)², in the
// mesh's units), so the volumes hug a face instead of a box; the volume map is then not affine, and each vertex's
// parametric coordinates come from Newton's method on x(u, v, w) = vertex, started from the unbent grid's
// affine guess and moved to the neighbouring volume when a coordinate leaves [0, 1]. They are found once; after
// that every vertex is a fixed linear combination of (n + 1)³ control points: a row of the sparse matrix B.
// Thread contract: values; const methods are safe from any thread.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

namespace th::face {

struct BezierLatticeOptions {
  std::array<int, 3> volumes{4, 5, 2};  // volumes along x, y, z
  int degree = 3;                       // cubic
  double bend = 0.04;                   // backward bend of the sides, per squared mesh unit (see above)
};

struct Embedding {
  std::vector<int> points;                             // indices of the embedded points (columns of the input)
  std::vector<int> volume;                             // per embedded point: its volume (a + nx·(b + ny·c))
  Eigen::Matrix3Xd parameters;                         // per embedded point: (u, v, w) in [0, 1]³ within its volume
  Eigen::SparseMatrix<double, Eigen::RowMajor> basis;  // embedded points x control points: B
  double largestResidual = 0.0;                        // max |x(u, v, w) − point| after Newton, mesh units
};

class BezierLattice {
 public:
  // A lattice whose unbent grid spans [minCorner, maxCorner]. Throws th::Error for a degree < 1, a volume count
  // < 1 or an empty box.
  static BezierLattice around(const Eigen::Vector3d& minCorner, const Eigen::Vector3d& maxCorner,
                              const BezierLatticeOptions& options = {});
  // The smallest lattice (plus `margin` on every side) whose bent volumes hold all `points`.
  static BezierLattice enclosing(const Eigen::Matrix3Xd& points, double margin,
                                 const BezierLatticeOptions& options = {});

  // Every column of `points` inside the lattice gets parametric coordinates (in [0, 1]³) and a row of B;
  // points outside it are left out (they are not deformed by the lattice). Throws th::Error if Newton fails to converge
  // for a point inside (a folded lattice).
  Embedding embed(const Eigen::Matrix3Xd& points) const;

  // The position inside volume `volume` at (u, v, w) for control points `controlPoints` (numControlPoints x 3).
  Eigen::Vector3d evaluate(int volume, const Eigen::Vector3d& parameters, const Eigen::MatrixX3d& controlPoints) const;
  Eigen::Vector3d evaluate(int volume, const Eigen::Vector3d& parameters) const {
    return evaluate(volume, parameters, controlPoints_);
  }

  const Eigen::MatrixX3d& controlPoints() const { return controlPoints_; }  // numControlPoints x 3, rest pose
  int numControlPoints() const { return static_cast<int>(controlPoints_.rows()); }
  int numVolumes() const { return volumes_[0] * volumes_[1] * volumes_[2]; }
  int degree() const { return degree_; }
  const std::array<int, 3>& volumes() const { return volumes_; }
  // Global index of control point (i, j, k) of the grid.
  int controlIndex(int i, int j, int k) const;
  // Whether a control point lies on the lattice's outer surface. A field that is zero there leaves every point
  // on that surface in place, so the lattice's inside joins the undeformed outside without a crack.
  bool onBoundary(int index) const;
  // Global indices of the (n + 1)³ control points of a volume, i fastest.
  std::vector<int> controlPointsOf(int volume) const;

 private:
  std::array<int, 3> volumes_{};
  int degree_ = 3;
  double bend_ = 0.0;
  Eigen::Vector3d min_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_ = Eigen::Vector3d::Zero();
  Eigen::MatrixX3d controlPoints_;

  Eigen::Vector3d bent(const Eigen::Vector3d& p) const;
  Eigen::Vector3d unbent(const Eigen::Vector3d& p) const;
  // The volume and parameters of `p` on the unbent grid: the start of Newton's method.
  std::pair<std::array<int, 3>, Eigen::Vector3d> affineGuess(const Eigen::Vector3d& p) const;
};

}  // namespace th::face
