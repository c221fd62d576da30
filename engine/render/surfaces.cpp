#include "render/surfaces.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>

namespace th::render {
namespace {

bool contains(std::string_view text, std::string_view part) {
  return text.find(part) != std::string_view::npos;
}

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// A pseudo-random value in 0..1 per point of the plane.
double hash(double x, double y) {
  const auto fract = [](double a) { return a - std::floor(a); };
  const double h = std::sin(x * 127.1 + y * 311.7) * 43758.5453;
  return fract(h);
}

// Value noise, 0..1, smooth between the integer lattice's random values.
double valueNoise(double x, double y) {
  const double ix = std::floor(x);
  const double iy = std::floor(y);
  double fx = x - ix;
  double fy = y - iy;
  fx = fx * fx * (3.0 - 2.0 * fx);
  fy = fy * fy * (3.0 - 2.0 * fy);
  const double bottom = hash(ix, iy) + (hash(ix + 1.0, iy) - hash(ix, iy)) * fx;
  const double top = hash(ix, iy + 1.0) + (hash(ix + 1.0, iy + 1.0) - hash(ix, iy + 1.0)) * fx;
  return bottom + (top - bottom) * fy;
}

// Where blood shows through, 0..0.5 (the face's tile, mirrored about its midline u = 0.5): the cheeks below the
// eyes and the nose's tip.
double flush(double u, double v) {
  const double cheekX = (std::abs(u - 0.5) - 0.155) / 0.06;
  const double cheekY = (v - 0.6) / 0.045;
  const double noseX = (u - 0.5) / 0.025;
  const double noseY = (v - 0.612) / 0.025;
  return 0.5 * std::exp(-(cheekX * cheekX + cheekY * cheekY)) + 0.3 * std::exp(-(noseX * noseX + noseY * noseY));
}

double hairCover(double u, double v) {
  if (u < 1.0) {
    double hairline = 0.95 - 0.12 * smoothstep(0.22, 0.42, std::abs(u - 0.5));
    hairline += 0.004 * std::sin(u * 160.0) * std::sin(u * 37.0);  // not a ruled line
    return smoothstep(hairline - 0.01, hairline + 0.01, v);
  }
  const double s = std::abs(u - 1.5);
  const double nape = 0.4 + 1.8 * s * s;
  const double scalp = smoothstep(nape - 0.02, nape + 0.02, v) * (1.0 - smoothstep(0.33, 0.36, s));
  return scalp * (1.0 - smoothstep(0.215, 0.23, s) * smoothstep(0.78, 0.8, v));
}

std::vector<int> verticesWith(const SurfaceMap& map, Surface surface) {
  std::vector<int> out;
  for (std::size_t v = 0; v < map.ofVertex.size(); ++v)
    if (map.ofVertex[v] == surface) out.push_back(static_cast<int>(v));
  return out;
}

}  // namespace

Surface surfaceOf(std::string_view name) {
  if (contains(name, "Sclera")) return Surface::kSclera;
  if (contains(name, "Iris")) return Surface::kIris;
  if (contains(name, "Teeth")) return Surface::kTeeth;
  if (contains(name, "Gums") || contains(name, "Tongue")) return Surface::kGums;
  if (contains(name, "Lash")) return Surface::kLashes;
  if (contains(name, "Lacrimal") || contains(name, "EyeOcclusion") || contains(name, "EyeBlend"))
    return Surface::kEyeLayer;
  if (contains(name, "Face") || contains(name, "Head") || contains(name, "Skin")) return Surface::kSkin;
  return Surface::kOther;
}

SurfaceMap classifySurfaces(const face::Mesh& mesh) {
  SurfaceMap map;
  for (const face::Material& m : mesh.materials) map.ofMaterial.push_back(surfaceOf(m.name));
  map.ofTriangle.resize(mesh.triangles.size(), Surface::kOther);
  map.ofVertex.resize(static_cast<std::size_t>(mesh.numVertices()), Surface::kOther);
  std::vector<bool> seen(map.ofVertex.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int m = mesh.triangleMaterial[t];
    if (m >= 0 && static_cast<std::size_t>(m) < map.ofMaterial.size())
      map.ofTriangle[t] = map.ofMaterial[static_cast<std::size_t>(m)];
    for (int v : mesh.triangles[t])
      if (!seen[static_cast<std::size_t>(v)]) {
        seen[static_cast<std::size_t>(v)] = true;
        map.ofVertex[static_cast<std::size_t>(v)] = map.ofTriangle[t];
      }
  }
  return map;
}

void EyeRig::track(const Eigen::Matrix3Xd& positions) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int v : all) mean += positions.col(v);
  mean /= static_cast<double>(all.size());
  Eigen::Vector3d frontMean = Eigen::Vector3d::Zero();
  for (int v : front) frontMean += positions.col(v);
  frontMean /= static_cast<double>(front.size());
  const Eigen::Vector3d spine = frontMean - mean;
  if (!(spine.squaredNorm() > 0.0)) return;  // collapsed (or not finite): keep the last frame's
  centre = (mean + centreAlongAxis * spine).cast<float>();
  axis = spine.normalized().cast<float>();
}

