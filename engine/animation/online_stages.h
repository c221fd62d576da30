// The animation's streaming stages in the one shape of online_stage.h: the head from prosody, the mouth from
// speech, the visemes from speech or from the mouth network, and the mouth network itself. Each wraps the
// stream that does its math (HeadSynthesiser, MouthSynthesiser, VisemeStream, MouthNetworkStream) and keeps
// its ready frames until forgotten, so that a consumer reads them by index as from a feature extractor.
//
//   th::animation::HeadStage head(model, {.variant = HeadVariant::kTrajectory, .maxLagFrames = 2});
//   head.accept({prosody, voiced});
//   for (th::animation::HeadFrame out; next < head.numFramesReady(); ++next) head.getFrame(next, out);
//
// The latency of each, in its input frames (online_stage.h):
//   HeadStage                 maxLagFrames + trajectoryLookaheadFrames (the trajectory variant), or maxLagFrames
//   MouthStage                the model's future context tf + windowFrames - 1
//   VisemeStage               the model's context tc + lagFrames
//   MouthNetworkStage         futureSubframes, in subframes past the frame's centre (three subframes a frame)
//   ArticulationVisemeStage   lagFrames
// Thread contract: one thread per stage; the models must outlive it.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "animation/articulation.h"
#include "animation/head_model.h"
#include "animation/mouth_model.h"
#include "animation/mouth_network.h"
#include "animation/online_stage.h"
#include "animation/viseme_model.h"
#include "core/frame_store.h"

namespace th::animation {

// A speech frame: its level before normalisation (dB re full scale) and its c1..cN.
struct SpeechFrame {
  double levelDb = 0.0;
  Eigen::VectorXd mfcc;
};

// A prosody frame (ProsodyTracker's [pitch, energy, Δpitch, Δenergy]) and whether it is voiced.
struct ProsodyFrame {
  Eigen::Vector4d prosody = Eigen::Vector4d::Zero();
  bool voiced = false;
};

struct HeadFrame {
  Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero();  // relative to the mean pose
  // P(state | the prosody up to this frame): the forward filter, for a display of the model's belief (the
  // rotation waits for the decoder's lag; this does not).
  Eigen::VectorXd filteredPosterior;
};

struct MouthFrame {
  Eigen::VectorXd components;  // K visual components (mouthFapsOf turns them into FAPs)
  // P(state | audio up to this frame) under the model's audio marginal (its forward filter), for a display.
  Eigen::VectorXd posterior;
};

class HeadStage : public OnlineStage<ProsodyFrame, HeadFrame> {
 public:
  HeadStage(const HeadModel& model, const HeadSynthesisOptions& options);  // maxLagFrames >= 0
  void accept(const ProsodyFrame& frame) override;
  void inputFinished() override;
  int numFramesReady() const override;
  void getFrame(int frame, HeadFrame& out) const override;
  void forgetBefore(int frame) override;
  int latencyFrames() const override;
  std::size_t framesHeld() const override;
  int numStates() const;

 private:
  HeadSynthesiser synthesiser_;
  FrameStore<Eigen::VectorXd> posteriors_;  // of frames accepted and not forgotten
};

class MouthStage : public OnlineStage<SpeechFrame, MouthFrame> {
 public:
  MouthStage(const MouthModel& model, const MouthSynthesisOptions& options);  // windowFrames >= 1
  void accept(const SpeechFrame& frame) override;
  void inputFinished() override;
  int numFramesReady() const override { return static_cast<int>(ready_.size()); }
  void getFrame(int frame, MouthFrame& out) const override;
  void forgetBefore(int frame) override;
  int latencyFrames() const override { return synthesiser_.lookaheadFrames(); }
  std::size_t framesHeld() const override { return ready_.held() + static_cast<std::size_t>(latencyFrames()); }
  int numStates() const { return synthesiser_.numStates(); }

 private:
  void take();

  MouthSynthesiser synthesiser_;
  FrameStore<MouthFrame> ready_;
};

// Visemes from speech frames by the viseme model.
class VisemeStage : public OnlineStage<SpeechFrame, VisemeFrame> {
 public:
  VisemeStage(const VisemeModel& model, int lagFrames);
  void accept(const SpeechFrame& frame) override;
  void inputFinished() override;
  int numFramesReady() const override { return static_cast<int>(ready_.size()); }
  void getFrame(int frame, VisemeFrame& out) const override;
  void forgetBefore(int frame) override;
  int latencyFrames() const override { return stream_.latencyFrames(); }
  std::size_t framesHeld() const override { return ready_.held() + static_cast<std::size_t>(latencyFrames()); }

 private:
  void take();

  VisemeStream stream_;
  FrameStore<VisemeFrame> ready_;
  bool finished_ = false;
};

// The mouth network on speech subframes (c1..c13 and the level at 90 a second, subframeFeatureOptions()).
class MouthNetworkStage : public OnlineStage<SpeechFrame, MouthNetworkFrame> {
 public:
  explicit MouthNetworkStage(const MouthNetwork& model);
  void accept(const SpeechFrame& subframe) override;
  void inputFinished() override;
  int numFramesReady() const override { return static_cast<int>(ready_.size()); }
  void getFrame(int frame, MouthNetworkFrame& out) const override;
  void forgetBefore(int frame) override;
  int latencyFrames() const override { return model_.futureSubframes; }
  int inputFramesPerFrame() const override { return kSubframesPerFrame; }
  std::size_t framesHeld() const override;

 private:
  void take();

  const MouthNetwork& model_;
  MouthNetworkStream stream_;
  FrameStore<MouthNetworkFrame> ready_;
};

// The articulation's visemes: the network's class posteriors over its class priors, scaled by evidenceScale, as
// evidence for the class HMM of its training labels (articulation.h), decoded with a fixed lag.
class ArticulationVisemeStage : public OnlineStage<MouthNetworkFrame, VisemeFrame> {
 public:
  ArticulationVisemeStage(const MouthNetwork& model, const ArticulationOptions& options, int lagFrames);
  void accept(const MouthNetworkFrame& frame) override;
  void inputFinished() override;
  int numFramesReady() const override { return static_cast<int>(ready_.size()); }
  void getFrame(int frame, VisemeFrame& out) const override;
  void forgetBefore(int frame) override;
  int latencyFrames() const override { return stream_->latencyFrames(); }
  std::size_t framesHeld() const override { return ready_.held() + static_cast<std::size_t>(latencyFrames()); }

 private:
  void take();

  double evidenceScale_;
  hmm::HmmModel classes_;
  Eigen::VectorXd logPriors_;
  std::unique_ptr<VisemeStream> stream_;  // reads classes_
  FrameStore<VisemeFrame> ready_;
  bool finished_ = false;
};

}  // namespace th::animation
