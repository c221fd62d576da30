// The MPEG-4 facial animation parameters (ISO/IEC 14496-2, Annex C): the 68 FAPs, their units (FAPU) and the
// direction a positive value moves the feature point each one names; and FapFrame, one frame of FAP values, the
// type every stage hands the face (fap_track.h holds a track of them over time).
//
//   const th::face::FapDefinition& jaw = th::face::fapDefinition(3);   // open_jaw, MNS, moves 2.1 down
//   double metres = value * fapu.of(jaw.unit);                         // a FAP value is a count of its FAPU
//   th::face::FapFrame faps{};  faps[3] = 400;                         // index = FAP number
//
// Frame of the face: +x is the face's own left (the viewer's right), +y up, +z forward (out of the face).
// FAPUs are the neutral face's distances divided by 1024 (MNS mouth-nose separation, MW mouth width, ENS
// eye-nose separation, ES eye separation, IRISD iris diameter); angles are in AU = 1e-5 rad.
// FAPs 1 (viseme) and 2 (expression) are high-level and have no unit or direction; FAPs 23–26 and 48–50 are
// rotations (their `direction` is the rotation axis, sign chosen so that a positive angle moves as named).
// Thread contract: the table is immutable.
#pragma once

#include <Eigen/Core>
#include <array>
#include <numbers>
#include <string_view>

namespace th::face {

enum class Fapu { kNone, kMns, kMw, kEns, kEs, kIrisd, kAngle };

std::string_view fapuName(Fapu unit);  // "MNS", "MW", ..., "AU"; "" for kNone

constexpr int kNumFaps = 68;         // numbered 1..68
constexpr double kAngleUnit = 1e-5;  // AU in radians
constexpr double kDegreesPerAngleUnit = kAngleUnit * 180.0 / std::numbers::pi;

// One frame of FAP values: [n] is FAP n (1..68) in counts of its unit; [0] is unused.
using FapFrame = std::array<double, kNumFaps + 1>;

// The head's rotation, which a frame carries as FAPs 48, 49 and 50 (head_pitch, head_yaw, head_roll, in AU),
// as pitch, yaw and roll in degrees (pitch down, yaw to the face's left, roll to its right positive: BEAT2's
// convention, outputs/avatar_frame.h): the one conversion every consumer uses.
inline Eigen::Vector3d headDegreesOf(const FapFrame& faps) {
  return {faps[48] * kDegreesPerAngleUnit, faps[49] * kDegreesPerAngleUnit, faps[50] * kDegreesPerAngleUnit};
}

struct FapDefinition {
  int number;             // 1..68
  std::string_view name;  // the standard's name, e.g. "open_jaw"
  Fapu unit;
  bool bidirectional;
  std::string_view featurePoint;    // the feature point it moves ("2.1"), "" for high-level FAPs
  std::array<double, 3> direction;  // unit vector of positive motion (or rotation axis), face frame
  std::string_view group;           // "jaw", "inner lip", "eyelid", ... for panels and tables
};

// Throws th::Error for a number outside 1..68.
const FapDefinition& fapDefinition(int number);

// The number of the FAP with this name ("open_jaw" → 3), or 0 if there is none.
int fapNumber(std::string_view name);

// The FAPU values of a neutral face, in the mesh's length unit per FAPU (distance / 1024).
struct FapUnits {
  double mns = 0, mw = 0, ens = 0, es = 0, irisd = 0;
  double of(Fapu unit) const;  // the value for one unit; kAngle → 1e-5; kNone → 0
};

}  // namespace th::face
