// A character's speech animation as glTF tracks: the same poses `export --avatar` draws (avatar_pose.h), sampled
// at a fixed frame rate and handed to formats/gltf_animation.h, so that the tools that play glTF (Blender,
// three.js, Godot, Unity) play the speech on the user's character without our renderer.
//
//   const th::avatar::Avatar character = th::avatar::loadAvatar("brunette-t.glb");
//   const th::avatar::AvatarRig rig = th::avatar::rigAvatar(character);
//   const auto tracks = th::avatar::avatarAnimation(speech, character, rig);   // speech: a face::FapTrack
//   th::formats::writeAvatarAnimation("brunette-t.glb", tracks, "talk.glb");
//
// Frame i is at i / framesPerSecond seconds, over the speech's duration (avatarInputAt: its FAPs there, and its
// visemes where it has them). Tracks:
// - per mesh node whose morph targets the rig drives, every target's weight (targets x frames), the targets the
//   rig does not drive held at their rest weight (glTF animates a node's weights all together);
// - the local rotation of the neck, head and eye bones the pose turns (the eyes only where no eyeLook* targets
//   move them): the rest rotation times the turn, as poseAvatar makes it.
// A track's node is an index into Avatar::nodes, which loadAvatar keeps in the file's order: the node the writer
// reads back from the same file.
// Thread contract: a pure function.
#pragma once

#include <filesystem>
#include <string>

#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "face/fap_track.h"
#include "formats/gltf_animation.h"

namespace th::avatar {

struct AvatarAnimationOptions {
  double framesPerSecond = 30.0;  // keyframes a second (a video's rate; glTF players interpolate between them)
  std::string name = "speech";    // the glTF animation's name
};

formats::GltfAnimationTracks avatarAnimation(const face::FapTrack& speech, const Avatar& avatar, const AvatarRig& rig,
                                             const AvatarAnimationOptions& options = {});

// Where a character's animation can go, checked before any work: .glb or .gltf, or .vrm from a .vrm character
// (the animation alone is never a VRM). Throws th::Error naming `out`.
void checkAvatarAnimationOutput(const std::filesystem::path& avatar, const std::filesystem::path& out,
                                bool animationOnly);

// The speech on the character, written as `animate --avatar` and the library's th_animation_write_avatar write
// it: the character's file (`avatarFile`, which `avatar` was read from) with the speech as one more glTF animation,
// or the animation alone (`animationOnly`), at `out`, atomically. Returns the tracks written.
formats::GltfAnimationTracks writeSpeechOnAvatar(const std::filesystem::path& avatarFile, const Avatar& avatar,
                                                 const face::FapTrack& speech, const std::filesystem::path& out,
                                                 bool animationOnly);

// How many frames avatarAnimation makes of `speech` (at least one).
int avatarAnimationFrames(const face::FapTrack& speech, const AvatarAnimationOptions& options = {});

}  // namespace th::avatar
