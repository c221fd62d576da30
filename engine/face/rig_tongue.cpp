#include "face/rig_tongue.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include "core/error.h"

namespace th::face::rig {
namespace {

// Neighbours of each vertex over the triangles drawn with one material.
std::vector<std::vector<int>> neighboursIn(const Mesh& mesh, std::string_view material) {
  const int wanted = mesh.materialIndex(material);
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(mesh.numVertices()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (mesh.triangleMaterial[t] != wanted) continue;
    const auto& tri = mesh.triangles[t];
    for (std::size_t i = 0; i < 3; ++i) {
      const int a = tri[i], b = tri[(i + 1) % 3];
      neighbours[static_cast<std::size_t>(a)].push_back(b);
      neighbours[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  return neighbours;
}

// The tongue, told apart from the gums it shares M_GumsTongue with: what the jaw carries above the fold, grown
// from the top of the tongue.
struct TongueBody {
  std::vector<int> vertices;
  double level = 0.0;  // the height above which it is told apart from the floor of the mouth
  double back = 0.0;   // z where it leaves the part of the mouth the jaw carries (its root)
  int tip = -1, top = -1, leftBorder = -1, rightBorder = -1;  // 6.1, 6.2, 6.3, 6.4
};

TongueBody findTongue(const Mesh& mesh, const Eigen::VectorXd& jawFollow, double mw, double mns) {
  const Eigen::Matrix3Xd& rest = mesh.positions;
  const std::vector<int> mouth = mesh.verticesOf("M_GumsTongue");
  if (mouth.empty()) throw Error("face model: the mesh has no M_GumsTongue material");
  const std::vector<std::vector<int>> neighbours = neighboursIn(mesh, "M_GumsTongue");
  const auto carried = [&](int v) { return jawFollow[v] > 0.5; };
  const double midline = 0.02 * mw;  // 1 mm: the mesh is mirrored, its mid-line vertices have x = 0
  TongueBody tongue;
  // The top of the tongue: the highest mid-line vertex that the jaw carries (above it are only the palate and
  // the upper gums, which stay with the skull).
  for (int v : mouth)
    if (carried(v) && std::abs(rest(0, v)) < midline && (tongue.top < 0 || rest(1, v) > rest(1, tongue.top)))
      tongue.top = v;
  if (tongue.top < 0) throw Error("face model: no part of M_GumsTongue moves with the jaw");
  // The lower gums' front: the front-most vertex the jaw carries (in front of the tongue's tip, between the
  // lower lip and the roots of the lower incisors). The tongue's sides rest against the lower teeth, so nearness
  // to the teeth does not tell tongue from gum; being connected to this point above the fold does.
  int gumFront = -1;
  for (int v : mouth)
    if (carried(v) && (gumFront < 0 || rest(2, v) > rest(2, gumFront))) gumFront = v;
  // Grow from the top over carried vertices no lower than a level; lower the level step by step as long as
  // the region does not reach the gums. It stops where the tongue's underside folds into the floor of the
  // mouth, through which the gums would be reached.
  const auto grow = [&](double level, bool& touchesGums) {
    std::vector<char> in(static_cast<std::size_t>(rest.cols()), 0);
    std::vector<int> region{tongue.top}, stack{tongue.top};
    in[static_cast<std::size_t>(tongue.top)] = 1;
    touchesGums = false;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (int n : neighbours[static_cast<std::size_t>(v)]) {
        if (in[static_cast<std::size_t>(n)] || !carried(n) || rest(1, n) < level) continue;
        in[static_cast<std::size_t>(n)] = 1;
        if (n == gumFront) touchesGums = true;
        region.push_back(n);
        stack.push_back(n);
      }
    }
    return region;
  };
  const double step = 0.01 * mns;
  for (double level = rest(1, tongue.top) - step; level > rest(1, tongue.top) - mns; level -= step) {
    bool touchesGums = false;
    std::vector<int> region = grow(level, touchesGums);
    if (touchesGums) break;
    tongue.vertices = std::move(region);
    tongue.level = level;
  }
  if (tongue.vertices.size() < 20) throw Error("face model: the tongue cannot be told apart from the gums");
  // Its root: the front-most of its vertices that border on mouth the jaw does not carry (the throat).
  tongue.back = std::numeric_limits<double>::infinity();
  for (int v : tongue.vertices) tongue.back = std::min(tongue.back, rest(2, v));
  for (int v : tongue.vertices)
    for (int n : neighbours[static_cast<std::size_t>(v)])
      if (!carried(n)) tongue.back = std::max(tongue.back, rest(2, v));
  for (int v : tongue.vertices) {
    if (std::abs(rest(0, v)) < midline && (tongue.tip < 0 || rest(2, v) > rest(2, tongue.tip))) tongue.tip = v;
    if (tongue.leftBorder < 0 || rest(0, v) > rest(0, tongue.leftBorder)) tongue.leftBorder = v;
    if (tongue.rightBorder < 0 || rest(0, v) < rest(0, tongue.rightBorder)) tongue.rightBorder = v;
  }
  return tongue;
}

// The tip's FAPs (43–45) move the front third whole and fade out over the middle; raise_tongue (46) lifts the
// body and tip, fading out over the back 40 %. `length`: from the root to the tip; `fold`: the fade above the
// fold.
void addTongueFields(const NeutralFace& neutral, const FeaturePointMap& points, const TongueBody& tongue, double length,
                     double fold, LinearFields& fields) {
  const Eigen::Matrix3Xd& rest = neutral.rest;
  const double tipZ = rest(2, tongue.tip);
  std::vector<std::pair<int, double>> tip, body;
  for (int v : tongue.vertices) {
    const double lift = smoothstep(tongue.level, tongue.level + fold, rest(1, v));
    const double z = rest(2, v);
    const double wTip = lift * smoothstep(tipZ - 0.7 * length, tipZ - 0.3 * length, z);
    const double wBody = lift * smoothstep(tongue.back, tongue.back + 0.4 * length, z);
    if (wTip > 1e-6) tip.emplace_back(v, wTip);
    if (wBody > 1e-6) body.emplace_back(v, wBody);
  }
  for (int fap : {43, 44, 45}) addDirectField(neutral, points, fap, tip, fields);
  addDirectField(neutral, points, 46, body, fields);
}

// tongue_roll (47): the sides curl up into a U, each vertex turning about the mid-line's axis (along z, at the
// height of the tongue's top) by its share of the angle: 0 on the mid-line, growing to 1 at the borders (6.3,
// 6.4), times the body's fade. The border points turn by exactly the angle.
TongueRoll rollOf(const NeutralFace& neutral, const TongueBody& tongue, double length, double fold) {
  const Eigen::Matrix3Xd& rest = neutral.rest;
  TongueRoll roll;
  roll.axisY = rest(1, tongue.top);
  const double halfWidth = 0.5 * (rest(0, tongue.leftBorder) - rest(0, tongue.rightBorder));
  const auto bodyShare = [&](int v) {
    return smoothstep(tongue.level, tongue.level + fold, rest(1, v)) *
           smoothstep(tongue.back, tongue.back + 0.4 * length, rest(2, v));
  };
  const double atBorders = std::min(bodyShare(tongue.leftBorder), bodyShare(tongue.rightBorder));
  if (!(atBorders > 0.2)) throw Error("face model: the tongue's borders lie too near its root to roll");
  for (int v : tongue.vertices) {
    const double x = rest(0, v);
    const double share = std::min(1.0, smoothstep(0.0, halfWidth, std::abs(x)) * bodyShare(v) / atBorders);
    if (share > 1e-6) roll.shares.emplace_back(v, static_cast<float>(x > 0.0 ? share : -share));
  }
  return roll;
}

}  // namespace

// ICT draws gums and tongue as one material, one connected surface (the tongue's underside folds into the floor
// of the mouth, which runs into the lower gums), so `findTongue` tells it apart by geometry: what the jaw carries
// above the fold, grown from the top of the tongue. Its fields are direct per-vertex ones (the mouth is far
// inside the skin's lattice, which holds only skin), applied before the jaw turns, so the tongue rides on the
// jaw. Each fades to 0 down to the fold (`level`) and back to the root, where the tongue meets the throat, which
// stays.
TongueRoll rigTongue(const NeutralFace& neutral, FeaturePointMap& points, const Eigen::VectorXd& jawFollow,
                     LinearFields& fields) {
  const TongueBody tongue = findTongue(neutral.mesh, jawFollow, neutral.mw, neutral.mns);
  points.set("6.1", {tongue.tip});
  points.set("6.2", {tongue.top});
  points.set("6.3", {tongue.leftBorder});
  points.set("6.4", {tongue.rightBorder});
  const double length = neutral.rest(2, tongue.tip) - tongue.back;
  if (!(length > 0.0)) throw Error("face model: the tongue's tip is not in front of its root");
  const double fold = 0.15 * neutral.mns;  // the fade above the fold, 3 mm
  addTongueFields(neutral, points, tongue, length, fold, fields);
  return rollOf(neutral, tongue, length, fold);
}

}  // namespace th::face::rig
