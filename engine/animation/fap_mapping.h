// From the models' outputs to MPEG-4 FAPs: head rotations → FAPs 48–50, and the mouth model's jaw opening →
// FAP 3 (open_jaw) through the jaw's geometry plus the lip FAPs that go with it.
//
//   th::animation::MouthFapMap map = th::animation::defineMouthFapMap(th::face::loadIctFace(dir));
//   Eigen::MatrixXd mouth = th::animation::mouthFaps(map, jawDegrees);   // rows: mouthFapNumbers(map)
//   Eigen::MatrixXd head = th::animation::headFaps(rotationsDegrees);    // rows: FAPs 48, 49, 50 (AU)
//
// Head: BEAT2's angles (R = Ry(yaw)·Rx(pitch)·Rz(roll), y up, z forward, +x the speaker's left) already turn
// the way FAPs 48–50 do (pitch down, yaw to the left, roll to the right are positive), so each is its angle in
// AU (1e-5 rad).
// Jaw: the mouth model reconstructs BEAT2's jaw opening (SMPL-X jaw axis-angle x, degrees; 0 is FLAME's closed
// mouth, so negative values clamp to 0). The jaw is a hinge measured on the reference face (face/jaw.h: a rigid
// fit to the lower teeth between ICT FaceKit's neutral mesh and its jawOpen shape). Opening by θ moves the chin
// bone under feature point 2.1 to pivot + R(θ)(chin − pivot). Every vertex follows that rotation by its share
// (face::jawFollowWeights, read from the shape: the chin's skin 0.83, the lower teeth 1). FAP 3 is the chin
// point's downward displacement in MNS, as the standard defines it, and face-independent because the geometry
// is measured in the face's own FAPU; the face turns a FAP 3 value back into θ.
// Lips: a linear map, defined from the reference face's jawOpen shape: at the shape's opening, each lip
// feature point's displacement beyond its share of the jaw's (the same weights), projected on its FAP's
// direction in its FAPU, divided by the shape's angle, gives that FAP per radian of opening.
// What this cannot show: BEAT2 fits most of the mouth's shape into FLAME expression coefficients, whose
// geometry needs FLAME's basis (not in the shared data; non-commercial licence). Their share of the visual
// components is dropped here; lip shape independent of the jaw comes from tracked lips (tracking/).
// Thread contract: pure functions of values.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "core/json_reading.h"
#include "face/feature_points.h"

namespace th::animation {

struct MouthFapMap {
  Eigen::Vector3d hingeAxis = Eigen::Vector3d::UnitX();     // face frame, unit; a positive angle opens
  Eigen::Vector3d chinFromPivot = Eigen::Vector3d::Zero();  // feature point 2.1 − pivot, in MNS units
  double chinFollow = 1.0;         // the chin point's share of the bone's motion (jawFollowWeights)
  std::vector<int> lipFaps;        // FAP numbers, ascending
  Eigen::VectorXd lipPerRadian;    // each lip FAP's value per radian of jaw opening
  double shapeAngleDegrees = 0.0;  // the jawOpen shape's opening, where the lip pattern was measured
};

MouthFapMap defineMouthFapMap(const face::FaceAssets& face);

// FAP 3 followed by the lip FAPs: the rows of mouthFaps.
std::vector<int> mouthFapNumbers(const MouthFapMap& map);

// (1 + lip FAPs) x T FAP values for a jaw opening per frame (degrees).
Eigen::MatrixXd mouthFaps(const MouthFapMap& map, const Eigen::RowVectorXd& jawDegrees);

inline constexpr std::array<int, 3> kHeadFaps{48, 49, 50};

// 3 x T in AU from pitch, yaw, roll in degrees (3 x T).
Eigen::MatrixXd headFaps(const Eigen::MatrixXd& rotationsDegrees);

// The map as a JSON object, and back (checked: unit axis, finite numbers, valid lip FAPs; th::Error names the
// file and the field).
nlohmann::json mouthFapMapJson(const MouthFapMap& map);
MouthFapMap mouthFapMapFromJson(const Json& json, const std::filesystem::path& file);

}  // namespace th::animation
