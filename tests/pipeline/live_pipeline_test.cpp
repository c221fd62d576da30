// The live pipeline's supervision, without a sound card: a looped recording starts a pass (and counts it as a
// source opened) each time it ends; a sound input that will not open is counted as never opened and is
// given up after giveUpSeconds with a failure that says why.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "audio/media_audio.h"
#include "core/data_path.h"
#include "pipeline/animation_models.h"
#include "pipeline/live.h"

namespace {

using th::pipeline::AnimationFrame;
using th::pipeline::LivePipeline;
using th::pipeline::LivePipelineOptions;
using th::pipeline::LiveSource;

std::shared_ptr<const th::pipeline::AnimationModels> shippedModels() {
  static const auto models = std::make_shared<const th::pipeline::AnimationModels>(th::pipeline::loadAnimationModels(
      th::pipeline::shippedModel("head.json"), th::pipeline::shippedModel("mouth_live.json")));
  return models;
}

std::vector<float> speech(double seconds) {
  const auto clip = th::audio::readRecording(th::sharedDataPath("beat2/audio_only/2_scott_0_4_4.wav"));
  return {clip.samples.begin(), clip.samples.begin() + static_cast<long>(seconds * clip.sampleRateHz)};
}

// Supervises and drains frames until `until` holds or `patience` runs out; returns the frames taken.
template <typename Condition>
int superviseUntil(LivePipeline& live, Condition until, std::chrono::seconds patience) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  int frames = 0;
  AnimationFrame frame;
  while (!until() && std::chrono::steady_clock::now() < deadline) {
    live.supervise();
    while (live.nextFrame(frame)) ++frames;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return frames;
}

TEST(LivePipeline, ALoopedRecordingOpensOncePerPassAndEndsWhenItsInputEnds) {
  LivePipelineOptions options;
  options.loop = true;
  options.speed = 0.0;  // as fast as the worker takes it
  LivePipeline live(shippedModels(), LiveSource{.recording = speech(1.0), .name = "speech.wav", .device = {}}, options);
  const int frames = superviseUntil(
      live, [&] { return live.passes() >= 3; }, std::chrono::seconds(120));
  ASSERT_GE(live.passes(), 3) << "the recording did not loop";
  EXPECT_EQ(live.sourcesOpened(), static_cast<std::uint64_t>(live.passes()));
  EXPECT_EQ(live.sessionsStarted(), static_cast<std::uint64_t>(live.passes()));
  EXPECT_EQ(live.sourcesLost(), 0U);
  EXPECT_GT(frames, 30) << "two whole passes of a second each give frames";
  EXPECT_FALSE(live.done()) << "a loop runs until its input is ended";
  live.endInput();
  superviseUntil(
      live, [&] { return live.done(); }, std::chrono::seconds(60));
  EXPECT_TRUE(live.done());
  EXPECT_TRUE(live.failure().empty()) << live.failure();
}

TEST(LivePipeline, AnInputThatWillNotOpenIsGivenUpAfterGiveUpSecondsAndNeverCountedOpen) {
  LivePipelineOptions options;
  options.retrySeconds = 0.1;
  options.giveUpSeconds = 0.5;
  // No machine has sound input 100000: PortAudio refuses it (or has no devices at all).
  LivePipeline live(shippedModels(), LiveSource{.recording = {}, .name = "", .device = 100000}, options);
  superviseUntil(
      live, [&] { return live.done(); }, std::chrono::seconds(60));
  ASSERT_TRUE(live.done()) << "never gave up";
  EXPECT_NE(live.failure().find("no sound input for"), std::string::npos) << live.failure();
  EXPECT_FALSE(live.sourceError().empty());
  EXPECT_EQ(live.sourcesOpened(), 0U);
  EXPECT_EQ(live.sourcesLost(), 0U) << "nothing was open to be lost";
  EXPECT_FALSE(live.running());
}

}  // namespace
