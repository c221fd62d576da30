#include "face/poses.h"

#include <numbers>

namespace th::face {
namespace {

double degrees(double d) {
  return d * std::numbers::pi / 180.0 / kAngleUnit;
}

Pose pose(std::string name, std::string title, std::initializer_list<std::pair<int, double>> values) {
  Pose result{std::move(name), std::move(title), {}};
  for (const auto& [fap, value] : values) result.faps[static_cast<std::size_t>(fap)] = value;
  return result;
}

}  // namespace

std::vector<Pose> keyPoses() {
  return {
      pose("neutral", "neutral", {}),
      pose("jaw_open", "jaw open (FAP 3 = 600)", {{3, 600}}),
      // Corners up and out, inner and outer contour, and a little cheek lift.
      pose("smile", "smile (lip corners, cheeks)",
           {{6, 120}, {7, 120}, {53, 120}, {54, 120}, {12, 220}, {13, 220}, {59, 220}, {60, 220}, {41, 80}, {42, 80}}),
      pose("blink", "blink (FAPs 19, 20 = 1024)", {{19, 1024}, {20, 1024}}),
      pose("yaw_20", "head yaw 20 deg (FAP 49)", {{49, degrees(20)}}),
      pose("brows_up", "brows raised (FAPs 31-36)", {{31, 250}, {32, 250}, {33, 300}, {34, 300}, {35, 250}, {36, 250}}),
      pose("pucker", "pucker (corners in, lips out)",
           {{6, -110}, {7, -110}, {53, -110}, {54, -110}, {16, 300}, {17, 300}}),
      pose("look_left", "eyes left (FAPs 23, 24)", {{23, degrees(20)}, {24, degrees(20)}}),
      pose("ah_nod", "'ah' with a nod (FAPs 3, 48)", {{3, 400}, {4, -60}, {5, -80}, {48, degrees(10)}}),
  };
}

std::vector<Pose> goldenPoses() {
  std::vector<Pose> poses = keyPoses();
  poses.resize(5);
  return poses;
}

}  // namespace th::face
