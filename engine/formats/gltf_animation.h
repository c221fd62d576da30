// Speech animation as glTF, for the tools that play glTF characters (Blender, three.js, Godot, Unity): morph
// target weights and node rotations, one keyframe per video frame, written either into the avatar itself or
// into a small file that only has the avatar's node hierarchy.
//
//   auto avatar = th::formats::readGltfAvatar("brunette-t.glb");
//   th::formats::GltfAnimationTracks tracks;                        // 30 frames a second, named "speech"
//   tracks.morphs.push_back({avatar.findNode("Wolf3D_Head"), weights});   // targets x frames, 0..1
//   tracks.rotations.push_back({avatar.findNode("Head"), headRotations}); // one local rotation per frame
//   th::formats::writeAvatarAnimation("brunette-t.glb", tracks, "talk.glb");
//   th::formats::writeAnimationOnly("brunette-t.glb", tracks, "talk-animation.gltf");
//
// Both forms: one animation named tracks.name; per track a sampler with LINEAR interpolation whose input is the
// frame times i / framesPerSecond (floats, with min and max) and whose output is, for a morph track, frames x
// targets floats frame by frame (glTF's layout for `weights`), for a rotation track unit quaternions (x, y, z, w),
// each on the same side of the sphere as the one before so that interpolation takes the short way. The output's
// extension picks the container: .glb (one binary buffer) or .gltf (JSON with the buffer embedded as a data URI,
// so the file stands alone); writeAvatarAnimation also takes .vrm (binary, as .glb).
//
// The avatar is a .glb, .gltf or .vrm file, read with tinygltf. Its meshes, skins, materials, textures,
// extensions (VRM's included) and its own animations are kept; its buffers become one, and images that were files
// or data URIs beside a .gltf move into that buffer. A binary avatar compressed with EXT_meshopt_compression is
// decompressed (tinygltf cannot read the extension's fallback buffer), so the written file is larger than the
// avatar.
//
// Every write checks the tracks against the avatar first (a positive finite frame rate, at least one track and one
// frame, the same frame count in every track, nodes in range and animated once per path, a morph track's rows equal
// to its node's mesh's target count, finite values, non-zero quaternions) and is atomic: all or nothing. Errors
// (th::Error) are one line naming the file at fault: the avatar for a node or target count it does not have, the
// output for tracks that could not be written anywhere.
// Thread contract: pure functions of files.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace th::formats {

// The node (with a mesh that has morph targets) whose weights move: targets x frames.
struct GltfMorphTrack {
  int node = -1;
  Eigen::MatrixXf weights;
};

// A node's local rotation, one per frame, relative to its parent: it replaces the rest rotation (a turn away from
// rest is GltfAvatarNode::rotation * turn). Its translation and scale stay at rest.
struct GltfRotationTrack {
  int node = -1;
  std::vector<Eigen::Quaternionf> rotations;
};

struct GltfAnimationTracks {
  double framesPerSecond = 30.0;
  std::string name = "speech";
  std::vector<GltfMorphTrack> morphs;
  std::vector<GltfRotationTrack> rotations;
};

// What a caller needs to aim tracks at an avatar's nodes, read from its file.
struct GltfAvatarNode {
  std::string name;
  int parent = -1;                       // -1: a root
  int mesh = -1;                         // -1: none
  int targetCount = 0;                   // the mesh's morph targets, 0 without
  std::vector<std::string> targetNames;  // the mesh's extras.targetNames, where it has them
  // The rest pose relative to the parent (a node placed by a matrix: identity here, and it cannot be rotated).
  Eigen::Vector3f translation = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  Eigen::Vector3f scale = Eigen::Vector3f::Ones();
  bool placedByMatrix = false;
};

struct GltfAvatar {
  std::vector<GltfAvatarNode> nodes;  // in the file's order: a track's node is an index here
  // The first node so named, -1 if none.
  int findNode(std::string_view name) const;
  // The nodes whose meshes have morph targets, in order.
  std::vector<int> morphNodes() const;
  // A target's index in a node's mesh by its name, -1 if none.
  int targetIndex(int node, std::string_view target) const;
};

// Throws th::Error naming the file if it is missing or not glTF.
GltfAvatar readGltfAvatar(const std::filesystem::path& avatar);

// The avatar with the tracks added as one more animation, written to `out` (.glb, .vrm or .gltf).
void writeAvatarAnimation(const std::filesystem::path& avatar, const GltfAnimationTracks& tracks,
                          const std::filesystem::path& out);

// The animation alone, to `out` (.glb or .gltf): the avatar's nodes (names, parents, rest transforms, scenes)
// and, for each node with a morph track, a stand-in mesh of one degenerate triangle with as many morph targets as
// the avatar's mesh and its extras.targetNames, so that tools which retarget by node and target name can apply
// the animation to the character. No skins, materials or textures.
void writeAnimationOnly(const std::filesystem::path& avatar, const GltfAnimationTracks& tracks,
                        const std::filesystem::path& out);

}  // namespace th::formats
