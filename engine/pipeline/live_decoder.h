// Speech in, animation frames out, as a stream: what the live pipeline's worker thread runs.
//
//   th::pipeline::LiveDecoder decoder(&head, &mouth, {});      // models from animation/head_model.h, mouth_model.h
//   decoder.acceptWaveform(chunk);                             // 16 kHz mono, chunks of any size
//   th::pipeline::AnimationFrame frame;
//   while (decoder.next(frame)) show(frame);                   // in order, frame i at i / 30 s
//   decoder.inputFinished();                                   // then the last frames
//
// One feature extractor (running energy normalisation, no context: the mouth model stacks its own) feeds both
// models: prosody → the head model's online decoder → rotations → FAPs 48–50; MFCC → the mouth model's
// streaming inversion → jaw opening → FAP 3 and the lip FAPs. A frame is out once both parts have it. The
// values are those of animation::animate() with the same online options on the whole recording, frame for
// frame (tests/pipeline). A null model leaves its FAPs at 0.
//
// Thread contract: one thread per instance; the models are shared read-only and must outlive it.
#pragma once

#include <deque>
#include <memory>
#include <span>

#include "animation/head_model.h"
#include "animation/mouth_model.h"
#include "animation/prosody.h"
#include "audio/resampler.h"
#include "features/online_features.h"
#include "pipeline/animation_frame.h"

namespace th::pipeline {

struct LiveDecoderOptions {
  // Online decoding: Viterbi with a bounded lag, then the smooth trajectory through the decided states.
  animation::HeadSynthesisOptions head{.variant = animation::HeadVariant::kTrajectory, .maxLagFrames = 6};
  // Inversion on short windows: the window is look-ahead.
  animation::MouthSynthesisOptions mouth{.method = animation::MouthMethod::kInversion, .windowFrames = 2, .maxIterations = 20};
};

// How far past a frame's time the input must reach before the frame is out, part by part.
struct DecoderLookahead {
  double featuresMs = 0.0;  // the extractor's (F0, MFCC window, deltas)
  int headFrames = 0;       // the head decoder's lag and trajectory look-ahead
  int mouthFrames = 0;      // the MFCC context and the inversion window
  double totalMs = 0.0;     // features + the slower of head and mouth
};

class LiveDecoder : public FrameDecoder {
 public:
  // Throws th::Error if both models are null, the mouth model has no FAP map, or an option cannot stream
  // (a batch head, maxLagFrames < 0, or a mouth window below 1).
  LiveDecoder(const animation::HeadModel* head, const animation::MouthModel* mouth, const LiveDecoderOptions& options);
  ~LiveDecoder() override;
  LiveDecoder(const LiveDecoder&) = delete;
  LiveDecoder& operator=(const LiveDecoder&) = delete;

  void acceptWaveform(std::span<const float> samples16k) override;
  void inputFinished() override;
  bool next(AnimationFrame& frame) override;  // the next frame, if ready

  DecoderLookahead lookahead() const;
  const LiveDecoderOptions& options() const { return options_; }
  std::vector<int> fapNumbers() const;  // the FAPs the frames set, in FAP order (as animate()'s columns)

 private:
  void pull();

  const animation::HeadModel* head_;
  const animation::MouthModel* mouth_;
  LiveDecoderOptions options_;
  features::OnlineFeatureExtractor extractor_;
  animation::ProsodyTracker prosody_;
  std::unique_ptr<animation::HeadSynthesiser> headStream_;
  std::unique_ptr<animation::MouthSynthesiser> mouthStream_;
  std::vector<int> mouthFaps_;  // the mouth model's FAP numbers, in its map's order
  std::vector<float> row_;
  int featureFrames_ = 0;  // rows taken from the extractor
  int headTaken_ = 0;      // rotations taken from the head synthesiser
  std::deque<AnimationFrame> pending_;  // frames with their features, waiting for head and mouth
  std::deque<Eigen::Vector3d> rotations_;
  std::deque<double> jaws_;
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

}  // namespace th::pipeline
