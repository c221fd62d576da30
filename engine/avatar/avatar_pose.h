// A character posed by the frame that drives our own face: its morph targets by name, its neck and head bones
// from the head's rotation, its eyes from the gaze and its lids from the blinks; then its meshes deformed
// (morph targets, then linear-blend skinning) on the CPU, ready to draw.
//
//   const th::avatar::AvatarRig rig = th::avatar::rigAvatar(character);   // once: what drives what
//   th::avatar::AvatarPose pose;
//   std::vector<th::avatar::DeformedMesh> meshes;
//   for each frame:
//     th::avatar::poseAvatar(character, rig, th::avatar::avatarInputOf(frame.faps, &visemeProbabilities), pose);
//     th::avatar::deformAvatar(character, pose, meshes);       // no allocation after the first frame
//
// The morph targets, in the first scheme the character has (a scheme counts if it has at least a third of its
// names, ARKit's only with a jawOpen that moves something; a target that moves nothing counts as absent):
// - ARKit's 52 (our ARKit weights, formats/arkit_format.h);
// - else the 15 Oculus visemes ("viseme_PP" ...: our viseme probabilities, or without them the jaw's opening
//   as aa, mouthClose as PP, mouthFunnel as oh and mouthPucker as ou), with ARKit's blinks, gaze and brows
//   where present;
// - else VRM's expressions (aa ih ou ee oh from our five vowel weights, blink, blinkLeft, blinkRight).
// The head's rotation (pitch, yaw, roll in the BEAT2 convention, outputs/avatar_frame.h's) is a rotation about
// the world's axes, neckShare of each angle on the neck bone and the rest on the head (all on the head without
// a neck); a VRM 0.x character faces −z and gets it turned round. Eyes: the eyeLook* targets where the scheme
// has them, else the eye bones (30° sideways, 25° up and down at full weight, ARKit's full scale).
// Thread contract: values and pure functions (poseAvatar and deformAvatar write only their outputs).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "avatar/avatar_input.h"
#include "avatar/avatar_model.h"
#include "face/fap.h"
#include "face/fap_track.h"
#include "face/visemes.h"

namespace th::avatar {

enum class MorphScheme { kArkit, kOculusVisemes, kVrmExpressions, kNone };

struct RigOptions {
  double neckShare = 0.4;  // of the head's rotation on the neck bone
  // A character made in its T-pose (arms level) is shown with its upper arms lowered to this angle below the
  // horizontal, as people stand to speak; arms already lower stay as they are. 0: as the file has them.
  double armsDownDegrees = 70.0;
};

struct AvatarRig {
  MorphScheme scheme = MorphScheme::kNone;
  // Per mesh, per driving name: the target index, or -1.
  std::vector<std::array<int, 52>> arkitTargets;
  std::vector<std::array<int, face::kNumOculusVisemes>> visemeTargets;
  bool eyesByTargets = false;  // eyeLook* targets present in the scheme
  double neckShare = 0.4;
  // The upper arms' nodes (-1: none) and the turn, about the world's axes, that lowers each.
  std::array<int, 2> arms{-1, -1};
  std::array<Eigen::Quaternionf, 2> armTurns{Eigen::Quaternionf::Identity(), Eigen::Quaternionf::Identity()};
  std::vector<std::string> missing;  // what the character lacks ("no neck bone", ...), for a note to the user
};

// What drives what; throws th::Error (naming the character) when nothing would move: no morph targets of any
// scheme and no head bone.
AvatarRig rigAvatar(const Avatar& avatar, const RigOptions& options = {});
std::string schemeName(MorphScheme scheme);

struct AvatarPose {
  std::vector<std::vector<float>> weights;  // per mesh, per target
  std::vector<Eigen::Affine3f> locals;      // per node
};

void poseAvatar(const Avatar& avatar, const AvatarRig& rig, const AvatarInput& input, AvatarPose& pose);

// A mesh as drawn: per primitive, positions and normals in the scene's space.
struct DeformedMesh {
  std::vector<Eigen::Matrix3Xf> positions;
  std::vector<Eigen::Matrix3Xf> normals;
  std::vector<std::uint32_t> activeTargets;  // the morph targets applied: those weighing at least 1e-4
};

// Which vertices a rig can move: those weighted to the neck, the head, the eyes or a bone under them, and
// those a driven morph target displaces; per mesh, per primitive. A character is mostly body, which stays put.
struct MovingVertices {
  std::vector<std::vector<std::vector<std::uint32_t>>> vertices;  // [mesh][primitive] -> vertex indices
  std::size_t count = 0;                                          // of all of them
};
MovingVertices movingVertices(const Avatar& avatar, const AvatarRig& rig);

// Every vertex of every mesh; or, with `moving` (and `meshes` deformed before by the same avatar), only the
// vertices that can move, the rest kept as they were.
void deformAvatar(const Avatar& avatar, const AvatarPose& pose, std::vector<DeformedMesh>& meshes,
                  const MovingVertices* moving = nullptr);

// The rest pose (every weight its rest value, every node at rest).
AvatarPose restPose(const Avatar& avatar);

}  // namespace th::avatar
