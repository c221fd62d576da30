#include "render/animated_avatar.h"

#include <algorithm>
#include <cmath>

namespace th::render {

OrbitCamera frameAvatarHead(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes,
                            double aspect) {
  // The head bone and every node under it.
  std::vector<bool> underHead(avatar.nodes.size(), false);
  const int head = avatar.bones[avatar::kHead];
  for (const int n : avatar.drawOrder) {
    const int parent = avatar.nodes[static_cast<std::size_t>(n)].parent;
    underHead[static_cast<std::size_t>(n)] = n == head || (parent >= 0 && underHead[static_cast<std::size_t>(parent)]);
  }
  // The face: the mesh with the most morph targets (hair, hats and long hair would widen the box); every mesh
  // when none has targets.
  // Of meshes with as many targets (the eyes and teeth often share the face's list), the largest.
  std::size_t face = avatar.meshes.size();
  std::pair<std::size_t, Eigen::Index> most{0, 0};
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    Eigen::Index vertices = 0;
    for (const avatar::Primitive& primitive : avatar.meshes[m].primitives) vertices += primitive.positions.cols();
    const std::pair<std::size_t, Eigen::Index> size{avatar.meshes[m].targetNames.size(), vertices};
    if (size.first > 0 && size > most) {
      most = size;
      face = m;
    }
  }
  Eigen::Vector3f low = Eigen::Vector3f::Constant(1e30f), high = -low;
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    if (face < avatar.meshes.size() && m != face) continue;
    const avatar::MeshInstance& mesh = avatar.meshes[m];
    const avatar::Skin* skin = mesh.skin >= 0 ? &avatar.skins[static_cast<std::size_t>(mesh.skin)] : nullptr;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const avatar::Primitive& primitive = mesh.primitives[p];
      const Eigen::Matrix3Xf& positions = meshes[m].positions[p];
      for (Eigen::Index v = 0; v < positions.cols(); ++v) {
        bool onHead = head < 0;  // no head bone: frame the whole character
        if (!onHead && skin != nullptr && primitive.joints.cols() == positions.cols()) {
          Eigen::Index strongest = 0;
          primitive.weights.col(v).maxCoeff(&strongest);
          const int joint = skin->joints[primitive.joints(strongest, v)];
          onHead = underHead[static_cast<std::size_t>(joint)];
        } else if (!onHead && skin == nullptr) {
          onHead = underHead[static_cast<std::size_t>(mesh.node)];
        }
        if (!onHead) continue;
        low = low.cwiseMin(positions.col(v));
        high = high.cwiseMax(positions.col(v));
      }
    }
  }
  if (!(low.array() <= high.array()).all()) {  // nothing on the head: the whole character
    for (const avatar::DeformedMesh& mesh : meshes)
      for (const Eigen::Matrix3Xf& positions : mesh.positions) {
        if (positions.cols() == 0) continue;
        low = low.cwiseMin(positions.rowwise().minCoeff());
        high = high.cwiseMax(positions.rowwise().maxCoeff());
      }
  }
  const float height = std::max(high.y() - low.y(), 1e-3f);
  const float width = std::max(high.x() - low.x(), 1e-3f);
  OrbitCamera camera;
  camera.pitchDegrees = 8.0f;
  // The head and a little of the neck below it, the face slightly above the centre.
  const float shown = 1.6f * std::max(height, width / static_cast<float>(aspect));
  camera.target = {0.5f * (low.x() + high.x()), low.y() + 0.42f * height, 0.5f * (low.z() + high.z())};
  const float halfFov = 0.5f * camera.fovYDegrees * static_cast<float>(M_PI) / 180.0f;
  camera.distance = 0.5f * shown / std::tan(halfFov);
  camera.nearPlane = 0.05f * camera.distance;
  camera.farPlane = 20.0f * camera.distance;
  if (avatar.facesMinusZ()) camera.yawDegrees = 180.0f;
  return camera;
}