std::vector<EyeRig> findEyes(const face::Mesh& mesh, const SurfaceMap& map) {
  std::vector<EyeRig> eyes;
  for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
    if (map.ofMaterial[m] != Surface::kIris) continue;
    EyeRig eye;
    eye.all = mesh.verticesOf(mesh.materials[m].name);
    if (eye.all.size() < 8) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int v : eye.all) mean += mesh.positions.col(v);
    mean /= static_cast<double>(eye.all.size());
    // Least-squares sphere: |p|^2 = 2 p.c + k.
    Eigen::MatrixXd a(static_cast<Eigen::Index>(eye.all.size()), 4);
    Eigen::VectorXd b(a.rows());
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const Eigen::Vector3d p = mesh.positions.col(eye.all[static_cast<std::size_t>(i)]);
      a.row(i) << 2.0 * p.transpose(), 1.0;
      b[i] = p.squaredNorm();
    }
    const Eigen::Vector3d centre = a.colPivHouseholderQr().solve(b).head<3>();
    Eigen::Vector3d axis = mean - centre;
    if (!(axis.norm() > 1e-9)) continue;
    axis.normalize();
    const double cos15 = std::cos(15.0 * std::numbers::pi / 180.0);
    for (int v : eye.all)
      if ((mesh.positions.col(v) - centre).normalized().dot(axis) > cos15) eye.front.push_back(v);
    if (eye.front.empty()) continue;
    Eigen::Vector3d front = Eigen::Vector3d::Zero();
    for (int v : eye.front) front += mesh.positions.col(v);
    front /= static_cast<double>(eye.front.size());
    const Eigen::Vector3d spine = front - mean;
    if (!(spine.squaredNorm() > 0.0)) continue;
    eye.centreAlongAxis = (centre - mean).dot(spine) / spine.squaredNorm();
    eye.track(mesh.positions);
    eyes.push_back(std::move(eye));
  }
  return eyes;
}

