// Speech in, animation frames out, as a stream: what the live pipeline's worker thread runs.
//
//   th::pipeline::LiveDecoder decoder(&head, &mouth, {});      // models from animation/head_model.h, mouth_model.h
//   decoder.acceptWaveform(chunk);                             // 16 kHz mono, chunks of any size
//   th::pipeline::AnimationFrame frame;
//   while (decoder.next(frame)) show(frame);                   // in order, frame i at i / 30 s
//   decoder.inputFinished();                                   // then the last frames
//
// Wiring only: each model runs as a stage of animation/online_stages.h (frames in, frames out, one streaming shape),
// and the decoder feeds each stage the frames of its source it has not had yet, then reads what the stages have decided
// by index. Two feature extractors run on the same samples: the prosody one (F0, energy, deltas) feeds the head stage →
// rotations → FAPs 48–50; an MFCC-only one (no pitch tracker to wait for) feeds the mouth stage (the streaming
// inversion) → jaw opening → FAP 3 and the lip FAPs. The head waits ~280 ms for its pitch tracker and its stage's
// latency, the mouth ~50 ms, so by default the mouth sets the pace: frame i carries the mouth of instant i and the head
// (and F0) of frame i - headDelayFrames, decided by then (lookahead() adds up the extractors' look-ahead and the
// stages' latencyFrames()). With `waitForHead`, a frame waits for its own head instead, and the frames are those of
// pipeline::animate() with the same online options, frame for frame (tests/pipeline). A null model leaves its FAPs at
// 0. With a viseme model, the MFCC extractor also feeds its stage, and each frame carries the newest visemes decided.
// With an articulation (animation/articulation.h), a third extractor (90 frames a second) feeds the mouth network's
// stage, whose frames feed the articulation's viseme stage, and each frame waits for its own class, so that its lips
// are closed on PP and raised on FF as offline: the face and the visemes say the same thing on every frame.
//
// Thread contract: one thread per instance; the models are shared read-only and must outlive it.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "animation/articulation.h"
#include "animation/head_model.h"
#include "animation/mouth_model.h"
#include "animation/online_stages.h"
#include "animation/prosody.h"
#include "animation/viseme_model.h"
#include "audio/resampler.h"
#include "features/online_features.h"
#include "pipeline/animation_frame.h"
#include "pipeline/animation_models.h"

namespace th::pipeline {

struct LiveDecoderOptions {
  // Online decoding: Viterbi with a bounded lag, then the smooth trajectory through the decided states.
  animation::HeadSynthesisOptions head{.variant = animation::HeadVariant::kTrajectory,
                                       .maxLagFrames = animation::kLiveHeadLagFrames};
  // Inversion on short windows: the window is look-ahead (pipeline/live_presets.h: 1 in the default preset).
  animation::MouthSynthesisOptions mouth{
      .method = animation::MouthMethod::kInversion, .windowFrames = 1, .maxIterations = 20};
  // false: frames out as soon as the mouth is decided, the head shown headDelayFrames late (lips need sync,
  // head motion tolerates a third of a second); true: each frame waits for its own head (file playback, where
  // the sound can be delayed to match).
  bool waitForHead = false;
  // The F0 search range of the prosody features (a voice outside the default 60-500 Hz, or one to hold tighter).
  double minF0Hz = features::PitchOptions{}.minF0Hz;
  double maxF0Hz = features::PitchOptions{}.maxF0Hz;
  // The viseme stream's decision lag beyond its context (animation/viseme_model.h). A frame never waits for its
  // visemes: it carries the newest decided (visemeIndex), a frame or two behind the mouth.
  int visemeLagFrames = 2;
  // The articulation's class decoding: its decision lag (frames, beyond the network's look-ahead), and how it
  // weighs the network and closes the lips.
  int articulationLagFrames = 0;
  animation::ArticulationOptions articulation{};
};

// How far past a frame's time the input must reach before the frame is out, part by part.
struct DecoderLookahead {
  double featuresMs = 0.0;       // the prosody extractor's (F0 decision lag, MFCC window, deltas)
  double mouthFeaturesMs = 0.0;  // the MFCC extractor's (half its window)
  double articulationMs = 0.0;   // the articulation's: half its window, the network's look-ahead, its lag
  int headFrames = 0;            // the head decoder's lag and trajectory look-ahead
  int mouthFrames = 0;           // the MFCC context and the inversion window
  double headMs = 0.0;           // features + head frames: when a frame's own head is decided
  double mouthMs = 0.0;          // mouth features + mouth frames, or the articulation's if later: when its mouth is
  int headDelayFrames = 0;       // how late the head is shown (0 with waitForHead)
  double totalMs = 0.0;          // what a frame waits for in all
};

class LiveDecoder : public FrameDecoder {
 public:
  // Throws th::Error if both models are null, the mouth model drives no FAPs (no FAP map and no visual FAPs), or an
  // option cannot stream (a batch head, maxLagFrames < 0, or a mouth window below 1).
  LiveDecoder(const animation::HeadModel* head, const animation::MouthModel* mouth, const LiveDecoderOptions& options,
              const animation::VisemeModel* visemes = nullptr, const animation::MouthNetwork* articulation = nullptr);
  ~LiveDecoder() override;
  LiveDecoder(const LiveDecoder&) = delete;
  LiveDecoder& operator=(const LiveDecoder&) = delete;

