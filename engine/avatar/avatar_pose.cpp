#include "avatar/avatar_pose.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/error.h"
#include "face/fap_track.h"
#include "formats/arkit_format.h"

namespace th::avatar {
namespace {

constexpr double kRadians = 3.14159265358979323846 / 180.0;
constexpr float kLookSidewaysDegrees = 30.0f;  // ARKit's full scale (formats/arkit_format.h)
constexpr float kLookVerticalDegrees = 25.0f;

std::string lowered(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// A target by name, ignoring case (exporters differ in it); a target that moves nothing counts as absent
// (converters leave such: a VRoid character's jawOpen), so another scheme can move that part.
int findTarget(const MeshInstance& mesh, std::string_view name) {
  const std::string wanted = lowered(name);
  for (std::size_t t = 0; t < mesh.targetNames.size(); ++t) {
    if (lowered(mesh.targetNames[t]) != wanted) continue;
    for (const Primitive& primitive : mesh.primitives)
      if (t < primitive.targetPositions.size() && primitive.targetPositions[t].cwiseAbs().maxCoeff() > 1e-6f)
        return static_cast<int>(t);
    return -1;
  }
  return -1;
}

// Oculus's names as characters carry them: viseme_PP ..., and viseme_I, viseme_O, viseme_U for ih, oh, ou.
int findViseme(const MeshInstance& mesh, int viseme) {
  static constexpr std::array<std::string_view, face::kNumOculusVisemes> kShort{
      "sil", "PP", "FF", "TH", "DD", "kk", "CH", "SS", "nn", "RR", "aa", "E", "I", "O", "U"};
  const int found =
      findTarget(mesh, "viseme_" + std::string(face::kOculusVisemeNames[static_cast<std::size_t>(viseme)]));
  return found >= 0 ? found : findTarget(mesh, "viseme_" + std::string(kShort[static_cast<std::size_t>(viseme)]));
}

bool isEyeOrBrowOrBlink(std::string_view arkitName) {
  return arkitName.starts_with("eyeBlink") || arkitName.starts_with("eyeLook") || arkitName.starts_with("brow");
}

// A rotation given about the world's axes, applied at a node without moving it in the rest pose's frame:
// local' = local · (G⁻¹ R G), G the node's rest rotation in the world.
Eigen::Quaternionf inNodeFrame(const Eigen::Quaternionf& world, const Eigen::Quaternionf& restGlobal) {
  return restGlobal.conjugate() * world * restGlobal;
}

// BEAT2's R = Ry(yaw) Rx(pitch) Rz(roll), each angle times `share`; for a character facing −z the same motion
// seen from its front (turned half round about y).
Eigen::Quaternionf headRotation(const Eigen::Vector3d& degrees, double share, bool facesMinusZ) {
  const Eigen::Quaterniond r = Eigen::AngleAxisd(share * degrees[1] * kRadians, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(share * degrees[0] * kRadians, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(share * degrees[2] * kRadians, Eigen::Vector3d::UnitZ());
  if (!facesMinusZ) return r.cast<float>();
  const Eigen::Quaterniond half(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()));
  return (half * r * half.conjugate()).cast<float>();
}

}  // namespace

std::string schemeName(MorphScheme scheme) {
  switch (scheme) {
    case MorphScheme::kArkit:
      return "ARKit blendshapes";
    case MorphScheme::kOculusVisemes:
      return "Oculus visemes";
    case MorphScheme::kVrmExpressions:
      return "VRM expressions";
    case MorphScheme::kNone:
      break;
  }
  return "no morph targets";
}

namespace {

// Each upper arm's direction at rest (from its joint to its child's), turned in its vertical plane down to
// `degrees` below the horizontal where it is higher.
void lowerTheArms(const Avatar& avatar, double degrees, AvatarRig& rig) {
  if (degrees <= 0.0) return;
  std::vector<Eigen::Affine3f> locals;
  for (const Node& node : avatar.nodes) locals.push_back(node.local());
  const std::vector<Eigen::Affine3f> globals = globalTransforms(avatar, locals);
  const auto sine = static_cast<float>(std::sin(degrees * kRadians)),
             cosine = static_cast<float>(std::cos(degrees * kRadians));
  for (std::size_t side = 0; side < 2; ++side) {
    const int arm = avatar.upperArms[side];
    if (arm < 0) continue;
    // The child farthest from the joint: the elbow (not a twist or helper bone at the shoulder).
    const Eigen::Vector3f shoulder = globals[static_cast<std::size_t>(arm)].translation();
    Eigen::Vector3f along = Eigen::Vector3f::Zero();
    for (std::size_t n = 0; n < avatar.nodes.size(); ++n)
      if (avatar.nodes[n].parent == arm) {
        const Eigen::Vector3f offset = globals[n].translation() - shoulder;
        if (offset.squaredNorm() > along.squaredNorm()) along = offset;
      }
    if (along.squaredNorm() <= 0.0f) continue;
    const Eigen::Vector3f direction = along.normalized();
    Eigen::Vector3f outwards(direction.x(), 0.0f, direction.z());
    if (outwards.squaredNorm() < 1e-6f || -direction.y() >= sine) continue;  // already down
    outwards.normalize();
    const Eigen::Vector3f lowered = cosine * outwards - sine * Eigen::Vector3f::UnitY();
    rig.arms[side] = arm;
    rig.armTurns[side] = Eigen::Quaternionf::FromTwoVectors(direction, lowered);
  }
}

}  // namespace

AvatarRig rigAvatar(const Avatar& avatar, const RigOptions& options) {
  AvatarRig rig;
  rig.neckShare = options.neckShare;
  int arkitNames = 0, visemeNames = 0;
  std::array<bool, 52> arkitSeen{};
  std::array<bool, face::kNumOculusVisemes> visemeSeen{};
  for (const MeshInstance& mesh : avatar.meshes) {
    std::array<int, 52> arkit{};
    std::array<int, face::kNumOculusVisemes> visemes{};
    for (std::size_t k = 0; k < arkit.size(); ++k) {
      arkit[k] = findTarget(mesh, formats::kArkitNames[k]);
      arkitSeen[k] = arkitSeen[k] || arkit[k] >= 0;
    }
    for (int k = 0; k < face::kNumOculusVisemes; ++k) {
      visemes[static_cast<std::size_t>(k)] = findViseme(mesh, k);
      visemeSeen[static_cast<std::size_t>(k)] =
          visemeSeen[static_cast<std::size_t>(k)] || visemes[static_cast<std::size_t>(k)] >= 0;
    }
    rig.arkitTargets.push_back(arkit);
    rig.visemeTargets.push_back(visemes);
  }
  arkitNames = static_cast<int>(std::count(arkitSeen.begin(), arkitSeen.end(), true));
  visemeNames = static_cast<int>(std::count(visemeSeen.begin(), visemeSeen.end(), true));
  const bool jaw = arkitSeen[static_cast<std::size_t>(formats::arkitIndex("jawOpen"))];
  int vowels = 0;
  for (const char* vowel : {"aa", "ih", "ou", "ee", "oh"}) vowels += avatar.expressions.count(vowel) > 0;
  if (arkitNames >= 52 / 3 && jaw)
    rig.scheme = MorphScheme::kArkit;
  else if (visemeNames >= face::kNumOculusVisemes / 3)
    rig.scheme = MorphScheme::kOculusVisemes;
  else if (vowels >= 3)
    rig.scheme = MorphScheme::kVrmExpressions;
  // Only the scheme's names are driven: ARKit's eye, brow and blink shapes join the visemes; nothing else.
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    for (std::size_t k = 0; k < 52; ++k) {
      const bool used = rig.scheme == MorphScheme::kArkit ||
                        (rig.scheme == MorphScheme::kOculusVisemes && isEyeOrBrowOrBlink(formats::kArkitNames[k]));
      if (!used) rig.arkitTargets[m][k] = -1;
    }
    if (rig.scheme != MorphScheme::kOculusVisemes) rig.visemeTargets[m].fill(-1);
  }
  for (const auto& targets : rig.arkitTargets)
    for (std::size_t k = 0; k < 52; ++k)
      if (targets[k] >= 0 && formats::kArkitNames[k].starts_with("eyeLook")) rig.eyesByTargets = true;
  lowerTheArms(avatar, options.armsDownDegrees, rig);
  if (avatar.bones[kHead] < 0) rig.missing.push_back("no head bone (the head stays still)");
  if (avatar.bones[kNeck] < 0 && avatar.bones[kHead] >= 0) rig.missing.push_back("no neck bone (the head turns alone)");
  if (!rig.eyesByTargets && (avatar.bones[kLeftEye] < 0 || avatar.bones[kRightEye] < 0))
    rig.missing.push_back("no eye bones or eyeLook targets (the eyes stay still)");
  if (rig.scheme == MorphScheme::kNone) {
    if (avatar.bones[kHead] < 0)
      throw Error(avatar.name +
                  ": has no morph targets we know (ARKit's, Oculus visemes or VRM expressions) and no head bone: "
                  "nothing to drive");
    rig.missing.push_back("no morph targets we know (the mouth stays still)");
  }
  return rig;
}

AvatarPose restPose(const Avatar& avatar) {
  AvatarPose pose;
  for (const MeshInstance& mesh : avatar.meshes) pose.weights.push_back(mesh.restWeights);
  for (const Node& node : avatar.nodes) pose.locals.push_back(node.local());
  return pose;
}

namespace {

// A VRM character's expressions: its five vowels, and its blinks (one for both lids where it has no blink of
// each), added to the morph targets they bind, each weight at most 1.
void addVrmExpressions(const Avatar& avatar, const AvatarInput& input, AvatarPose& pose) {
  const float blinkLeft = input.arkit[static_cast<std::size_t>(formats::arkitIndex("eyeBlinkLeft"))];
  const float blinkRight = input.arkit[static_cast<std::size_t>(formats::arkitIndex("eyeBlinkRight"))];
  const bool separateLids = avatar.expressions.count("blinkLeft") > 0 && avatar.expressions.count("blinkRight") > 0;
  const std::array<std::pair<const char*, float>, 8> driven{
      {{"aa", input.vrm[0]},
       {"ih", input.vrm[1]},
       {"ou", input.vrm[2]},
       {"ee", input.vrm[3]},
       {"oh", input.vrm[4]},
       {"blink", separateLids ? 0.0f : 0.5f * (blinkLeft + blinkRight)},
       {"blinkLeft", separateLids ? blinkLeft : 0.0f},
       {"blinkRight", separateLids ? blinkRight : 0.0f}}};
  for (const auto& [name, weight] : driven) {
    const auto found = avatar.expressions.find(name);
    if (found == avatar.expressions.end()) continue;
    for (const TargetBind& bind : found->second) {
      if (bind.mesh < 0 || bind.target < 0 ||
          bind.target >= static_cast<int>(pose.weights[static_cast<std::size_t>(bind.mesh)].size()))
        continue;
      float& w = pose.weights[static_cast<std::size_t>(bind.mesh)][static_cast<std::size_t>(bind.target)];
      w = std::min(1.0f, w + weight * bind.weight);
    }
  }
}

}  // namespace

void poseAvatar(const Avatar& avatar, const AvatarRig& rig, const AvatarInput& input, AvatarPose& pose) {
  if (pose.weights.size() != avatar.meshes.size() || pose.locals.size() != avatar.nodes.size()) pose = restPose(avatar);
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    std::vector<float>& weights = pose.weights[m];
    std::copy(avatar.meshes[m].restWeights.begin(), avatar.meshes[m].restWeights.end(), weights.begin());
    for (std::size_t k = 0; k < 52; ++k)
      if (const int t = rig.arkitTargets[m][k]; t >= 0) weights[static_cast<std::size_t>(t)] = input.arkit[k];
    if (rig.scheme != MorphScheme::kOculusVisemes) continue;
    // Without visemes (an animation file of FAPs alone), the visemes nearest to ARKit's mouth: the jaw's
    // opening as aa, the lips pressed as PP, rounded as oh and ou.
    std::array<float, face::kNumOculusVisemes> visemes = input.oculus;
    if (!input.hasVisemes) {
      const auto weight = [&](const char* name) {
        return input.arkit[static_cast<std::size_t>(formats::arkitIndex(name))];
      };
      visemes.fill(0.0f);
      visemes[10] = weight("jawOpen");      // aa
      visemes[1] = weight("mouthClose");    // PP
      visemes[13] = weight("mouthFunnel");  // oh
      visemes[14] = weight("mouthPucker");  // ou
    }
    for (std::size_t k = 0; k < rig.visemeTargets[m].size(); ++k)
      if (const int t = rig.visemeTargets[m][k]; t >= 0) weights[static_cast<std::size_t>(t)] = visemes[k];
  }
  if (rig.scheme == MorphScheme::kVrmExpressions) addVrmExpressions(avatar, input, pose);
  // Bones: the rest pose, then the head's rotation shared between neck and head, and the eyes' gaze.
  for (std::size_t n = 0; n < avatar.nodes.size(); ++n) pose.locals[n] = avatar.nodes[n].local();
  const auto restGlobalRotation = [&](int node) {
    Eigen::Quaternionf q = Eigen::Quaternionf::Identity();
    for (int n = node; n >= 0; n = avatar.nodes[static_cast<std::size_t>(n)].parent)
      q = avatar.nodes[static_cast<std::size_t>(n)].rotation * q;
    return q;
  };
  const auto rotate = [&](int node, const Eigen::Quaternionf& world) {
    if (node < 0) return;
    Node posed = avatar.nodes[static_cast<std::size_t>(node)];
    posed.rotation = (posed.rotation * inNodeFrame(world, restGlobalRotation(node))).normalized();
    pose.locals[static_cast<std::size_t>(node)] = posed.local();
  };
  for (std::size_t side = 0; side < 2; ++side) rotate(rig.arms[side], rig.armTurns[side]);
  const int neck = avatar.bones[kNeck], head = avatar.bones[kHead];
  const double neckShare = neck >= 0 && head >= 0 ? rig.neckShare : 0.0;
  rotate(neck >= 0 && head >= 0 ? neck : -1, headRotation(input.headDegrees, neckShare, avatar.facesMinusZ()));
  rotate(head, headRotation(input.headDegrees, 1.0 - neckShare, avatar.facesMinusZ()));
  if (!rig.eyesByTargets) {
    const auto weight = [&](const char* name) {
      return input.arkit[static_cast<std::size_t>(formats::arkitIndex(name))];
    };
    // Yaw to the character's left positive, pitch down positive, as the head's.
    const double down =
        kLookVerticalDegrees * 0.5 *
        (weight("eyeLookDownLeft") + weight("eyeLookDownRight") - weight("eyeLookUpLeft") - weight("eyeLookUpRight"));
    const double leftYaw = kLookSidewaysDegrees * (weight("eyeLookOutLeft") - weight("eyeLookInLeft"));
    const double rightYaw = kLookSidewaysDegrees * (weight("eyeLookInRight") - weight("eyeLookOutRight"));
    rotate(avatar.bones[kLeftEye], headRotation(Eigen::Vector3d(down, leftYaw, 0.0), 1.0, avatar.facesMinusZ()));
    rotate(avatar.bones[kRightEye], headRotation(Eigen::Vector3d(down, rightYaw, 0.0), 1.0, avatar.facesMinusZ()));
  }
}

MovingVertices movingVertices(const Avatar& avatar, const AvatarRig& rig) {
  // The bones the rig turns, and every node under them.
  std::vector<bool> moves(avatar.nodes.size(), false);
  for (const int bone : avatar.bones)
    if (bone >= 0) moves[static_cast<std::size_t>(bone)] = true;
  for (const int n : avatar.drawOrder) {
    const int parent = avatar.nodes[static_cast<std::size_t>(n)].parent;
    if (parent >= 0 && moves[static_cast<std::size_t>(parent)]) moves[static_cast<std::size_t>(n)] = true;
  }
  // The targets the rig can drive, per mesh.
  std::vector<std::vector<bool>> driven(avatar.meshes.size());
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    driven[m].assign(avatar.meshes[m].targetNames.size(), false);
    for (const int t : rig.arkitTargets[m])
      if (t >= 0) driven[m][static_cast<std::size_t>(t)] = true;
    for (const int t : rig.visemeTargets[m])
      if (t >= 0) driven[m][static_cast<std::size_t>(t)] = true;
  }
  if (rig.scheme == MorphScheme::kVrmExpressions)
    for (const auto& [name, binds] : avatar.expressions)
      for (const TargetBind& bind : binds)
        if (bind.mesh >= 0 && bind.target >= 0 &&
            bind.target < static_cast<int>(driven[static_cast<std::size_t>(bind.mesh)].size()))
          driven[static_cast<std::size_t>(bind.mesh)][static_cast<std::size_t>(bind.target)] = true;
  MovingVertices moving;
  moving.vertices.resize(avatar.meshes.size());
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    const MeshInstance& mesh = avatar.meshes[m];
    const Skin* skin = mesh.skin >= 0 ? &avatar.skins[static_cast<std::size_t>(mesh.skin)] : nullptr;
    const bool nodeMoves = skin == nullptr && moves[static_cast<std::size_t>(mesh.node)];
    for (const Primitive& primitive : mesh.primitives) {
      std::vector<std::uint32_t>& list = moving.vertices[m].emplace_back();
      for (Eigen::Index v = 0; v < primitive.positions.cols(); ++v) {
        bool moved = nodeMoves;
        if (!moved && skin != nullptr && primitive.joints.cols() == primitive.positions.cols())
          for (int k = 0; k < 4 && !moved; ++k)
            moved =
                primitive.weights(k, v) > 0.0f && moves[static_cast<std::size_t>(skin->joints[primitive.joints(k, v)])];
        for (std::size_t t = 0; t < primitive.targetPositions.size() && !moved; ++t)
          moved = driven[m][t] && primitive.targetPositions[t].col(v).squaredNorm() > 0.0f;
        if (moved) list.push_back(static_cast<std::uint32_t>(v));
      }
      moving.count += list.size();
    }
  }
  return moving;
}