AnimatedAvatar::AnimatedAvatar(const avatar::Avatar& avatar, GlContext& context, const AvatarRenderOptions& options)
    : avatar_(avatar),
      rig_(avatar::rigAvatar(avatar)),
      moving_(avatar::movingVertices(avatar, rig_)),
      renderer_(context, avatar, options),
      pose_(avatar::restPose(avatar)) {
  renderer_.setMovingVertices(moving_);
  // The rig's pose at rest (the arms lowered from a T-pose), every vertex: after this, only the moving ones.
  avatar::poseAvatar(avatar_, rig_, avatar::AvatarInput{}, pose_);
  avatar::deformAvatar(avatar_, pose_, meshes_);
  renderer_.setMeshes(meshes_);
  camera_ = frameAvatarHead(avatar_, meshes_, static_cast<double>(options.width) / options.height);
}

void AnimatedAvatar::pose(const face::FapFrame& faps, const float* visemeProbabilities) {
  pose(avatar::avatarInputOf(faps, visemeProbabilities));
}

void AnimatedAvatar::poseAt(const face::FapTrack& animation, double seconds) {
  pose(avatar::avatarInputAt(animation, seconds));
}

void AnimatedAvatar::pose(const avatar::AvatarInput& input) {
  avatar::poseAvatar(avatar_, rig_, input, pose_);
  avatar::deformAvatar(avatar_, pose_, meshes_, &moving_);
  renderer_.setMeshes(meshes_, &moving_);
}

std::string AnimatedAvatar::description() const {
  return avatar_.name + " (" + avatar::schemeName(rig_.scheme) + ")";
}

void AnimatedAvatar::resize(int width, int height) {
  renderer_.resize(width, height);
  avatar::AvatarPose rest;
  avatar::poseAvatar(avatar_, rig_, avatar::AvatarInput{}, rest);
  std::vector<avatar::DeformedMesh> meshes;
  avatar::deformAvatar(avatar_, rest, meshes);
  camera_ = frameAvatarHead(avatar_, meshes, static_cast<double>(width) / height);
}

Eigen::Vector3f avatarMouthCentre(const avatar::Avatar& avatar, const std::vector<avatar::DeformedMesh>& meshes) {
  // The mouth's opening target, as the rig would pick it: ARKit's jawOpen, the aa viseme, VRM's aa.
  std::vector<avatar::TargetBind> opening;
  for (const char* name : {"jawOpen", "viseme_aa"}) {
    for (std::size_t m = 0; m < avatar.meshes.size(); ++m)
      if (const int t = avatar.meshes[m].targetIndex(name); t >= 0)
        opening.push_back({.mesh = static_cast<int>(m), .target = t});
    // The first name with a target that moves something.
    const bool moves = std::any_of(opening.begin(), opening.end(), [&](const avatar::TargetBind& bind) {
      for (const avatar::Primitive& primitive : avatar.meshes[static_cast<std::size_t>(bind.mesh)].primitives)
        if (primitive.targetPositions[static_cast<std::size_t>(bind.target)].cwiseAbs().maxCoeff() > 0.0f) return true;
      return false;
    });
    if (moves) break;
    opening.clear();
  }
  if (opening.empty())
    if (const auto found = avatar.expressions.find("aa"); found != avatar.expressions.end()) opening = found->second;
  // The vertices it moves most (the lips and the chin), where they are drawn now.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double count = 0.0;
  for (const avatar::TargetBind& bind : opening) {
    const avatar::MeshInstance& mesh = avatar.meshes[static_cast<std::size_t>(bind.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const Eigen::Matrix3Xf& moved = mesh.primitives[p].targetPositions[static_cast<std::size_t>(bind.target)];
      float most = 0.0f;
      for (Eigen::Index v = 0; v < moved.cols(); ++v) most = std::max(most, moved.col(v).norm());
      if (most <= 0.0f) continue;
      const Eigen::Matrix3Xf& drawn = meshes[static_cast<std::size_t>(bind.mesh)].positions[p];
      for (Eigen::Index v = 0; v < moved.cols(); ++v)
        if (moved.col(v).norm() > 0.3f * most) {
          sum += drawn.col(v).cast<double>();
          count += 1.0;
        }
    }
  }
  return count > 0.0 ? Eigen::Vector3f((sum / count).cast<float>()) : Eigen::Vector3f::Constant(NAN);
}

void AnimatedAvatar::frameMouth() {
  const Eigen::Vector3f mouth = avatarMouthCentre(avatar_, meshes_);
  if (!mouth.allFinite()) return;  // no mouth target: the head stays framed
  camera_.target = mouth;
  camera_.distance *= 0.3f;
}

}  // namespace th::render
