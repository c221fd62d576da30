#include "outputs/avatar_frame.h"

#include <cmath>

#include "formats/arkit_format.h"

namespace th::outputs {

float AvatarFrame::blinkLeft() const {
  static const int shape = formats::arkitIndex("eyeBlinkLeft");
  return arkit[static_cast<std::size_t>(shape)];
}
float AvatarFrame::blinkRight() const {
  static const int shape = formats::arkitIndex("eyeBlinkRight");
  return arkit[static_cast<std::size_t>(shape)];
}
float AvatarFrame::jawOpen() const {
  static const int shape = formats::arkitIndex("jawOpen");
  return arkit[static_cast<std::size_t>(shape)];
}
float AvatarFrame::smile() const {
  static const int left = formats::arkitIndex("mouthSmileLeft");
  static const int right = formats::arkitIndex("mouthSmileRight");
  return 0.5f * (arkit[static_cast<std::size_t>(left)] + arkit[static_cast<std::size_t>(right)]);
}

float AvatarFrame::frown() const {
  static const int left = formats::arkitIndex("mouthFrownLeft");
  static const int right = formats::arkitIndex("mouthFrownRight");
  return 0.5f * (arkit[static_cast<std::size_t>(left)] + arkit[static_cast<std::size_t>(right)]);
}

Eigen::Quaternionf AvatarFrame::unityHeadRotation() const {
  constexpr double kRadians = 3.14159265358979323846 / 180.0;
  const Eigen::Matrix3d ours = (Eigen::AngleAxisd(headDegrees[1] * kRadians, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(headDegrees[0] * kRadians, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(headDegrees[2] * kRadians, Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  // Unity's x points to the avatar's right, ours to its left: the same rotation seen with x mirrored.
  const Eigen::Matrix3d mirror = Eigen::Vector3d(-1.0, 1.0, 1.0).asDiagonal();
  return Eigen::Quaternionf(Eigen::Quaterniond(Eigen::Matrix3d(mirror * ours * mirror)).cast<float>());
}

AvatarFrame avatarFrameOf(const pipeline::AnimationFrame& frame) {
  AvatarFrame avatar;
  const bool hasVisemes = frame.visemeIndex >= 0;
  static_cast<avatar::AvatarInput&>(avatar) =
      avatar::avatarInputOf(frame.faps, hasVisemes ? frame.visemeProbabilities.data() : nullptr);
  avatar.index = frame.index;
  avatar.timeSeconds = frame.timeSeconds;
  avatar.faps = frame.faps;
  if (hasVisemes) avatar.mouthClass = frame.mouthClass;
  return avatar;
}

}  // namespace th::outputs