namespace {

// The targets a mesh's weights move this frame (the rest weigh too little to show).
void activeTargets(const std::vector<float>& weights, std::vector<std::uint32_t>& active) {
  active.clear();
  for (std::size_t t = 0; t < weights.size(); ++t)
    if (std::abs(weights[t]) >= 1e-4f) active.push_back(static_cast<std::uint32_t>(t));
}

// One vertex: its morph targets at their weights (only the active ones), then skinned (or moved with its node).
void deformVertex(const Primitive& primitive, const std::vector<float>& weights,
                  const std::vector<std::uint32_t>& active, bool skinned, const std::vector<Eigen::Matrix4f>& joints,
                  const Eigen::Matrix4f& node, Eigen::Index v, Eigen::Matrix3Xf& positions, Eigen::Matrix3Xf& normals) {
  Eigen::Vector3f p = primitive.positions.col(v), n = primitive.normals.col(v);
  for (const std::uint32_t t : active) {
    if (t >= primitive.targetPositions.size()) break;
    p += weights[t] * primitive.targetPositions[t].col(v);
    n += weights[t] * primitive.targetNormals[t].col(v);
  }
  Eigen::Matrix4f blend;
  if (skinned) {
    blend.setZero();
    for (int k = 0; k < 4; ++k)
      if (const float w = primitive.weights(k, v); w != 0.0f) blend += w * joints[primitive.joints(k, v)];
  } else {
    blend = node;
  }
  positions.col(v) = blend.topLeftCorner<3, 3>() * p + blend.topRightCorner<3, 1>();
  normals.col(v) = (blend.topLeftCorner<3, 3>() * n).normalized();
}

}  // namespace

