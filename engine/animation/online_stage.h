// One streaming shape for the animation's stages, frames in and frames out: Kaldi's online feature interface
// (src/itf/online-feature-itf.h: NumFramesReady, GetFrame; its base features' AcceptWaveform, InputFinished)
// with a frame in place of the waveform, so that a consumer wires stages together the same way whatever they do.
//
//   th::animation::MouthStage mouth(model, options);          // an OnlineStage<SpeechFrame, MouthFrame>
//   mouth.accept(speechFrame);                                // each input frame, in order
//   th::animation::MouthFrame out;
//   for (; next < mouth.numFramesReady(); ++next) mouth.getFrame(next, out);
//   mouth.forgetBefore(next);                                 // frames before `next` will not be read again
//   mouth.inputFinished();                                    // then the last frames are ready
//
// Output frame i is centred on input frame inputFramesPerFrame() · i (1 for every stage but the mouth network,
// which hears three speech subframes per animation frame). latencyFrames() is the stage's look-ahead: frame i is
// ready once input frames up to inputFramesPerFrame() · i + latencyFrames() have been accepted, or the input has
// finished. Some stages can decide a frame sooner, never later: an online Viterbi decoder whose paths merged
// early, an inversion window decided whole when its last frame arrives. Consumers add these up for audio/video sync
// (pipeline/live_decoder.h). Ready frames stay readable, in any order, until forgetBefore() drops them: what a stage
// holds is its look-ahead and the ready frames not yet forgotten, however long the stream. Thread contract: one thread
// per stage.
#pragma once

#include <cstddef>

namespace th::animation {

// The output side: what a consumer reads.
template <typename Out>
class OnlineFrameSource {
 public:
  OnlineFrameSource() = default;
  virtual ~OnlineFrameSource() = default;
  OnlineFrameSource(const OnlineFrameSource&) = delete;  // a stage holds the state of one stream
  OnlineFrameSource& operator=(const OnlineFrameSource&) = delete;

  virtual int numFramesReady() const = 0;
  // firstKept <= frame < numFramesReady(); throws th::Error for a frame not held.
  virtual void getFrame(int frame, Out& out) const = 0;
  // Frames before `frame` will not be read again and are freed (a frame not yet ready is never forgotten).
  virtual void forgetBefore(int frame) = 0;
  virtual int latencyFrames() const = 0;
  virtual int inputFramesPerFrame() const { return 1; }
  // Frames' worth of data held: the look-ahead waiting to be decided and the ready frames not yet forgotten.
  virtual std::size_t framesHeld() const = 0;
};

// A stage: frames in, in order, then the end of the input.
template <typename In, typename Out>
class OnlineStage : public OnlineFrameSource<Out> {
 public:
  virtual void accept(const In& frame) = 0;  // throws th::Error after inputFinished()
  virtual void inputFinished() = 0;          // every frame still waiting is decided; a second call does nothing
};

}  // namespace th::animation