  void acceptWaveform(std::span<const float> samples16k) override;
  void inputFinished() override;
  bool next(AnimationFrame& frame) override;  // the next frame, if ready

  DecoderLookahead lookahead() const;
  const LiveDecoderOptions& options() const { return options_; }
  std::vector<int> fapNumbers() const;  // the FAPs the frames set, in FAP order (as animate()'s columns)
  // Frames' worth of data held in all its parts: bounded, however long the stream (only the recent frames
  // each stage looks back at are kept).
  std::size_t framesHeld() const;

 private:
  void pull();
  bool readsMouthExtractor() const { return mouth_ != nullptr || speechVisemes_ != nullptr; }

  const animation::MouthModel* mouth_;
  const animation::MouthNetwork* articulation_ = nullptr;
  LiveDecoderOptions options_;
  // The features: prosody rows for the head (and each frame's F0), MFCCs for the mouth and the viseme model,
  // subframes for the articulation's network. Frames are read again by index until shown.
  features::OnlineFeatureExtractor prosodyExtractor_;
  features::OnlineFeatureExtractor mouthExtractor_;
  std::unique_ptr<features::OnlineFeatureExtractor> networkExtractor_;
  animation::ProsodyTracker prosody_;
  // The stages (animation/online_stages.h); the visemes come from the viseme model or from the network.
  std::unique_ptr<animation::HeadStage> headStage_;
  std::unique_ptr<animation::MouthStage> mouthStage_;
  std::unique_ptr<animation::MouthNetworkStage> networkStage_;
  std::unique_ptr<animation::VisemeStage> speechVisemes_;
  std::unique_ptr<animation::ArticulationVisemeStage> networkVisemes_;
  animation::OnlineFrameSource<animation::VisemeFrame>* visemes_ = nullptr;  // whichever of the two there is
  // How far each stage has been fed: prosody rows, MFCC frames, subframes, network frames.
  int prosodyRows_ = 0;
  int mfccFrames_ = 0;
  int subframes_ = 0;
  int networkFrames_ = 0;
  std::vector<int> mouthFaps_;  // the mouth model's FAP numbers, in its map's order
  int headDelayFrames_ = 0;
  // Frames read and passed on, kept so that their storage is reused from frame to frame.
  std::vector<float> row_;
  std::vector<float> mfcc_;
  animation::SpeechFrame speech_;
  animation::MouthNetworkFrame heard_;
  animation::HeadFrame head_;
  animation::MouthFrame mouthFrame_;
  animation::VisemeFrame visemeFrame_;
  bool finished_ = false;
  int nextIndex_ = 0;  // the next frame out
};

// A decoder behind a sample-rate converter, for a device that will not run at 16 kHz: samples at
// `inputRateHz` in, converted (libsoxr, streaming) and passed on.
class ResamplingDecoder : public FrameDecoder {
 public:
  ResamplingDecoder(std::unique_ptr<FrameDecoder> inner, double inputRateHz);
  ~ResamplingDecoder() override;
  void acceptWaveform(std::span<const float> samples) override;
  void inputFinished() override;
  bool next(AnimationFrame& frame) override { return inner_->next(frame); }

 private:
  std::unique_ptr<FrameDecoder> inner_;
  std::unique_ptr<audio::Resampler> resampler_;
  std::vector<float> converted_;
};

// A stream's decoder as live and the C library's streams run it: a LiveDecoder that keeps its models alive (it
// may outlive what loaded them: live's worker runs the old decoder until it takes a new one, a library stream
// outlives its models handle), behind a ResamplingDecoder unless the input is at 16 kHz.
struct StreamDecoder {
  std::unique_ptr<FrameDecoder> decoder;
  DecoderLookahead lookahead;  // the LiveDecoder's
  std::vector<int> fapNumbers;
};
// Throws th::Error for null models or options the decoder rejects.
StreamDecoder makeStreamDecoder(std::shared_ptr<const AnimationModels> models, const LiveDecoderOptions& options,
                                double inputRateHz);

}  // namespace th::pipeline
