// What the live pipeline's worker hands to the display: one animation frame (FAPs and what the panel plots),
// and the interface of the decoder that makes them from speech.
//
// Thread contract: an AnimationFrame is a value; a FrameDecoder belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>

#include "face/fap.h"
#include "face/visemes.h"

namespace th::pipeline {

struct AnimationFrame {
  int index = 0;             // frame number from the start of the stream
  double timeSeconds = 0.0;  // index / frames per second: the speech this frame shows
  // Head (48–50: the head's rotation, face::headDegreesOf gives it in degrees), jaw (3) and lip FAPs; the rest 0.
  face::FapFrame faps{};
  // The frame whose prosody the head and F0 show: index, or index - the decoder's head delay when the head is
  // shown late (negative: no head yet, the rest pose).
  int prosodyIndex = 0;
  double f0Hz = 0.0;        // of frame prosodyIndex (0: unvoiced), for plots
  double energy = 0.0;      // normalised log energy of this frame
  double levelDb = -140.0;  // its level before normalisation, dB re full scale (idle motion's speech gate)
  // The head model's state posteriors at frame prosodyIndex (its forward filter: P(state | prosody so far)),
  // the first headStates of them; for the panel's plot.
  static constexpr int kMaxHeadStates = 32;
  std::array<float, kMaxHeadStates> headPosterior{};
  int headStates = 0;
  // The mouth model's: P(state | audio up to this frame) under its audio marginal.
  static constexpr int kMaxMouthStates = 16;
  std::array<float, kMaxMouthStates> mouthPosterior{};
  int mouthStates = 0;
  // The viseme model's, where the decoder has one: the mouth classes' probabilities and the class shown
  // (face/visemes.h), of frame visemeIndex, the newest it has decided by this frame (visemeIndex < 0: none yet).
  std::array<float, face::kNumMouthClasses> visemeProbabilities{};
  int mouthClass = face::kSilence;
  int visemeIndex = -1;
  // Steady-clock times (ns) set by the live session: when the worker had read the input that released this
  // frame, and when the frame left the decoder.
  std::int64_t inputReadNs = 0;
  std::int64_t decodedNs = 0;
};

// Speech (16 kHz mono) in as a stream, frames out in order.
class FrameDecoder {
 public:
  virtual ~FrameDecoder() = default;
  virtual void acceptWaveform(std::span<const float> samples16k) = 0;
  virtual void inputFinished() = 0;
  virtual bool next(AnimationFrame& frame) = 0;  // the next frame, if ready
};

}  // namespace th::pipeline
