#include "face/feature_points.h"

#include <algorithm>
#include <limits>

#include "core/data_path.h"
#include "core/error.h"
#include "core/json_reading.h"

namespace th::face {
namespace {

// MPEG-4 feature point ← iBUG 68-point landmark(s). Pairs average two landmarks (an eyelid's middle lies
// between the two iBUG points on it).
struct LandmarkPoint {
  const char* id;
  std::vector<int> landmarks;
};

const std::vector<LandmarkPoint>& ibugFeaturePoints() {
  static const std::vector<LandmarkPoint> table{
      {"2.1", {8}},                          // bottom of the chin
      {"2.2", {62}},     {"2.3", {66}},      // inner lip, upper and lower middle
      {"2.4", {64}},     {"2.5", {60}},      // inner lip corners, left and right
      {"2.6", {63}},     {"2.7", {61}},      // inner upper lip, left and right of the middle
      {"2.8", {65}},     {"2.9", {67}},      // inner lower lip, likewise
      {"2.13", {12}},    {"2.14", {4}},      // jaw line towards the angles of the jaw
      {"3.1", {43, 44}}, {"3.2", {37, 38}},  // upper eyelid middles, left and right
      {"3.3", {46, 47}}, {"3.4", {40, 41}},  // lower eyelid middles
      {"3.7", {45}},     {"3.8", {36}},      // outer eye corners
      {"3.11", {42}},    {"3.12", {39}},     // inner eye corners
      {"4.1", {22}},     {"4.2", {21}},      // inner eyebrow ends
      {"4.3", {24}},     {"4.4", {19}},      // eyebrow middles
      {"4.5", {26}},     {"4.6", {17}},      // outer eyebrow ends
      {"8.1", {51}},     {"8.2", {57}},      // outer lip, upper and lower middle
      {"8.3", {54}},     {"8.4", {48}},      // outer lip corners
      {"8.5", {52}},     {"8.6", {50}},      // outer upper lip, left and right of the middle
      {"8.7", {56}},     {"8.8", {58}},      // outer lower lip, likewise
      {"9.1", {35}},     {"9.2", {31}},      // nostrils, left and right
      {"9.3", {30}},                         // nose tip
      {"9.15", {33}},                        // bottom of the nose, above the upper lip
  };
  return table;
}

std::vector<int> landmarkVertices(const std::filesystem::path& path, int numVertices) {
  const Json json = readJsonFile(path, "landmark map");
  if (!json.is_object() || !json.contains("idx_to_landmark_verts") || !json["idx_to_landmark_verts"].is_array() ||
      json["idx_to_landmark_verts"].size() != 68) {
    throw fileError(path, "idx_to_landmark_verts must be a list of 68 vertex indices");
  }
  std::vector<int> vertices;
  for (const Json& v : json["idx_to_landmark_verts"]) {
    if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() >= numVertices)
      throw fileError(path, "idx_to_landmark_verts holds an index that is not a vertex of the mesh");
    vertices.push_back(v.get<int>());
  }
  return vertices;
}

}  // namespace

void FeaturePointMap::set(std::string id, std::vector<int> vertices) {
  points_[std::move(id)] = std::move(vertices);
}

bool FeaturePointMap::has(std::string_view id) const {
  return points_.find(id) != points_.end();
}

const std::vector<int>& FeaturePointMap::vertices(std::string_view id) const {
  const auto found = points_.find(id);
  if (found == points_.end()) throw Error("feature point " + std::string(id) + " is not on this mesh");
  return found->second;
}

Eigen::Vector3d FeaturePointMap::position(const Eigen::Matrix3Xd& positions, std::string_view id) const {
  const std::vector<int>& members = vertices(id);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int v : members) sum += positions.col(v);
  return sum / static_cast<double>(members.size());
}

std::vector<std::string> FeaturePointMap::ids() const {
  std::vector<std::string> result;
  for (const auto& [id, members] : points_) result.push_back(id);
  return result;
}

FapUnits measureFapUnits(const FeaturePointMap& points, const Eigen::Matrix3Xd& neutral) {
  auto at = [&](std::string_view id) { return points.position(neutral, id); };
  FapUnits units;
  units.es = (at("3.5").x() - at("3.6").x()) / 1024.0;
  units.irisd = 0.5 * ((at("3.1").y() - at("3.3").y()) + (at("3.2").y() - at("3.4").y())) / 1024.0;
  units.ens = (at("3.5").y() - at("9.15").y()) / 1024.0;
  units.mns = (at("9.15").y() - at("2.2").y()) / 1024.0;
  units.mw = (at("8.3").x() - at("8.4").x()) / 1024.0;
  for (double unit : {units.es, units.irisd, units.ens, units.mns, units.mw})
    if (!(unit > 0.0)) throw Error("FAP units: a neutral-face distance is not positive (mesh facing the wrong way?)");
  return units;
}

std::filesystem::path ictFaceDirectory() {
  const std::filesystem::path copied = std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "assets" / "ict-facekit";
  std::error_code error;
  if (std::filesystem::is_regular_file(copied / "generic_neutral_mesh.obj", error)) return copied;
  return sharedDataPath("face/ict-facekit");
}

FaceAssets loadIctFace(const std::filesystem::path& directory) {
  FaceAssets face;
  face.neutral = loadObjMesh(directory / "generic_neutral_mesh.obj");
  face.jawOpen = loadObjPositions(directory / "jawOpen.obj", face.neutral.numVertices());
  face.landmarks = landmarkVertices(directory / "vertex_indices.json", face.neutral.numVertices());
  for (const LandmarkPoint& point : ibugFeaturePoints()) {
    std::vector<int> vertices;
    for (int landmark : point.landmarks) vertices.push_back(face.landmarks[static_cast<std::size_t>(landmark)]);
    face.points.set(point.id, std::move(vertices));
  }
  // Pupils: the front of each eye. ICT's iris material is a whole sphere over the eyeball (the iris is in its
  // texture), so the pupil is the mean of that sphere's front-most vertices (its apex on the eye's axis).
  for (const auto& [id, material] : {std::pair{"3.5", "M_IrisLeft"}, std::pair{"3.6", "M_IrisRight"}}) {
    const std::vector<int> iris = face.neutral.verticesOf(material);
    if (iris.empty())
      throw fileError(directory / "generic_neutral_mesh.obj", std::string("no ") + material + " material");
    double front = -std::numeric_limits<double>::infinity(), back = std::numeric_limits<double>::infinity();
    for (int v : iris)
      front = std::max(front, face.neutral.positions(2, v)), back = std::min(back, face.neutral.positions(2, v));
    std::vector<int> apex;
    for (int v : iris)
      if (face.neutral.positions(2, v) >= front - 0.05 * (front - back)) apex.push_back(v);
    face.points.set(id, std::move(apex));
  }
  return face;
}

}  // namespace th::face
