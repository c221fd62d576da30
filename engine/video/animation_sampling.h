// FAP values of an animation at any time, for rendering at a frame rate other than the animation's.
//
//   th::face::FapValues faps = th::video::fapValuesAt(animation, frame / 25.0);
//
// Linear interpolation between the two nearest frames (frame i is at i / fps); before the first frame the first,
// after the last the last. FAPs the animation does not carry are 0.
// Thread contract: pure function.
#pragma once

#include "face/face_model.h"
#include "video/animation_file.h"

namespace th::video {

face::FapValues fapValuesAt(const Animation& animation, double seconds);

// The animation's length in seconds: numFrames / fps.
double durationOf(const Animation& animation);

}  // namespace th::video
