// One frame as avatar programs take it: what the live outputs (VMC, OSC, VTube Studio) and the C library's
// stream hand on, made from the live pipeline's AnimationFrame: a character's weights (avatar::AvatarInput, the
// same a character drawn here is posed with, made by the same avatar::avatarInputOf) with the frame's number,
// time, FAPs and mouth class.
//
//   const th::outputs::AvatarFrame avatar = th::outputs::avatarFrameOf(frame);
//   send(avatar.arkit[17]);                              // jawOpen, 0..1
//   const Eigen::Quaternionf q = avatar.unityHeadRotation();
//
// - ARKit's 52 weights from the frame's FAPs (formats/arkit_format.h, the default scale);
// - the viseme model's probabilities as Oculus's 15 weights and VRM's five vowels (face/visemes.h), zero where
//   the decoder has no viseme model (hasVisemes false);
// - the head's pitch, yaw and roll in degrees (BEAT2's convention: R = Ry(yaw) Rx(pitch) Rz(roll), y up,
//   z forward, +x the speaker's left; pitch down, yaw to the speaker's left and roll to the right positive),
//   and the same rotation in Unity's left-handed frame (x to the avatar's right) as VMC sends it.
// Thread contract: a value; avatarFrameOf is a pure function.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "avatar/avatar_input.h"
#include "face/fap.h"
#include "face/visemes.h"
#include "pipeline/animation_frame.h"

namespace th::outputs {

struct AvatarFrame : avatar::AvatarInput {
  int index = 0;
  double timeSeconds = 0.0;
  face::FapFrame faps{};
  int mouthClass = face::kSilence;  // the class shown (face::MouthClass), where hasVisemes

  float blinkLeft() const;   // ARKit eyeBlinkLeft
  float blinkRight() const;  // eyeBlinkRight
  float jawOpen() const;
  float smile() const;  // the mean of mouthSmileLeft and mouthSmileRight
  float frown() const;  // the mean of mouthFrownLeft and mouthFrownRight
  Eigen::Quaternionf unityHeadRotation() const;
};

AvatarFrame avatarFrameOf(const pipeline::AnimationFrame& frame);

}  // namespace th::outputs
