// What the parts of the face's rig (FaceModel::build) share: the neutral face they are all measured on (its
// mesh, skin and FAP units), the linear FAP fields they fill, and the direct per-vertex fields that the ears and
// the tongue use where the skin's lattice cannot reach or is too coarse.
//
//   const th::face::rig::NeutralFace neutral = th::face::rig::neutralFace(mesh, units);
//   th::face::rig::LinearFields fields;
//   th::face::rig::addDirectField(neutral, points, 65, weights, fields);
//
// Every field is normalised so that the feature point its FAP names moves by exactly value × FAPU in the
// standard's direction (face_model.h tells how each FAP moves the mesh).
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <string_view>
#include <utility>
#include <vector>

#include "face/face_model.h"
#include "face/fap.h"
#include "face/feature_points.h"
#include "face/mesh.h"

namespace th::face::rig {

// The neutral face the rig is built from. `mesh` is the model's own copy, which must outlive this.
struct NeutralFace {
  const Mesh& mesh;
  const Eigen::Matrix3Xd& rest;  // mesh.positions
  FapUnits units;
  // The FAPUs' neutral distances (× 1024), mesh units: mouth width, mouth-nose and eye separation, iris diameter.
  double mw = 0.0, mns = 0.0, es = 0.0, irisd = 0.0;
  std::vector<int> face;  // M_Face
  // All the skin: the face and the rest of the head (which meets it at the temples, forehead and neck),
  // ascending.
  std::vector<int> skin;

  Eigen::Vector3d at(const FeaturePointMap& points, std::string_view id) const { return points.position(rest, id); }
};

// Throws th::Error if the mesh has no M_Face material (the skin).
NeutralFace neutralFace(const Mesh& mesh, const FapUnits& units);

// The linear FAPs' displacement fields per unit value (FaceModel::linearField) and how far each reaches
// (FaceModel::reach), indexed by FAP number.
struct LinearFields {
  std::array<std::vector<FaceModel::FieldEntry>, kNumFaps + 1> entries;
  std::array<double, kNumFaps + 1> reach{};
};

// A field given straight per vertex (not through the lattice): a weight per vertex times the FAP's direction,
// normalised so the feature point moves by exactly value × FAPU. Its reach is as far from the feature point as
// a moved vertex lies. Throws th::Error if the weights do not carry the feature point (a mean weight ≤ 0.5).
void addDirectField(const NeutralFace& neutral, const FeaturePointMap& points, int number,
                    const std::vector<std::pair<int, double>>& weights, LinearFields& fields);

inline double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

inline Eigen::Vector3d directionOf(const FapDefinition& fap) {
  return {fap.direction[0], fap.direction[1], fap.direction[2]};
}

}  // namespace th::face::rig
