// A recording in, MPEG-4 FAP curves out: the head model (prosody → FAPs 48–50) and the mouth model (MFCC →
// jaw opening → FAP 3 and the lip FAPs), batch or in their streaming forms, at the models' 30 frames/s.
//
//   th::animation::HeadModel head = th::animation::loadHeadModel("models/head.json");
//   th::animation::MouthModel mouth = th::animation::loadMouthModel("models/mouth.json");
//   th::face::FapTrack anim = th::animation::animate(clip.samples, &head, &mouth, {});
//   th::formats::writeAnimation("speech.fap", anim);
//
// Frame i is at i / 30 s for both parts (the feature extractor centres frame i there). A null model leaves its
// FAPs out. Head rotations are relative to the model's mean pose (the face's rest pose looks ahead). With idle
// on, the eyelid and eyeball FAPs (19, 20, 23–26) carry blinks and gaze shifts and the head rests in silence.
// Thread contract: a pure function; models are shared read-only.
#pragma once

#include <span>

#include "animation/head_model.h"
#include "animation/idle_motion.h"
#include "animation/mouth_model.h"
#include "formats/animation_format.h"

namespace th::animation {

struct AnimateOptions {
  HeadSynthesisOptions head = {};    // variant; maxLagFrames ≥ 0 for the online (fixed-lag) decoder
  MouthSynthesisOptions mouth = {};  // method; windowFrames > 0 for the streaming inversion
  bool idle = true;             // blinks, gaze shifts and the head at rest in silence (idle_motion.h)
  IdleMotionOptions idleOptions = {};
};

inline constexpr double kAnimationFramesPerSecond = 30.0;
static_assert(kAnimationFramesPerSecond == kMouthFramesPerSecond, "the mouth's frames are the animation's");

// samples16k: mono at 16 kHz. Throws th::Error if both models are null, the mouth model drives no FAPs (no
// FAP map and no visual FAPs), or the recording is shorter than one frame.
face::FapTrack animate(std::span<const float> samples16k, const HeadModel* head, const MouthModel* mouth,
                         const AnimateOptions& options = {});

}  // namespace th::animation
