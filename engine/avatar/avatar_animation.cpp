#include "avatar/avatar_animation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/text_files.h"

namespace th::avatar {
namespace {

// The VRM expressions poseAvatar drives (the five vowels and the blinks).
constexpr std::array<std::string_view, 8> kDrivenExpressions{"aa", "ih",    "ou",        "ee",
                                                             "oh", "blink", "blinkLeft", "blinkRight"};

// Per mesh: does the rig drive any of its targets?
std::vector<bool> meshesDriven(const Avatar& avatar, const AvatarRig& rig) {
  std::vector<bool> driven(avatar.meshes.size(), false);
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    if (avatar.meshes[m].targetNames.empty()) continue;
    const auto any = [](const auto& targets) {
      return std::any_of(targets.begin(), targets.end(), [](int t) { return t >= 0; });
    };
    driven[m] = any(rig.arkitTargets[m]) || any(rig.visemeTargets[m]);
  }
  if (rig.scheme == MorphScheme::kVrmExpressions)
    for (const std::string_view name : kDrivenExpressions) {
      const auto found = avatar.expressions.find(std::string(name));
      if (found == avatar.expressions.end()) continue;
      for (const TargetBind& bind : found->second)
        if (bind.mesh >= 0 && bind.mesh < static_cast<int>(avatar.meshes.size()) && bind.target >= 0 &&
            bind.target < static_cast<int>(avatar.meshes[static_cast<std::size_t>(bind.mesh)].targetNames.size()))
          driven[static_cast<std::size_t>(bind.mesh)] = true;
    }
  return driven;
}

// The bones poseAvatar turns, each once: the neck (with a head to share the turn), the head, and the eyes where
// no eyeLook* targets move them.
std::vector<int> turnedBones(const Avatar& avatar, const AvatarRig& rig) {
  std::vector<int> bones;
  const auto add = [&](int node) {
    if (node >= 0 && std::find(bones.begin(), bones.end(), node) == bones.end()) bones.push_back(node);
  };
  if (avatar.bones[kHead] >= 0) add(avatar.bones[kNeck]);
  add(avatar.bones[kHead]);
  if (!rig.eyesByTargets) {
    add(avatar.bones[kLeftEye]);
    add(avatar.bones[kRightEye]);
  }
  return bones;
}

}  // namespace

void checkAvatarAnimationOutput(const std::filesystem::path& avatar, const std::filesystem::path& out,
                                bool animationOnly) {
  const std::string extension = lowercaseExtension(out);
  if (extension != ".glb" && extension != ".gltf" && extension != ".vrm")
    throw fileError(out, "a character's animation is glTF: name a .glb, .gltf or .vrm");
  if (extension == ".vrm" && animationOnly)
    throw fileError(out, "the animation alone is not a VRM character: name a .glb or .gltf");
  if (extension == ".vrm" && lowercaseExtension(avatar) != ".vrm")
    throw fileError(out, "a VRM is written from a VRM character (" + avatar.filename().string() +
                             " is not .vrm): name a .glb or .gltf");
}

int avatarAnimationFrames(const face::FapTrack& speech, const AvatarAnimationOptions& options) {
  const double frames = std::ceil(speech.durationSeconds() * options.framesPerSecond - 1e-9);
  return std::max(1, static_cast<int>(frames));
}

formats::GltfAnimationTracks avatarAnimation(const face::FapTrack& speech, const Avatar& avatar, const AvatarRig& rig,
                                             const AvatarAnimationOptions& options) {
  if (!std::isfinite(options.framesPerSecond) || options.framesPerSecond <= 0.0)
    throw Error("an avatar animation needs a positive frame rate, not " + std::to_string(options.framesPerSecond));
  const int frames = avatarAnimationFrames(speech, options);
  formats::GltfAnimationTracks tracks;
  tracks.framesPerSecond = options.framesPerSecond;
  tracks.name = options.name;

  // The tracks, sized once; each frame's pose is copied into its column.
  const std::vector<bool> driven = meshesDriven(avatar, rig);
  std::vector<std::size_t> morphMeshes;
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m) {
    if (!driven[m]) continue;
    morphMeshes.push_back(m);
    const auto targets = static_cast<Eigen::Index>(avatar.meshes[m].targetNames.size());
    tracks.morphs.push_back({avatar.meshes[m].node, Eigen::MatrixXf(targets, frames)});
  }
  for (const int bone : turnedBones(avatar, rig))
    tracks.rotations.push_back({bone, std::vector<Eigen::Quaternionf>(static_cast<std::size_t>(frames))});

  AvatarPose pose = restPose(avatar);
  for (int i = 0; i < frames; ++i) {
    poseAvatar(avatar, rig, avatarInputAt(speech, i / options.framesPerSecond), pose);
    for (std::size_t k = 0; k < morphMeshes.size(); ++k) {
      const std::vector<float>& weights = pose.weights[morphMeshes[k]];
      tracks.morphs[k].weights.col(i) =
          Eigen::Map<const Eigen::VectorXf>(weights.data(), static_cast<Eigen::Index>(weights.size()));
    }
    for (formats::GltfRotationTrack& track : tracks.rotations)
      track.rotations[static_cast<std::size_t>(i)] =
          Eigen::Quaternionf(pose.locals[static_cast<std::size_t>(track.node)].rotation());
  }
  return tracks;
}

formats::GltfAnimationTracks writeSpeechOnAvatar(const std::filesystem::path& avatarFile, const Avatar& avatar,
                                                 const face::FapTrack& speech, const std::filesystem::path& out,
                                                 bool animationOnly) {
  formats::GltfAnimationTracks tracks = avatarAnimation(speech, avatar, rigAvatar(avatar));
  if (animationOnly)
    formats::writeAnimationOnly(avatarFile, tracks, out);
  else
    formats::writeAvatarAnimation(avatarFile, tracks, out);
  return tracks;
}

}  // namespace th::avatar