Eigen::VectorXf lashOpacity(const face::Mesh& mesh, const SurfaceMap& map) {
  Eigen::VectorXf opacity = Eigen::VectorXf::Ones(mesh.numVertices());
  const std::vector<int> lashes = verticesWith(map, Surface::kLashes);
  const std::vector<int> skin = verticesWith(map, Surface::kSkin);
  if (lashes.empty() || skin.empty()) return opacity;

  // Distance to the nearest skin vertex: 0 at a lash's root, largest at its tip. Only skin near the lashes'
  // bounding box can hold a root.
  Eigen::Vector3d low = mesh.positions.col(lashes[0]);
  Eigen::Vector3d high = low;
  for (int v : lashes) {
    low = low.cwiseMin(mesh.positions.col(v));
    high = high.cwiseMax(mesh.positions.col(v));
  }
  const double margin = 1.0;
  std::vector<int> near;
  for (int v : skin)
    if ((mesh.positions.col(v).array() >= low.array() - margin).all() &&
        (mesh.positions.col(v).array() <= high.array() + margin).all())
      near.push_back(v);
  std::vector<double> distance(lashes.size(), margin);
  for (std::size_t i = 0; i < lashes.size(); ++i)
    for (int v : near)
      distance[i] = std::min(distance[i], (mesh.positions.col(v) - mesh.positions.col(lashes[i])).norm());

  // Cards are connected pieces of lash triangles; a card whose middle is below the eyes' height is a lower
  // lash.
  std::vector<int> parent(static_cast<std::size_t>(mesh.numVertices()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (map.ofTriangle[t] != Surface::kLashes) continue;
    const auto& tri = mesh.triangles[t];
    parent[static_cast<std::size_t>(root(tri[1]))] = root(tri[0]);
    parent[static_cast<std::size_t>(root(tri[2]))] = root(tri[0]);
  }
  std::map<int, std::pair<double, int>> cardHeight;  // root -> (sum of y, count)
  for (int v : lashes) {
    auto& [sum, count] = cardHeight[root(v)];
    sum += mesh.positions(1, v);
    ++count;
  }
  double eyeHeight = 0.5 * (low.y() + high.y());
  const std::vector<int> iris = verticesWith(map, Surface::kIris);
  if (!iris.empty()) {
    eyeHeight = 0.0;
    for (int v : iris) eyeHeight += mesh.positions(1, v);
    eyeHeight /= static_cast<double>(iris.size());
  }
  // Per card: the longest distance from the skin, so every lash fades over its own length.
  std::map<int, double> cardLength;
  for (std::size_t i = 0; i < lashes.size(); ++i) {
    double& length = cardLength[root(lashes[i])];
    length = std::max(length, distance[i]);
  }
  for (std::size_t i = 0; i < lashes.size(); ++i) {
    const int card = root(lashes[i]);
    const auto& [sum, count] = cardHeight[card];
    const bool lower = sum / count < eyeHeight;
    const double length = cardLength[card];
    const double along = length > 0.0 ? distance[i] / length : 0.0;
    opacity[lashes[i]] = static_cast<float>((lower ? 0.3 : 0.9) * (1.0 - smoothstep(0.1, 1.0, along)));
  }
  return opacity;
}

Eigen::VectorXf lipWeight(const face::Mesh& mesh, const SurfaceMap& map, const Eigen::VectorXf& openness) {
  Eigen::VectorXf weight = Eigen::VectorXf::Zero(mesh.numVertices());
  const std::vector<int> teeth = verticesWith(map, Surface::kTeeth);
  if (teeth.empty() || openness.size() != mesh.numVertices()) return weight;
  Eigen::Vector3d low = mesh.positions.col(teeth[0]);
  Eigen::Vector3d high = low;
  for (int v : teeth) {
    low = low.cwiseMin(mesh.positions.col(v));
    high = high.cwiseMax(mesh.positions.col(v));
  }
  const double centreX = 0.5 * (low.x() + high.x());
  const double teethWidth = high.x() - low.x();

  // The slit: skin in front of the teeth, within the teeth's span, folded in so far that it sees little sky.
  std::vector<int> slit;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (map.ofVertex[static_cast<std::size_t>(v)] != Surface::kSkin) continue;
    const Eigen::Vector3d p = mesh.positions.col(v);
    if (p.z() < high.z() - 0.3 || std::abs(p.x() - centreX) > 0.5 * teethWidth || p.y() < low.y() || p.y() > high.y())
      continue;
    if (openness[v] < 0.3f) slit.push_back(v);
  }
  if (slit.size() < 4) return weight;
  // The slit's height across the mouth, in bins of x (its frontmost vertices: the lips' meeting line).
  const double bin = 0.25;
  std::map<int, std::pair<double, double>> line;  // bin -> (z of the frontmost, its y)
  double halfWidth = 0.0;
  for (int v : slit) {
    const Eigen::Vector3d p = mesh.positions.col(v);
    const int b = static_cast<int>(std::floor((p.x() - centreX) / bin));
    auto it = line.find(b);
    if (it == line.end() || p.z() > it->second.first) line[b] = {p.z(), p.y()};
    halfWidth = std::max(halfWidth, std::abs(p.x() - centreX));
  }
  // Between bin centres the line is interpolated linearly, so the lips' edges do not step.
  std::vector<std::pair<double, double>> knots;  // (x, y)
  for (const auto& [b, zy] : line) knots.emplace_back(centreX + (b + 0.5) * bin, zy.second);
  const auto slitY = [&](double x) {
    if (x <= knots.front().first) return knots.front().second;
    if (x >= knots.back().first) return knots.back().second;
    const auto it = std::lower_bound(knots.begin(), knots.end(), std::pair{x, -1e300});
    const auto& [x1, y1] = *it;
    const auto& [x0, y0] = *std::prev(it);
    return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
  };
  // Lips' heights from the mouth's width (an adult's upper red lip is about a fifth of the mouth's width, the
  // lower a little taller), tapering to nothing at the corners.
  const double upper = 0.19 * 2.0 * halfWidth;
  const double lower = 0.22 * 2.0 * halfWidth;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (map.ofVertex[static_cast<std::size_t>(v)] != Surface::kSkin) continue;
    const Eigen::Vector3d p = mesh.positions.col(v);
    const double across = std::abs(p.x() - centreX) / halfWidth;
    if (across >= 1.0 || p.z() < high.z() - 1.5) continue;
    const double taper = std::pow(1.0 - across * across, 0.6);
    const double dy = p.y() - slitY(p.x());
    const double height = (dy > 0.0 ? upper : lower) * taper;
    if (height <= 0.0) continue;
    weight[v] = static_cast<float>(1.0 - smoothstep(0.6 * height, 1.1 * height, std::abs(dy)));
  }
  // Soften the edge over the mesh's neighbourhoods: a vertex-sized step would show as a jagged border.
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::VectorXf sum = weight;
    Eigen::VectorXf count = Eigen::VectorXf::Ones(weight.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (map.ofTriangle[t] != Surface::kSkin) continue;
      for (int a : mesh.triangles[t])
        for (int b : mesh.triangles[t])
          if (a != b) {
            sum[a] += weight[b];
            count[a] += 1.0f;
          }
    }
    weight = sum.cwiseQuotient(count);
  }
  return weight;
}

