// th_models through libtalkinghead: streams started on one models handle, on two threads at once, give the frames
// of a stream started alone on a handle of its own, and keep their models after the handle is freed; files
// animated on one handle on two threads are the one animated alone.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "core/data_path.h"
#include "stream_frames.h"
#include "talkinghead/talkinghead.h"
#include "wav_samples.h"

namespace {

using th::test::expectSameFrames;
using th::test::pullAllFrames;

TEST(LibraryModels, StreamsOnOneHandleOnTwoThreadsGiveTheFramesOfAStreamStartedAlone) {
  double rate = 0.0;
  const std::vector<float> samples =
      th::test::readWavSamples(th::sharedDataPath("speech/arctic/arctic_a0001.wav").string(), rate);
  ASSERT_GT(samples.size(), 16000u);
  th_stream_settings settings;
  ASSERT_EQ(th_stream_settings_init(&settings), TH_OK);
  settings.sample_rate_hz = rate;

  th_models* own = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &own), TH_OK) << th_last_error();
  th_stream* alone = nullptr;
  ASSERT_EQ(th_stream_start(own, &settings, &alone), TH_OK) << th_last_error();
  th_models_free(own);
  const std::vector<th_frame> expected = pullAllFrames(alone, samples, 160);
  ASSERT_GT(expected.size(), 60u);

  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_stream* streams[2] = {nullptr, nullptr};
  for (th_stream*& stream : streams) ASSERT_EQ(th_stream_start(models, &settings, &stream), TH_OK);
  th_models_free(models);  // the streams keep the models they use

  std::vector<th_frame> got[2];
  std::thread first([&] { got[0] = pullAllFrames(streams[0], samples, 160); });
  std::thread second([&] { got[1] = pullAllFrames(streams[1], samples, 1234); });  // another block size
  first.join();
  second.join();
  expectSameFrames(got[0], expected);
  expectSameFrames(got[1], expected);
}

TEST(LibraryModels, AFileAnimatedOnTheHandleIsTheOneAnimatedAlone) {
  const std::string speech = th::sharedDataPath("speech/arctic/arctic_a0001.wav").string();
  th_models* own = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &own), TH_OK) << th_last_error();
  th_animation* alone = nullptr;
  ASSERT_EQ(th_animate(own, speech.c_str(), nullptr, &alone), TH_OK) << th_last_error();
  th_models_free(own);
  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_animation* shared[2] = {nullptr, nullptr};
  std::thread first([&] { EXPECT_EQ(th_animate(models, speech.c_str(), nullptr, &shared[0]), TH_OK); });
  std::thread second([&] { EXPECT_EQ(th_animate(models, speech.c_str(), nullptr, &shared[1]), TH_OK); });
  first.join();
  second.join();
  th_models_free(models);
  for (th_animation* animation : shared) {
    ASSERT_NE(animation, nullptr);
    ASSERT_EQ(th_animation_frames(animation), th_animation_frames(alone));
    th_frame a, b;
    th_frame_init(&a);
    th_frame_init(&b);
    for (int i = 0; i < th_animation_frames(alone); ++i) {
      ASSERT_EQ(th_animation_frame(alone, i, &a), TH_OK);
      ASSERT_EQ(th_animation_frame(animation, i, &b), TH_OK);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "frame " << i;
    }
    th_animation_free(animation);
  }
  th_animation_free(alone);
}

TEST(LibraryModels, ABadModelFileFailsAtLoadNamingIt) {
  for (const auto field : {&th_models_options::head_model, &th_models_options::mouth_model,
                           &th_models_options::viseme_model, &th_models_options::head_style}) {
    th_models_options options;
    th_models_options_init(&options);
    options.*field = "/nonexistent/model.json";
    th_models* models = nullptr;
    EXPECT_EQ(th_models_load(&options, &models), TH_ERROR_FILE);
    EXPECT_EQ(models, nullptr);
    EXPECT_NE(std::string(th_last_error()).find("/nonexistent/model.json"), std::string::npos) << th_last_error();
  }
}

}  // namespace
