// The animation's stages against the contract of online_stage.h, each with a shipped model on made-up input:
// frame i is ready once input i·r + latencyFrames() has come (exactly, for the stages that never decide
// sooner), ready frames are read by index until forgotten and not after, what a stage holds does not grow with
// the stream, and inputFinished() readies the rest.
#include "animation/online_stages.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "made_up_speech.h"

namespace {

using namespace th::animation;

std::string modelPath(const char* name) {
  return std::string(TALKINGHEAD_SOURCE_DIR) + "/models/" + name;
}

template <typename In, typename Out>
void checkContract(OnlineStage<In, Out>& stage, const std::vector<In>& inputs, bool exact) {
  const int perFrame = stage.inputFramesPerFrame();
  const int latency = stage.latencyFrames();
  const auto accepted = static_cast<int>(inputs.size());
  Out out;
  int read = 0;
  std::size_t heldMidway = 0;
  for (int n = 1; n <= accepted; ++n) {
    stage.accept(inputs[static_cast<std::size_t>(n - 1)]);
    // Frame i is due once input frame i·r + latency (the n-th input is frame n - 1) has come.
    const int due = n - 1 >= latency ? (n - 1 - latency) / perFrame + 1 : 0;
    const int ready = stage.numFramesReady();
    if (exact) {
      ASSERT_EQ(ready, due) << "after " << n << " inputs";
    } else {
      ASSERT_GE(ready, due) << "after " << n << " inputs";
      ASSERT_LE(ready, (n - 1) / perFrame + 1) << "no frame before its own input";
    }
    for (; read < ready; ++read) stage.getFrame(read, out);
    stage.forgetBefore(read + 5);  // frames not yet ready are not forgotten: they are read when they are
    if (read > 0) {
      EXPECT_THROW(stage.getFrame(read - 1, out), th::Error) << "forgotten";
    }
    if (n == accepted / 2) heldMidway = stage.framesHeld();
  }
  EXPECT_THROW(stage.getFrame(stage.numFramesReady(), out), th::Error) << "not ready";
  if (latency > 0) {
    EXPECT_GT(heldMidway, 0U) << "its look-ahead";
  }
  EXPECT_LE(stage.framesHeld(), heldMidway + 2) << "no growth with the stream's length";
  stage.inputFinished();
  stage.inputFinished();
  const int all = (accepted + perFrame - 1) / perFrame;
  ASSERT_EQ(stage.numFramesReady(), all) << "the end of the input readies the rest";
  for (; read < all; ++read) stage.getFrame(read, out);
  EXPECT_THROW(stage.accept(inputs.front()), th::Error) << "input after its end";
}

using th::test::madeUpSpeech;

TEST(OnlineStages, HeadStage) {
  const HeadModel model = loadHeadModel(modelPath("head.json"));
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<ProsodyFrame> prosody(900);
  for (std::size_t t = 0; t < prosody.size(); ++t)
    prosody[t] = {.prosody = Eigen::Vector4d::NullaryExpr([&] { return noise(random); }), .voiced = t % 40 < 30};
  for (const HeadVariant variant : {HeadVariant::kStateMeans, HeadVariant::kTrajectory}) {
    HeadStage stage(model, {.variant = variant, .maxLagFrames = kLiveHeadLagFrames});
    EXPECT_EQ(stage.latencyFrames(), kLiveHeadLagFrames + (variant == HeadVariant::kTrajectory ? 3 : 0));
    // The online Viterbi decoder may decide sooner than its lag.
    checkContract(stage, prosody, false);
    HeadFrame frame;
    stage.getFrame(stage.numFramesReady() - 1, frame);
    EXPECT_NEAR(frame.filteredPosterior.sum(), 1.0, 1e-9);
  }
  EXPECT_THROW(HeadStage(model, {.maxLagFrames = -1}), th::Error) << "batch decoding does not stream";
}

TEST(OnlineStages, MouthStage) {
  const MouthModel model = loadMouthModel(modelPath("mouth.json"));
  const std::vector<SpeechFrame> speech = madeUpSpeech(600, 11, 4);
  for (const int window : {1, 3}) {
    MouthStage stage(model, {.method = MouthMethod::kInversion, .windowFrames = window, .maxIterations = 20});
    EXPECT_EQ(stage.latencyFrames(), model.futureContextFrames + window - 1);
    // A window is decided whole when its last frame comes: its first frames wait the longest.
    checkContract(stage, speech, window == 1);
    MouthFrame frame;
    stage.getFrame(stage.numFramesReady() - 1, frame);
    EXPECT_EQ(frame.components.size(), model.basis.components());
    EXPECT_NEAR(frame.posterior.sum(), 1.0, 1e-9);
  }
}

TEST(OnlineStages, VisemeStage) {
  const VisemeModel model = loadVisemeModel(modelPath("visemes.json"));
  VisemeStage stage(model, 2);
  EXPECT_EQ(stage.latencyFrames(), model.contextFrames + 2);
  checkContract(stage, madeUpSpeech(600, static_cast<int>(model.priorMean.size()), 5), true);
}

TEST(OnlineStages, MouthNetworkAndArticulationVisemeStages) {
  const MouthNetwork model = loadMouthNetwork(modelPath("articulation_live.json"));
  const std::vector<SpeechFrame> subframes = madeUpSpeech(3 * 300 + 1, kNetworkMfcc, 6);
  MouthNetworkStage network(model);
  EXPECT_EQ(network.inputFramesPerFrame(), kSubframesPerFrame);
  EXPECT_EQ(network.latencyFrames(), model.futureSubframes);
  checkContract(network, subframes, true);

  // The network's frames, as evidence for the class HMM.
  MouthNetworkStage again(model);
  std::vector<MouthNetworkFrame> heard;
  for (const SpeechFrame& subframe : subframes) again.accept(subframe);
  again.inputFinished();
  heard.resize(static_cast<std::size_t>(again.numFramesReady()));
  for (int i = 0; i < again.numFramesReady(); ++i) again.getFrame(i, heard[static_cast<std::size_t>(i)]);
  for (const int lag : {0, 3}) {
    ArticulationVisemeStage visemes(model, {}, lag);
    EXPECT_EQ(visemes.latencyFrames(), lag);
    checkContract(visemes, heard, true);
  }
  EXPECT_THROW(ArticulationVisemeStage(model, {}, -1), th::Error);
}

}  // namespace
