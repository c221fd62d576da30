// The C API's options per verb through libtalkinghead: each struct's defaults from its _init, a struct_size below
// its first version refused, NULL arguments refused with a message naming the call (but NULL models, the
// installed ones), and the deprecated calls on th_stream_options giving the frames the new calls give.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "core/data_path.h"
#include "stream_frames.h"
#include "talkinghead/talkinghead.h"
#include "wav_samples.h"

namespace {

std::string speech() {
  return th::sharedDataPath("speech/arctic/arctic_a0001.wav").string();
}

bool says(const char* text) {
  return std::string(th_last_error()).find(text) != std::string::npos;
}

// Each field set to something an _init must overwrite.
template <typename Struct>
Struct garbage() {
  Struct given;
  std::memset(&given, 0x5a, sizeof given);
  return given;
}

std::vector<th_frame> pulled(th_stream* stream, const std::vector<float>& samples) {
  return th::test::pullAllFrames(stream, samples, 441);
}

std::vector<th_frame> framesOf(th_animation* animation) {
  std::vector<th_frame> frames(static_cast<std::size_t>(th_animation_frames(animation)));
  for (std::size_t i = 0; i < frames.size(); ++i) {
    th_frame_init(&frames[i]);
    EXPECT_EQ(th_animation_frame(animation, static_cast<int>(i), &frames[i]), TH_OK);
  }
  th_animation_free(animation);
  return frames;
}

// Frames of a recording long enough to compare (more than two seconds), byte for byte.
void expectSameFrames(const std::vector<th_frame>& got, const std::vector<th_frame>& expected) {
  ASSERT_GT(expected.size(), 60u);
  th::test::expectSameFrames(got, expected);
}

TEST(LibraryVerbOptions, InitGivesTheDefaults) {
  auto models = garbage<th_models_options>();
  ASSERT_EQ(th_models_options_init(&models), TH_OK);
  EXPECT_EQ(models.struct_size, sizeof(th_models_options));
  EXPECT_EQ(models.head_model, nullptr);
  EXPECT_EQ(models.mouth_model, nullptr);
  EXPECT_EQ(models.viseme_model, nullptr);
  EXPECT_EQ(models.head_style, nullptr);

  auto stream = garbage<th_stream_settings>();
  ASSERT_EQ(th_stream_settings_init(&stream), TH_OK);
  EXPECT_EQ(stream.struct_size, sizeof(th_stream_settings));
  EXPECT_EQ(stream.sample_rate_hz, 16000.0);
  EXPECT_EQ(stream.wait_for_head, 0);

  auto animate = garbage<th_animate_options>();
  ASSERT_EQ(th_animate_options_init(&animate), TH_OK);
  EXPECT_EQ(animate.struct_size, sizeof(th_animate_options));
  EXPECT_EQ(animate.progress, nullptr);
  EXPECT_EQ(animate.user_data, nullptr);
}

TEST(LibraryVerbOptions, InitRefusesNullAndASizeBelowTheFirstVersion) {
  EXPECT_EQ(th_models_options_init_sized(nullptr, sizeof(th_models_options)), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_models_options_init")) << th_last_error();
  EXPECT_EQ(th_stream_settings_init_sized(nullptr, sizeof(th_stream_settings)), TH_ERROR_ARGUMENT);
  EXPECT_EQ(th_animate_options_init_sized(nullptr, sizeof(th_animate_options)), TH_ERROR_ARGUMENT);

  th_models_options models;
  EXPECT_EQ(th_models_options_init_sized(&models, offsetof(th_models_options, head_style)), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("struct_size")) << th_last_error();
  th_stream_settings stream;
  EXPECT_EQ(th_stream_settings_init_sized(&stream, offsetof(th_stream_settings, wait_for_head)), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_stream_settings_init")) << th_last_error();
  th_animate_options animate;
  EXPECT_EQ(th_animate_options_init_sized(&animate, sizeof(std::size_t)), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_animate_options_init")) << th_last_error();
}

TEST(LibraryVerbOptions, ACallGivenAStructBelowItsFirstVersionRefusesIt) {
  th_models_options small;
  th_models_options_init(&small);
  small.struct_size = sizeof(std::size_t);
  th_models* models = nullptr;
  EXPECT_EQ(th_models_load(&small, &models), TH_ERROR_ARGUMENT);
  EXPECT_EQ(models, nullptr);
  EXPECT_TRUE(says("th_models_load: struct_size")) << th_last_error();

  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_stream_settings settings;
  th_stream_settings_init(&settings);
  settings.struct_size = offsetof(th_stream_settings, wait_for_head);
  th_stream* stream = nullptr;
  EXPECT_EQ(th_stream_start(models, &settings, &stream), TH_ERROR_ARGUMENT);
  EXPECT_EQ(stream, nullptr);
  EXPECT_TRUE(says("th_stream_start: struct_size")) << th_last_error();

  th_animate_options options;
  th_animate_options_init(&options);
  options.struct_size = 0;
  th_animation* animation = nullptr;
  EXPECT_EQ(th_animate(models, speech().c_str(), &options, &animation), TH_ERROR_ARGUMENT);
  EXPECT_EQ(animation, nullptr);
  EXPECT_TRUE(says("th_animate: struct_size")) << th_last_error();
  th_models_free(models);
}

TEST(LibraryVerbOptions, NullArgumentsAreRefusedNamingTheCall) {
  EXPECT_EQ(th_models_load(nullptr, nullptr), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_models_load")) << th_last_error();

  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_stream* stream = nullptr;
  EXPECT_EQ(th_stream_start(models, nullptr, nullptr), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_stream_start")) << th_last_error();
  th_stream_settings settings;
  th_stream_settings_init(&settings);
  settings.sample_rate_hz = 100.0;
  for (const th_models* on : {static_cast<const th_models*>(models), static_cast<const th_models*>(nullptr)}) {
    EXPECT_EQ(th_stream_start(on, &settings, &stream), TH_ERROR_ARGUMENT);
    EXPECT_TRUE(says("th_stream_start: the sample rate")) << th_last_error();
    EXPECT_EQ(stream, nullptr);
  }

  th_animation* animation = nullptr;
  EXPECT_EQ(th_animate(models, nullptr, nullptr, &animation), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_animate")) << th_last_error();
  EXPECT_EQ(th_animate(models, speech().c_str(), nullptr, nullptr), TH_ERROR_ARGUMENT);
  EXPECT_EQ(th_animate(nullptr, nullptr, nullptr, &animation), TH_ERROR_ARGUMENT);
  EXPECT_EQ(animation, nullptr);

  // NULL options are the defaults.
  ASSERT_EQ(th_stream_start(models, nullptr, &stream), TH_OK) << th_last_error();
  th_stream_close(stream);
  th_models_free(models);
}

TEST(LibraryVerbOptions, NoModelsAreTheInstalledOnesReadForTheCall) {
  double rate = 0.0;
  const std::vector<float> samples = th::test::readWavSamples(speech(), rate);
  th_stream_settings settings;
  th_stream_settings_init(&settings);
  settings.sample_rate_hz = rate;
  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_stream* loaded = nullptr;
  th_stream* alone = nullptr;
  ASSERT_EQ(th_stream_start(models, &settings, &loaded), TH_OK) << th_last_error();
  ASSERT_EQ(th_stream_start(nullptr, &settings, &alone), TH_OK) << th_last_error();
  expectSameFrames(pulled(alone, samples), pulled(loaded, samples));

  th_animation* onModels = nullptr;
  th_animation* onNone = nullptr;
  ASSERT_EQ(th_animate(models, speech().c_str(), nullptr, &onModels), TH_OK) << th_last_error();
  ASSERT_EQ(th_animate(nullptr, speech().c_str(), nullptr, &onNone), TH_OK) << th_last_error();
  expectSameFrames(framesOf(onNone), framesOf(onModels));
  th_models_free(models);
}

TEST(LibraryVerbOptions, AFileThatCannotBeReadIsNamed) {
  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_animation* animation = nullptr;
  for (const th_models* on : {static_cast<const th_models*>(models), static_cast<const th_models*>(nullptr)}) {
    EXPECT_EQ(th_animate(on, "/nonexistent/speech.wav", nullptr, &animation), TH_ERROR_FILE);
    EXPECT_TRUE(says("/nonexistent/speech.wav")) << th_last_error();
    EXPECT_EQ(animation, nullptr);
  }
  th_models_free(models);
}

// th_stream_options, deprecated, split by verb: the old calls must give what the new ones give with the same
// choices, every field reaching its verb.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"

int countCalls(double, void* calls) {
  ++*static_cast<int*>(calls);
  return 0;
}

TEST(LibraryDeprecatedCalls, StreamTheFramesOfTheNewCalls) {
  double rate = 0.0;
  const std::vector<float> samples = th::test::readWavSamples(speech(), rate);
  ASSERT_GT(samples.size(), 16000u);
  for (const int waitForHead : {0, 1}) {
    th_stream_options old;
    ASSERT_EQ(th_stream_options_init(&old), TH_OK);
    old.sample_rate_hz = rate;
    old.wait_for_head = waitForHead;
    old.viseme_model = "";  // no visemes: the model choice reaches the models
    th_models_options choice;
    th_models_options_init(&choice);
    choice.viseme_model = "";
    th_stream_settings settings;
    th_stream_settings_init(&settings);
    settings.sample_rate_hz = rate;
    settings.wait_for_head = waitForHead;
    th_models* models = nullptr;
    ASSERT_EQ(th_models_load(&choice, &models), TH_OK) << th_last_error();
    th_stream* fresh = nullptr;
    ASSERT_EQ(th_stream_start(models, &settings, &fresh), TH_OK) << th_last_error();
    const std::vector<th_frame> expected = pulled(fresh, samples);
    EXPECT_EQ(expected.back().viseme, -1) << "the visemes were not switched off";

    th_stream* alone = nullptr;
    ASSERT_EQ(th_stream_open(&old, &alone), TH_OK) << th_last_error();
    expectSameFrames(pulled(alone, samples), expected);
    th_models* opened = nullptr;
    ASSERT_EQ(th_models_open(&old, &opened), TH_OK) << th_last_error();
    th_stream* onOpened = nullptr;
    ASSERT_EQ(th_stream_open_models(opened, &old, &onOpened), TH_OK) << th_last_error();
    expectSameFrames(pulled(onOpened, samples), expected);
    th_stream* onLoaded = nullptr;
    ASSERT_EQ(th_stream_open_models(models, &old, &onLoaded), TH_OK) << th_last_error();
    expectSameFrames(pulled(onLoaded, samples), expected);
    th_models_free(opened);
    th_models_free(models);
  }
}

TEST(LibraryDeprecatedCalls, AnimateTheFramesOfTheNewCalls) {
  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_animation* fresh = nullptr;
  ASSERT_EQ(th_animate(models, speech().c_str(), nullptr, &fresh), TH_OK) << th_last_error();
  const std::vector<th_frame> expected = framesOf(fresh);

  th_stream_options old;
  th_stream_options_init(&old);
  int calls = 0;
  old.progress = countCalls;  // the progress callback reaches the animation
  old.user_data = &calls;
  th_animation* alone = nullptr;
  ASSERT_EQ(th_animate_file(speech().c_str(), &old, &alone), TH_OK) << th_last_error();
  expectSameFrames(framesOf(alone), expected);
  EXPECT_EQ(calls, 2);
  th_animation* onModels = nullptr;
  ASSERT_EQ(th_animate_file_models(models, speech().c_str(), &old, &onModels), TH_OK) << th_last_error();
  expectSameFrames(framesOf(onModels), expected);
  EXPECT_EQ(calls, 4);
  th_models_free(models);
}

TEST(LibraryDeprecatedCalls, RefuseWhatTheyAlwaysRefused) {
  th_stream_options old;
  th_stream_options_init(&old);
  old.sample_rate_hz = 100.0;
  th_stream* stream = nullptr;
  EXPECT_EQ(th_stream_open(&old, &stream), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_stream_open: the sample rate")) << th_last_error();
  EXPECT_EQ(th_stream_open(&old, nullptr), TH_ERROR_ARGUMENT);
  EXPECT_EQ(th_models_open(&old, nullptr), TH_ERROR_ARGUMENT);
  EXPECT_EQ(th_stream_open_models(nullptr, &old, &stream), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_stream_open_models")) << th_last_error();
  th_animation* animation = nullptr;
  EXPECT_EQ(th_animate_file(nullptr, &old, &animation), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_animate_file")) << th_last_error();
  EXPECT_EQ(th_animate_file_models(nullptr, speech().c_str(), &old, &animation), TH_ERROR_ARGUMENT);
  EXPECT_TRUE(says("th_animate_file_models")) << th_last_error();

  th_stream_options_init(&old);
  old.head_model = "/nonexistent/head.json";
  th_models* models = nullptr;
  EXPECT_EQ(th_models_open(&old, &models), TH_ERROR_FILE);
  EXPECT_EQ(models, nullptr);
  EXPECT_TRUE(says("/nonexistent/head.json")) << th_last_error();
  EXPECT_EQ(th_animate_file(speech().c_str(), &old, &animation), TH_ERROR_FILE);
  EXPECT_TRUE(says("/nonexistent/head.json")) << th_last_error();
  EXPECT_EQ(animation, nullptr);
}

#pragma GCC diagnostic pop

}  // namespace
