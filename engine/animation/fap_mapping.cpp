#include "animation/fap_mapping.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "core/error.h"
#include "core/json_reading.h"
#include "face/fap.h"
#include "face/jaw.h"

namespace th::animation {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// The lip FAPs a jaw opening drives: inner (4–13) and outer (51–60) lip contours.
constexpr std::array<int, 20> kLipFaps{4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60};

Eigen::Vector3d directionOf(const face::FapDefinition& fap) {
  return {fap.direction[0], fap.direction[1], fap.direction[2]};
}

Eigen::Vector3d threeVectorFrom(const Json& json, const std::filesystem::path& file, const char* field) {
  if (!json.contains(field) || !json[field].is_array() || json[field].size() != 3)
    throw fileError(file, std::string("fap_map.") + field + " must be a list of 3 numbers");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    const Json& x = json[field][static_cast<std::size_t>(k)];
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      throw fileError(file, std::string("fap_map.") + field + " must be a list of 3 finite numbers");
    v[k] = x.get<double>();
  }
  return v;
}

}  // namespace

MouthFapMap defineMouthFapMap(const face::FaceAssets& face) {
  const Eigen::Matrix3Xd& neutral = face.neutral.positions;
  const face::FapUnits units = face::measureFapUnits(face.points, neutral);
  const std::vector<int> lowerTeeth = face::movedVertices(neutral, face.jawOpen, face.neutral.verticesOf("M_Teeth"));
  const face::JawHinge hinge = face::fitJawHinge(neutral, face.jawOpen, lowerTeeth);

  MouthFapMap map;
  map.hingeAxis = hinge.axis;
  const Eigen::VectorXd follow = face::jawFollowWeights(neutral, face.jawOpen, hinge);
  const auto followOf = [&](std::string_view point) {
    double sum = 0.0;
    for (int v : face.points.vertices(point)) sum += follow[v];
    return sum / static_cast<double>(face.points.vertices(point).size());
  };
  map.chinFromPivot = (face.points.position(neutral, "2.1") - hinge.pivot) / units.mns;
  map.chinFollow = followOf("2.1");
  map.shapeAngleDegrees = hinge.shapeAngle / kDegree;
  map.lipPerRadian.resize(kLipFaps.size());
  for (std::size_t i = 0; i < kLipFaps.size(); ++i) {
    const face::FapDefinition& fap = face::fapDefinition(kLipFaps[i]);
    const Eigen::Vector3d rest = face.points.position(neutral, fap.featurePoint);
    const Eigen::Vector3d moved = face.points.position(face.jawOpen, fap.featurePoint);
    const Eigen::Vector3d carried = followOf(fap.featurePoint) * (hinge.rotate(rest, hinge.shapeAngle) - rest);
    const double value = (moved - rest - carried).dot(directionOf(fap)) / units.of(fap.unit);
    map.lipFaps.push_back(fap.number);
    map.lipPerRadian[static_cast<Eigen::Index>(i)] = value / hinge.shapeAngle;
  }
  return map;
}

std::vector<int> mouthFapNumbers(const MouthFapMap& map) {
  std::vector<int> numbers{3};
  numbers.insert(numbers.end(), map.lipFaps.begin(), map.lipFaps.end());
  return numbers;
}

Eigen::MatrixXd mouthFaps(const MouthFapMap& map, const Eigen::RowVectorXd& jawDegrees) {
  const auto numLip = static_cast<Eigen::Index>(map.lipFaps.size());
  Eigen::MatrixXd faps(1 + numLip, jawDegrees.size());
  for (Eigen::Index t = 0; t < jawDegrees.size(); ++t) {
    const double angle = std::max(0.0, jawDegrees[t]) * kDegree;
    const Eigen::Vector3d chin = Eigen::AngleAxisd(angle, map.hingeAxis) * map.chinFromPivot;
    faps(0, t) = map.chinFollow * (map.chinFromPivot.y() - chin.y());  // downward, already in MNS
    faps.col(t).tail(numLip) = map.lipPerRadian * angle;
  }
  return faps;
}

Eigen::MatrixXd headFaps(const Eigen::MatrixXd& rotationsDegrees) {
  return rotationsDegrees * (kDegree / face::kAngleUnit);
}

nlohmann::json mouthFapMapJson(const MouthFapMap& map) {
  nlohmann::json lip = nlohmann::json::object();
  for (std::size_t i = 0; i < map.lipFaps.size(); ++i)
    lip[std::to_string(map.lipFaps[i])] = map.lipPerRadian[static_cast<Eigen::Index>(i)];
  return {{"hinge_axis", {map.hingeAxis.x(), map.hingeAxis.y(), map.hingeAxis.z()}},
          {"chin_from_pivot_mns", {map.chinFromPivot.x(), map.chinFromPivot.y(), map.chinFromPivot.z()}},
          {"chin_follow", map.chinFollow},
          {"shape_angle_deg", map.shapeAngleDegrees},
          {"lip_faps_per_radian", lip}};
}

MouthFapMap mouthFapMapFromJson(const Json& json, const std::filesystem::path& file) {
  if (!json.is_object()) throw fileError(file, "fap_map must be an object");
  MouthFapMap map;
  map.hingeAxis = threeVectorFrom(json, file, "hinge_axis");
  if (std::abs(map.hingeAxis.norm() - 1.0) > 1e-6) throw fileError(file, "fap_map.hinge_axis must be a unit vector");
  map.chinFromPivot = threeVectorFrom(json, file, "chin_from_pivot_mns");
  for (const char* field : {"chin_follow", "shape_angle_deg"})
    if (!json.contains(field) || !json[field].is_number() || !std::isfinite(json[field].get<double>()))
      throw fileError(file, std::string("fap_map.") + field + " must be a finite number");
  map.chinFollow = json["chin_follow"].get<double>();
  if (map.chinFollow <= 0.0 || map.chinFollow > 1.0) throw fileError(file, "fap_map.chin_follow must be in (0, 1]");
  map.shapeAngleDegrees = json["shape_angle_deg"].get<double>();
  if (!json.contains("lip_faps_per_radian") || !json["lip_faps_per_radian"].is_object())
    throw fileError(file, "fap_map.lip_faps_per_radian must be an object of FAP number → value");
  std::vector<std::pair<int, double>> lip;
  for (const auto& [key, value] : json["lip_faps_per_radian"].items()) {
    int number = 0;
    try {
      std::size_t used = 0;
      number = std::stoi(key, &used);
      if (used != key.size()) number = 0;
    } catch (const std::exception&) {
      number = 0;
    }
    if (number < 3 || number > face::kNumFaps || number == 3 || (number >= 48 && number <= 50))
      throw fileError(file, "fap_map.lip_faps_per_radian has \"" + key + "\", which is not a lip FAP number");
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      throw fileError(file, "fap_map.lip_faps_per_radian[" + key + "] must be a finite number");
    lip.emplace_back(number, value.get<double>());
  }
  std::sort(lip.begin(), lip.end());
  map.lipPerRadian.resize(static_cast<Eigen::Index>(lip.size()));
  for (std::size_t i = 0; i < lip.size(); ++i) {
    map.lipFaps.push_back(lip[i].first);
    map.lipPerRadian[static_cast<Eigen::Index>(i)] = lip[i].second;
  }
  return map;
}

}  // namespace th::animation
