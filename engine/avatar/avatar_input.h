// What drives a character each frame (the weights every character consumer takes: the renderer, the live
// outputs, the library's frames and the web package's), made from the frame that drives our own face.
//
//   const th::avatar::AvatarInput weights = th::avatar::avatarInputOf(faps, visemeProbabilities);   // or nullptr
//
// Thread contract: a value and pure functions.
#pragma once

#include <Eigen/Core>
#include <array>

#include "face/fap.h"
#include "face/fap_track.h"
#include "face/visemes.h"

namespace th::avatar {

// What drives a character each frame.
struct AvatarInput {
  std::array<float, 52> arkit{};  // formats::kArkitNames' order
  bool hasVisemes = false;
  std::array<float, face::kNumOculusVisemes> oculus{};
  std::array<float, 5> vrm{};                             // A I U E O
  Eigen::Vector3d headDegrees = Eigen::Vector3d::Zero();  // pitch, yaw, roll
};

// From a frame's FAPs (ARKit's weights at the default scale, the head from FAPs 48–50) and, where there are
// any, the mouth classes' probabilities (face::kNumMouthClasses; null: no visemes).
AvatarInput avatarInputOf(const face::FapFrame& faps, const float* classProbabilities);
// The same at a time of an animation: its FAPs there, and the visemes of its frame nearest in time where it
// has visemes.
AvatarInput avatarInputAt(const face::FapTrack& animation, double seconds);

}  // namespace th::avatar