SkinMarkings skinMarkings(const face::Mesh& mesh, const SurfaceMap& map) {
  SkinMarkings m;
  m.redness = Eigen::VectorXf::Zero(mesh.numVertices());
  m.hair = Eigen::VectorXf::Zero(mesh.numVertices());
  m.grain = Eigen::VectorXf::Zero(mesh.numVertices());
  if (mesh.uv.cols() != mesh.numVertices()) return m;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (map.ofVertex[static_cast<std::size_t>(v)] != Surface::kSkin) continue;
    const double u = mesh.uv(0, v);
    const double w = mesh.uv(1, v);
    // Blood and pigment vary apart at the centimetre scale: blotches of red.
    const double blotch = valueNoise(u * 30.0, w * 30.0) - 0.5;
    m.redness[v] = static_cast<float>(flush(u, w) + 0.25 * blotch);
    m.hair[v] = static_cast<float>(hairCover(u, w));
    m.grain[v] = static_cast<float>(hash(u * 173.0, w * 173.0));
  }
  return m;
}

void darkenMouthInterior(const face::Mesh& mesh, const SurfaceMap& map, Eigen::VectorXf& openness) {
  double front = -1e300;
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (map.ofVertex[static_cast<std::size_t>(v)] == Surface::kTeeth) front = std::max(front, mesh.positions(2, v));
  if (front == -1e300) return;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const Surface s = map.ofVertex[static_cast<std::size_t>(v)];
    if (s != Surface::kTeeth && s != Surface::kGums) continue;
    const double depth = front - mesh.positions(2, v);
    // The tongue and gums lie deeper in the mouth's shade than the teeth's front edges.
    const double shade = s == Surface::kGums ? 0.75 : 1.0;
    openness[v] *= static_cast<float>(shade * (1.0 - 0.85 * smoothstep(0.3, 3.5, depth)));
  }
}

}  // namespace th::render
