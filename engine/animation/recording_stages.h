// Each animation stage chosen by its options, in the one shape of online_stage.h, so that a whole recording and
// a stream are wired alike (pipeline/offline.cpp, pipeline/live_decoder.h):
//   - with a bounded look-ahead (a decoder's lag ≥ 0, an inversion window ≥ 1 frame), the streaming stage of
//     online_stages.h;
//   - without, the batch decoder that hears the whole input before deciding: a Viterbi path over the whole
//     recording, every frame inverted at once, the network's cepstral mean taken from the whole recording. It is a
//     WholeInputStage: no frame is ready before inputFinished(), every frame is after it.
//
//   std::unique_ptr<th::animation::HeadSource> head = th::animation::makeHeadStage(model, options.head);
//   for (const ProsodyFrame& frame : prosody) head->accept(frame);
//   head->inputFinished();
//   for (int t = 0; t < head->numFramesReady(); ++t) head->getFrame(t, rotation);
//
// Thread contract: one thread per stage; the models must outlive it.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "animation/articulation.h"
#include "animation/online_stages.h"
#include "core/error.h"
#include "core/frame_store.h"

namespace th::animation {

// A WholeInputStage's latencyFrames(): its frames wait for the end of the input, however long.
inline constexpr int kWholeInput = std::numeric_limits<int>::max();

// A batch computation in the stage shape: the input kept until its end, then decided at once by `decide`,
// which returns one output frame per inputFramesPerFrame input frames (rounded up).
template <typename In, typename Out>
class WholeInputStage final : public OnlineStage<In, Out> {
 public:
  using Decide = std::function<std::vector<Out>(const std::vector<In>&)>;

  WholeInputStage(std::string name, Decide decide, int inputFramesPerFrame = 1)
      : name_(std::move(name)), decide_(std::move(decide)), inputFramesPerFrame_(inputFramesPerFrame) {}

  void accept(const In& frame) override {
    if (finished_) throw Error(name_ + ": a frame after the end of the input");
    input_.push_back(frame);
  }
  void inputFinished() override {
    if (finished_) return;
    finished_ = true;
    for (Out& frame : decide_(input_)) ready_.push_back(std::move(frame));
    std::vector<In>().swap(input_);  // decided: the input is no longer held
  }
  int numFramesReady() const override { return static_cast<int>(ready_.size()); }
  void getFrame(int frame, Out& out) const override {
    if (frame < 0 || static_cast<std::size_t>(frame) < ready_.firstKept() ||
        static_cast<std::size_t>(frame) >= ready_.size())
      throw Error(name_ + ": frame " + std::to_string(frame) + " is not held");
    out = ready_[static_cast<std::size_t>(frame)];
  }
  void forgetBefore(int frame) override { ready_.forgetBefore(static_cast<std::size_t>(std::max(frame, 0))); }
  int latencyFrames() const override { return kWholeInput; }
  int inputFramesPerFrame() const override { return inputFramesPerFrame_; }
  std::size_t framesHeld() const override {
    return ready_.held() + input_.size() / static_cast<std::size_t>(inputFramesPerFrame_);
  }

 private:
  std::string name_;  // for errors
  Decide decide_;
  int inputFramesPerFrame_;
  std::vector<In> input_;
  FrameStore<Out> ready_;
  bool finished_ = false;
};

using HeadSource = OnlineStage<ProsodyFrame, HeadFrame>;
using MouthSource = OnlineStage<SpeechFrame, MouthFrame>;
using SpeechVisemeSource = OnlineStage<SpeechFrame, VisemeFrame>;
using MouthNetworkSource = OnlineStage<SpeechFrame, MouthNetworkFrame>;
using ArticulationVisemeSource = OnlineStage<MouthNetworkFrame, VisemeFrame>;

// options.maxLagFrames ≥ 0: HeadStage; < 0: synthesiseHead on the whole recording (its frames carry no
// filtered posterior).
std::unique_ptr<HeadSource> makeHeadStage(const HeadModel& model, const HeadSynthesisOptions& options);
// options.windowFrames ≥ 1: MouthStage; 0: synthesiseMouth on the whole recording (no posterior).
std::unique_ptr<MouthSource> makeMouthStage(const MouthModel& model, const MouthSynthesisOptions& options);
// lagFrames ≥ 0: VisemeStage; < 0: decodeVisemes on the whole recording.
std::unique_ptr<SpeechVisemeSource> makeVisemeStage(const VisemeModel& model, int lagFrames);
// The mouth network on subframes. As a stream (MouthNetworkStage), its running cepstral mean starts at the training
// speech's; with ownMean, at the whole recording's mean, which needs the whole recording first.
std::unique_ptr<MouthNetworkSource> makeMouthNetworkStage(const MouthNetwork& model, bool ownMean);
// lagFrames ≥ 0: ArticulationVisemeStage; < 0: networkVisemes on the whole recording.
std::unique_ptr<ArticulationVisemeSource> makeArticulationVisemeStage(const MouthNetwork& model,
                                                                      const ArticulationOptions& options,
                                                                      int lagFrames);

// Every frame of `input` through `stage`, then the end of the input: the frames it decided, in order.
template <typename In, typename Out>
std::vector<Out> runToEnd(OnlineStage<In, Out>& stage, const std::vector<In>& input) {
  for (const In& frame : input) stage.accept(frame);
  stage.inputFinished();
  std::vector<Out> output(static_cast<std::size_t>(stage.numFramesReady()));
  for (int t = 0; t < stage.numFramesReady(); ++t) stage.getFrame(t, output[static_cast<std::size_t>(t)]);
  return output;
}

}  // namespace th::animation
