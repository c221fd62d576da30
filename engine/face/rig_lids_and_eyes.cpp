#include "face/rig_lids_and_eyes.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string_view>
#include <tuple>

#include "core/error.h"

namespace th::face::rig {
namespace {

// Least-squares sphere through points (algebraic fit: |p|² = 2c·p + (r² − |c|²) is linear in c and r² − |c|²).
std::pair<Eigen::Vector3d, double> fitSphere(const Eigen::Matrix3Xd& positions, const std::vector<int>& vertices) {
  Eigen::MatrixXd a(static_cast<Eigen::Index>(vertices.size()), 4);
  Eigen::VectorXd b(static_cast<Eigen::Index>(vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3d p = positions.col(vertices[i]);
    a.row(static_cast<Eigen::Index>(i)) << 2 * p.x(), 2 * p.y(), 2 * p.z(), 1.0;
    b[static_cast<Eigen::Index>(i)] = p.squaredNorm();
  }
  const Eigen::Vector4d solution = a.colPivHouseholderQr().solve(b);
  const Eigen::Vector3d centre = solution.head<3>();
  return {centre, std::sqrt(solution[3] + centre.squaredNorm())};
}

// The skin and lashes around an eye that its lids carry, each with its share of the lid's angle.
void findLids(const NeutralFace& neutral, const FeaturePointMap& points, bool left, EyeRig& eye) {
  const Eigen::Matrix3Xd& rest = neutral.rest;
  const double irisd = neutral.irisd;
  const auto at = [&](std::string_view id) { return neutral.at(points, id); };
  const Eigen::Vector3d outer = at(left ? "3.7" : "3.8"), inner = at(left ? "3.11" : "3.12");
  const Eigen::Vector3d upper = at(left ? "3.1" : "3.2"), lower = at(left ? "3.3" : "3.4");
  const double middleX = 0.5 * (outer.x() + inner.x()), halfWidth = 0.5 * std::abs(outer.x() - inner.x());
  const double cornerY = 0.5 * (outer.y() + inner.y());
  std::vector<int> lidVertices = neutral.skin;
  const std::vector<int> lashes = neutral.mesh.verticesOf("M_EyeLashes");
  lidVertices.insert(lidVertices.end(), lashes.begin(), lashes.end());
  for (int v : lidVertices) {
    const Eigen::Vector3d p = rest.col(v);
    if ((p.x() > 0) != left) continue;
    const double across = std::abs(p.x() - middleX) / halfWidth;
    const double horizontal = 1.0 - smoothstep(0.85, 1.35, across);
    if (horizontal <= 0.0) continue;
    // Each lid's margin, a parabola through the corners and the lid's middle.
    const double shape = 1.0 - std::min(1.0, across * across);
    if (p.y() >= cornerY) {
      const double margin = cornerY + (upper.y() - cornerY) * shape;
      const double w = horizontal * (1.0 - smoothstep(margin + 0.3 * irisd, margin + 1.2 * irisd, p.y()));
      if (w > 1e-3) eye.upperLid.emplace_back(v, static_cast<float>(w));
    } else {
      const double margin = cornerY + (lower.y() - cornerY) * shape;
      const double w = horizontal * (1.0 - smoothstep(margin - 0.3 * irisd, margin - 1.0 * irisd, p.y()));
      if (w > 1e-3) eye.lowerLid.emplace_back(v, static_cast<float>(w));
    }
  }
}

}  // namespace

// Eyes: a sphere fitted to each sclera; the ball (sclera and iris) turns rigidly about its centre, and the
// lids turn about the same centre.
std::array<EyeRig, 2> rigEyes(const NeutralFace& neutral, const FeaturePointMap& points) {
  std::array<EyeRig, 2> eyes;
  for (int e = 0; e < 2; ++e) {
    const bool left = e == 0;
    EyeRig& eye = eyes[static_cast<std::size_t>(e)];
    const std::vector<int> sclera = neutral.mesh.verticesOf(left ? "M_ScleraLeft" : "M_ScleraRight");
    const std::vector<int> iris = neutral.mesh.verticesOf(left ? "M_IrisLeft" : "M_IrisRight");
    if (sclera.size() < 10 || iris.empty()) throw Error("face model: the mesh's eyes need sclera and iris materials");
    std::tie(eye.centre, eye.radius) = fitSphere(neutral.rest, sclera);
    eye.ball = sclera;
    eye.ball.insert(eye.ball.end(), iris.begin(), iris.end());
    findLids(neutral, points, left, eye);
  }
  return eyes;
}

double pupilRadius(const NeutralFace& neutral) {
  return 0.25 * neutral.irisd;
}

}  // namespace th::face::rig
