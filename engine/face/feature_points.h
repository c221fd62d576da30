// MPEG-4 feature points on a mesh, and the face's FAP units measured from them.
//
//   th::face::FaceAssets ict = th::face::loadIctFace(th::face::ictFaceDirectory());
//   Eigen::Vector3d chin = ict.points.position(ict.neutral.positions, "2.1");
//   th::face::FapUnits fapu = th::face::measureFapUnits(ict.points, ict.neutral.positions);
//
// A feature point is one vertex, or the mean of a few (a pupil is the apex of its eye's iris sphere). The ICT FaceKit
// map is made from the 68 iBUG landmarks its authors marked on the mesh (vertex_indices.json, idx_to_landmark_verts)
// and from its iris materials; the table is in feature_points.cpp with the landmark behind each point. The face's left
// (+x) is the iBUG right-hand side of the image. FAPUs (ISO/IEC 14496-2 C.2, each the neutral distance / 1024):
//   ES0 = 3.5.x − 3.6.x  (pupils),  IRISD0 = 3.1.y − 3.3.y (= 3.2.y − 3.4.y; we average both eyes),
//   ENS0 = 3.5.y − 9.15.y,  MNS0 = 9.15.y − 2.2.y,  MW0 = 8.3.x − 8.4.x.
// Thread contract: values.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "face/fap.h"
#include "face/mesh.h"

namespace th::face {

class FeaturePointMap {
 public:
  void set(std::string id, std::vector<int> vertices);
  bool has(std::string_view id) const;
  const std::vector<int>& vertices(std::string_view id) const;  // throws th::Error if absent
  Eigen::Vector3d position(const Eigen::Matrix3Xd& positions, std::string_view id) const;
  std::vector<std::string> ids() const;

 private:
  std::map<std::string, std::vector<int>, std::less<>> points_;
};

// Throws th::Error if a point a FAPU needs is missing or a FAPU comes out non-positive.
FapUnits measureFapUnits(const FeaturePointMap& points, const Eigen::Matrix3Xd& neutral);

// The ICT FaceKit head: neutral mesh, its feature points and the jawOpen blend shape.
struct FaceAssets {
  Mesh neutral;
  FeaturePointMap points;
  std::vector<int> landmarks;  // the 68 iBUG landmarks' vertices, in iBUG order (0-based)
  Eigen::Matrix3Xd jawOpen;    // 3 x V, the ARKit jawOpen shape at weight 1
};

// assets/ict-facekit in the source tree when the set-up script has copied it there, else the shared data's
// face/ict-facekit.
std::filesystem::path ictFaceDirectory();

// Reads generic_neutral_mesh.obj, jawOpen.obj and vertex_indices.json from `directory`; errors name the file.
FaceAssets loadIctFace(const std::filesystem::path& directory);

}  // namespace th::face
