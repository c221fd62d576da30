// Piecewise Bézier volumes: exact embedding by Newton inversion, a linear deformation, no cracks.
#include "face/bezier_volume.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "face/feature_points.h"

namespace {

using th::face::BezierLattice;

struct FaceLattice {
  Eigen::Matrix3Xd face;  // the skin vertices of the ICT head's face area
  BezierLattice lattice;
  double size = 0.0;
};

const FaceLattice& faceLattice() {
  static const FaceLattice built = [] {
    const th::face::Mesh mesh = th::face::loadObjMesh(th::face::ictFaceDirectory() / "generic_neutral_mesh.obj");
    const std::vector<int> skin = mesh.verticesOf("M_Face");
    FaceLattice result{Eigen::Matrix3Xd(3, static_cast<Eigen::Index>(skin.size())), {}, 0.0};
    for (std::size_t i = 0; i < skin.size(); ++i)
      result.face.col(static_cast<Eigen::Index>(i)) = mesh.positions.col(skin[i]);
    const Eigen::Vector3d low = result.face.rowwise().minCoeff();
    const Eigen::Vector3d high = result.face.rowwise().maxCoeff();
    result.size = (high - low).norm();
    // The bent grid starts 6 units further back at the sides, so the box reaches further back there.
    result.lattice =
        BezierLattice::around(low - Eigen::Vector3d(0.5, 0.5, 0.5), high + Eigen::Vector3d(0.5, 0.5, 8.0), {});
    return result;
  }();
  return built;
}

TEST(BezierLattice, TheUndeformedLatticeReproducesTheFaceMesh) {
  const FaceLattice& f = faceLattice();
  const th::face::Embedding embedded = f.lattice.embed(f.face);
  EXPECT_EQ(static_cast<Eigen::Index>(embedded.points.size()), f.face.cols()) << "every face vertex is inside";
  const Eigen::MatrixX3d rebuilt = embedded.basis * f.lattice.controlPoints();
  double worst = 0.0;
  for (std::size_t i = 0; i < embedded.points.size(); ++i)
    worst = std::max(worst,
                     (rebuilt.row(static_cast<Eigen::Index>(i)).transpose() - f.face.col(embedded.points[i])).norm());
  EXPECT_LT(worst, 1e-5 * f.size);
  // Each row of B is a partition of unity over (n + 1)³ = 64 control points.
  for (Eigen::Index r = 0; r < embedded.basis.rows(); r += 97) {
    EXPECT_NEAR(embedded.basis.row(r).sum(), 1.0, 1e-12);
    EXPECT_EQ(embedded.basis.row(r).nonZeros(), 64);
  }
}

TEST(BezierLattice, BendingTheGridMakesNewtonNecessary) {
  const FaceLattice& f = faceLattice();
  const th::face::Embedding embedded = f.lattice.embed(f.face);
  // The affine guess of the unbent grid is off: the bent lattice is not an affine map. Newton finds the points.
  Eigen::Vector3d low = f.face.rowwise().minCoeff(), high = f.face.rowwise().maxCoeff();
  const BezierLattice straight =
      BezierLattice::around(low - Eigen::Vector3d(0.5, 0.5, 0.5), high + Eigen::Vector3d(0.5, 0.5, 8.0), {.bend = 0.0});
  const th::face::Embedding affine = straight.embed(f.face);
  ASSERT_EQ(affine.points.size(), embedded.points.size());
  double largestShift = 0.0;
  for (Eigen::Index i = 0; i < affine.parameters.cols(); ++i)
    if (affine.volume[static_cast<std::size_t>(i)] == embedded.volume[static_cast<std::size_t>(i)])
      largestShift = std::max(largestShift, (affine.parameters.col(i) - embedded.parameters.col(i)).norm());
  EXPECT_GT(largestShift, 0.05);
  EXPECT_LT(embedded.largestResidual, 1e-9 * f.size);
}

TEST(BezierLattice, DeformationIsLinearInTheControlPoints) {
  const FaceLattice& f = faceLattice();
  const th::face::Embedding embedded = f.lattice.embed(f.face);
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  Eigen::MatrixX3d d1(f.lattice.numControlPoints(), 3), d2(f.lattice.numControlPoints(), 3);
  for (Eigen::Index i = 0; i < d1.size(); ++i) d1.data()[i] = noise(random), d2.data()[i] = noise(random);
  const Eigen::MatrixX3d rest = f.lattice.controlPoints();
  const Eigen::MatrixX3d combined = embedded.basis * (rest + 2.0 * d1 - 0.5 * d2);
  const Eigen::MatrixX3d separate = embedded.basis * rest + 2.0 * (embedded.basis * d1) - 0.5 * (embedded.basis * d2);
  EXPECT_LT((combined - separate).cwiseAbs().maxCoeff(), 1e-9);
  // B agrees with evaluating the volumes directly at the embedded coordinates.
  for (std::size_t i = 0; i < embedded.points.size(); i += 211) {
    const Eigen::Vector3d direct =
        f.lattice.evaluate(embedded.volume[i], embedded.parameters.col(static_cast<Eigen::Index>(i)), rest + d1);
    const Eigen::Vector3d viaB = (embedded.basis.row(static_cast<Eigen::Index>(i)) * (rest + d1)).transpose();
    EXPECT_LT((direct - viaB).norm(), 1e-9);
  }
}

TEST(BezierLattice, NeighbouringVolumesAgreeOnTheirSharedFaceUnderAnyDeformation) {
  const FaceLattice& f = faceLattice();
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  Eigen::MatrixX3d moved = f.lattice.controlPoints();
  for (Eigen::Index i = 0; i < moved.size(); ++i) moved.data()[i] += noise(random);
  const auto [nx, ny, nz] = f.lattice.volumes();
  double worst = 0.0;
  for (int c = 0; c < nz; ++c)
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) {
        const int volume = a + nx * (b + ny * c);
        for (int trial = 0; trial < 20; ++trial) {
          const double s = unit(random), t = unit(random);
          if (a + 1 < nx)
            worst = std::max(worst, (f.lattice.evaluate(volume, {1.0, s, t}, moved) -
                                     f.lattice.evaluate(volume + 1, {0.0, s, t}, moved))
                                        .norm());
          if (b + 1 < ny)
            worst = std::max(worst, (f.lattice.evaluate(volume, {s, 1.0, t}, moved) -
                                     f.lattice.evaluate(volume + nx, {s, 0.0, t}, moved))
                                        .norm());
          if (c + 1 < nz)
            worst = std::max(worst, (f.lattice.evaluate(volume, {s, t, 1.0}, moved) -
                                     f.lattice.evaluate(volume + nx * ny, {s, t, 0.0}, moved))
                                        .norm());
        }
      }
  EXPECT_LT(worst, 1e-12 * f.size);
}

TEST(BezierLattice, RejectsDegenerateSetUps) {
  EXPECT_THROW(BezierLattice::around({0, 0, 0}, {1, 1, 1}, {.degree = 0}), th::Error);
  EXPECT_THROW(BezierLattice::around({0, 0, 0}, {1, 0, 1}, {}), th::Error);
  EXPECT_THROW(BezierLattice::around({0, 0, 0}, {1, 1, 1}, {.volumes = {0, 1, 1}}), th::Error);
  // A point outside the lattice is simply not embedded.
  const BezierLattice small = BezierLattice::around({0, 0, 0}, {1, 1, 1}, {.volumes = {1, 1, 1}, .bend = 0.0});
  Eigen::Matrix3Xd points(3, 2);
  points << 0.5, 5.0, 0.5, 0.5, 0.5, 0.5;
  const th::face::Embedding embedded = small.embed(points);
  EXPECT_EQ(embedded.points, std::vector<int>{0});
}

}  // namespace
