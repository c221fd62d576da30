// What the two speech models hear of a recording, computed in one pass of the feature extractor: the prosody
// and voicing the head model decodes (prosody.h) and the MFCCs and level the mouth model inverts
// (mouth_data.h). The offline pipeline and the head corpora use it; the live decoder runs two extractors
// instead, so that the mouth need not wait for the pitch tracker's decision lag (pipeline/live_decoder.h).
//
//   const th::animation::SpeechAnalysis heard = th::animation::analyseSpeech(clip.samples);
//   Eigen::MatrixXd rotations = th::animation::synthesiseHead(head, heard.prosody, heard.voiced, {});
//   Eigen::MatrixXd mouth = th::animation::synthesiseMouth(model, heard.speech, {});
//
// Frame i is at i / 30 s in every part (the extractor centres frame i there); all parts have the same frames.
// Thread contract: a pure function.
#pragma once

#include <Eigen/Core>
#include <span>

#include "animation/mouth_data.h"
#include "animation/prosody.h"

namespace th::animation {

// The rate of every animation the models make: the mouth's and the head's frames.
inline constexpr double kAnimationFramesPerSecond = 30.0;
static_assert(kAnimationFramesPerSecond == kMouthFramesPerSecond, "the mouth's frames are the animation's");

struct SpeechAnalysis {
  Eigen::MatrixXd prosody;    // 4 x T: ProsodyTracker's pitch, energy and their deltas
  Eigen::RowVectorXd voiced;  // T: 1 where the pitch tracker found a voice, else 0
  SpeechFrames speech;        // c1..c11 and the level, T frames
  int numFrames() const { return static_cast<int>(prosody.cols()); }
};

// samples16k: mono at 16 kHz.
SpeechAnalysis analyseSpeech(std::span<const float> samples16k, const ProsodyOptions& options = {});

}  // namespace th::animation
