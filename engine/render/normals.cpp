#include "render/normals.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"

namespace th::render {

std::vector<int> findCoincidentVertices(const face::Mesh& mesh, double tolerance) {
  const int n = mesh.numVertices();
  std::vector<int> material(static_cast<std::size_t>(n), -2);  // -2: on no triangle
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int v : mesh.triangles[t])
      if (material[static_cast<std::size_t>(v)] == -2) material[static_cast<std::size_t>(v)] = mesh.triangleMaterial[t];
  // Sort by x, then compare each vertex with the following ones while x stays within the tolerance: fast for
  // meshes, where few vertices share an x.
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return mesh.positions(0, a) < mesh.positions(0, b) || (mesh.positions(0, a) == mesh.positions(0, b) && a < b);
  });
  std::vector<int> weldTo(static_cast<std::size_t>(n));
  std::iota(weldTo.begin(), weldTo.end(), 0);
  const double tolerance2 = tolerance * tolerance;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const int a = order[i];
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      const int b = order[j];
      if (mesh.positions(0, b) - mesh.positions(0, a) > tolerance) break;
      if (material[static_cast<std::size_t>(a)] != material[static_cast<std::size_t>(b)] ||
          material[static_cast<std::size_t>(a)] == -2)
        continue;
      if ((mesh.positions.col(a) - mesh.positions.col(b)).squaredNorm() > tolerance2) continue;
      // Union towards the lowest index; chains resolve because targets are found by following weldTo.
      int ra = a;
      while (weldTo[static_cast<std::size_t>(ra)] != ra) ra = weldTo[static_cast<std::size_t>(ra)];
      int rb = b;
      while (weldTo[static_cast<std::size_t>(rb)] != rb) rb = weldTo[static_cast<std::size_t>(rb)];
      if (ra != rb) weldTo[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    }
  }
  for (int v = 0; v < n; ++v) {  // flatten, so every vertex points straight at its group's representative
    int r = v;
    while (weldTo[static_cast<std::size_t>(r)] != r) r = weldTo[static_cast<std::size_t>(r)];
    weldTo[static_cast<std::size_t>(v)] = r;
  }
  return weldTo;
}

VertexNormals::VertexNormals(const face::Mesh& mesh, double tolerance)
    : VertexNormals(mesh.numVertices(), mesh.triangles, findCoincidentVertices(mesh, tolerance)) {}

VertexNormals::VertexNormals(int numVertices, std::vector<std::array<int, 3>> triangles, std::vector<int> weldTo)
    : numVertices_(numVertices), triangles_(std::move(triangles)) {
  for (const auto& t : triangles_)
    for (int v : t)
      if (v < 0 || v >= numVertices_) throw Error("VertexNormals: a triangle refers to a vertex that does not exist");
  if (weldTo.empty()) return;
  if (static_cast<int>(weldTo.size()) != numVertices_)
    throw Error("VertexNormals: weldTo must have one entry per vertex");
  for (int v = 0; v < numVertices_; ++v) {
    const int target = weldTo[static_cast<std::size_t>(v)];
    if (target < 0 || target >= numVertices_ || weldTo[static_cast<std::size_t>(target)] != target)
      throw Error("VertexNormals: weldTo must point at vertices that map to themselves");
    if (target != v) welded_.push_back({v, target});
  }
}

void VertexNormals::compute(const Eigen::Matrix3Xd& positions, Eigen::Matrix3Xf& normals) const {
  if (positions.cols() != numVertices_)
    throw Error("VertexNormals: " + std::to_string(positions.cols()) + " positions for a mesh of " +
                std::to_string(numVertices_) + " vertices");
  if (normals.cols() != numVertices_) normals.resize(3, numVertices_);
  normals.setZero();
  for (const auto& t : triangles_) {
    const Eigen::Vector3d a = positions.col(t[0]);
    const Eigen::Vector3d b = positions.col(t[1]);
    const Eigen::Vector3d c = positions.col(t[2]);
    // |cross| is twice the area: summing unnormalised cross products weights each face by its area.
    const Eigen::Vector3f n = (b - a).cross(c - a).cast<float>();
    normals.col(t[0]) += n;
    normals.col(t[1]) += n;
    normals.col(t[2]) += n;
  }
  for (const auto& [v, target] : welded_) normals.col(target) += normals.col(v);
  for (const auto& [v, target] : welded_) normals.col(v) = normals.col(target);
  for (Eigen::Index v = 0; v < normals.cols(); ++v) {
    const float length = normals.col(v).norm();
    if (length > 0.0f && std::isfinite(length))
      normals.col(v) /= length;
    else
      normals.col(v) = Eigen::Vector3f::UnitZ();
  }
}

}  // namespace th::render