void deformAvatar(const Avatar& avatar, const AvatarPose& pose, std::vector<DeformedMesh>& meshes,
                  const MovingVertices* moving) {
  const std::vector<Eigen::Affine3f> global = globalTransforms(avatar, pose.locals);
  if (meshes.size() != avatar.meshes.size()) moving = nullptr;  // nothing kept to start from
  meshes.resize(avatar.meshes.size());
  std::vector<Eigen::Matrix4f> joints;
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    const MeshInstance& mesh = avatar.meshes[m];
    DeformedMesh& out = meshes[m];
    if (out.positions.size() != mesh.primitives.size()) {
      out.positions.resize(mesh.primitives.size());
      out.normals.resize(mesh.primitives.size());
      moving = nullptr;
    }
    activeTargets(pose.weights[m], out.activeTargets);
    const bool skinned = mesh.skin >= 0;
    if (skinned) {
      const Skin& skin = avatar.skins[static_cast<std::size_t>(mesh.skin)];
      joints.resize(skin.joints.size());
      for (std::size_t j = 0; j < skin.joints.size(); ++j)
        joints[j] = global[static_cast<std::size_t>(skin.joints[j])].matrix() * skin.inverseBind[j];
    }
    const Eigen::Matrix4f node = global[static_cast<std::size_t>(mesh.node)].matrix();
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const Primitive& primitive = mesh.primitives[p];
      const bool skinThis = skinned && primitive.joints.cols() == primitive.positions.cols();
      Eigen::Matrix3Xf& positions = out.positions[p];
      Eigen::Matrix3Xf& normals = out.normals[p];
      if (moving != nullptr && positions.cols() == primitive.positions.cols()) {
        for (const std::uint32_t v : moving->vertices[m][p])
          deformVertex(primitive, pose.weights[m], out.activeTargets, skinThis, joints, node, v, positions, normals);
        continue;
      }
      positions.resize(3, primitive.positions.cols());
      normals.resize(3, primitive.positions.cols());
      for (Eigen::Index v = 0; v < primitive.positions.cols(); ++v)
        deformVertex(primitive, pose.weights[m], out.activeTargets, skinThis, joints, node, v, positions, normals);
    }
  }
}

}  // namespace th::avatar
