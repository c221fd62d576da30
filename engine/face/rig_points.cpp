#include "face/rig_points.h"

#include <cmath>
#include <limits>
#include <string_view>
#include <tuple>

#include "core/error.h"

namespace th::face::rig {
namespace {

// The skin vertex nearest to (x, y) seen from the front: the front-most among those close in x and y.
int frontVertexNear(const Eigen::Matrix3Xd& positions, const std::vector<int>& skin, double x, double y,
                    double tolerance) {
  int best = -1;
  double bestScore = std::numeric_limits<double>::infinity();
  for (int v : skin) {
    const double distance = std::hypot(positions(0, v) - x, positions(1, v) - y);
    if (distance > tolerance) continue;
    const double score = distance - 0.01 * positions(2, v);  // prefer the front surface among near ones
    if (score < bestScore) bestScore = score, best = v;
  }
  if (best < 0) throw Error("face model: no skin vertex near a feature point the standard needs");
  return best;
}

}  // namespace

void placeDerivedPoints(const NeutralFace& neutral, FeaturePointMap& points) {
  const Eigen::Matrix3Xd& rest = neutral.rest;
  const std::vector<int>& skin = neutral.skin;
  const double mw = neutral.mw;
  const auto at = [&](std::string_view id) { return neutral.at(points, id); };
  const Eigen::Vector3d lowerLip = at("8.2"), chin = at("2.1");
  int boss = -1;  // 2.10, the chin boss: the front-most midline point between the lower lip and the chin
  for (int v : skin)
    if (std::abs(rest(0, v)) < 0.03 * mw && rest(1, v) < lowerLip.y() && rest(1, v) > chin.y() &&
        (boss < 0 || rest(2, v) > rest(2, boss)))
      boss = v;
  if (boss < 0) throw Error("face model: no chin between the lower lip and the chin point");
  points.set("2.10", {boss});
  for (const auto& [side, eyeCorner, mouthCorner] : {std::tuple{"l", "3.7", "8.3"}, std::tuple{"r", "3.8", "8.4"}}) {
    const Eigen::Vector3d eye = at(eyeCorner), mouth = at(mouthCorner);
    const bool left = std::string_view(side) == "l";
    // 5.3/5.4: the cheekbone, below the eye's outer corner; 5.1/5.2: the cheek beside the mouth corner.
    points.set(left ? "5.3" : "5.4",
               {frontVertexNear(rest, skin, 0.9 * eye.x(), eye.y() - 0.35 * (eye.y() - mouth.y()), 0.1 * mw)});
    points.set(left ? "5.1" : "5.2",
               {frontVertexNear(rest, skin, eye.x(), mouth.y() + 0.2 * (eye.y() - mouth.y()), 0.1 * mw)});
  }
}

}  // namespace th::face::rig
