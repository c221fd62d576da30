// The C API's growth through libtalkinghead: the version from the build; structs read and written only as far as
// their struct_size, and refused below their first version; progress callbacks on file work that cancel it,
// leaving no file.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/data_path.h"
#include "core/temporary_file.h"
#include "core/text_files.h"
#include "talkinghead/talkinghead.h"

namespace {

namespace fs = std::filesystem;

std::string speech() {
  return th::sharedDataPath("speech/arctic/arctic_a0001.wav").string();
}

std::vector<fs::path> filesIn(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder)) files.push_back(entry.path().filename());
  return files;
}

TEST(LibraryVersion, TheLibrarysIsTheHeadersFromTheBuild) {
  EXPECT_STREQ(th_version(), TALKINGHEAD_VERSION);
  EXPECT_EQ(std::string(TALKINGHEAD_VERSION), std::to_string(TALKINGHEAD_VERSION_MAJOR) + "." +
                                                  std::to_string(TALKINGHEAD_VERSION_MINOR) + "." +
                                                  std::to_string(TALKINGHEAD_VERSION_PATCH));
}

// th_stream_options, deprecated, grew in 0.2: programs built against it still call these.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"

TEST(LibraryStructSize, BelowTheFirstVersionIsRefusedWithAMessage) {
  th_stream_options options;
  ASSERT_EQ(th_stream_options_init(&options), TH_OK);
  EXPECT_EQ(options.struct_size, sizeof(th_stream_options));
  options.struct_size = sizeof(std::size_t);
  th_stream* stream = nullptr;
  EXPECT_EQ(th_stream_open(&options, &stream), TH_ERROR_ARGUMENT);
  EXPECT_EQ(stream, nullptr);
  EXPECT_NE(std::string(th_last_error()).find("struct_size"), std::string::npos) << th_last_error();
  EXPECT_EQ(th_stream_options_init_sized(&options, 4), TH_ERROR_ARGUMENT);

  th_stream_options_init(&options);
  ASSERT_EQ(th_stream_open(&options, &stream), TH_OK) << th_last_error();
  th_frame frame{};  // struct_size 0: not initialised
  EXPECT_EQ(th_stream_pull(stream, &frame), -1);
  EXPECT_NE(std::string(th_last_error()).find("th_frame_init"), std::string::npos) << th_last_error();
  th_stream_close(stream);
}

int countCalls(double, void* calls) {
  ++*static_cast<int*>(calls);
  return 0;
}

TEST(LibraryStructSize, FieldsPastTheCallersSizeAreTheirDefaults) {
  // A program built before the callback was appended: its struct ends at wait_for_head, and what lies beyond
  // (here a callback the library must not see) is not its.
  th_stream_options options;
  ASSERT_EQ(th_stream_options_init_sized(&options, offsetof(th_stream_options, progress)), TH_OK);
  int calls = 0;
  options.progress = countCalls;
  options.user_data = &calls;
  th_animation* animation = nullptr;
  ASSERT_EQ(th_animate_file(speech().c_str(), &options, &animation), TH_OK) << th_last_error();
  EXPECT_EQ(calls, 0);
  // Nor a head style: one built before it was appended reads none, even with a bad one lying past its size.
  th_stream_options beforeStyle;
  ASSERT_EQ(th_stream_options_init_sized(&beforeStyle, offsetof(th_stream_options, head_style)), TH_OK);
  beforeStyle.head_style = "/no/such/style.json";
  th_animation* unstyled = nullptr;
  ASSERT_EQ(th_animate_file(speech().c_str(), &beforeStyle, &unstyled), TH_OK) << th_last_error();
  th_animation_free(unstyled);
  th_stream_options current;
  ASSERT_EQ(th_stream_options_init(&current), TH_OK);
  current.head_style = "/no/such/style.json";
  EXPECT_EQ(th_animate_file(speech().c_str(), &current, &unstyled), TH_ERROR_FILE);
  EXPECT_NE(std::string(th_last_error()).find("/no/such/style.json"), std::string::npos) << th_last_error();
  // A frame of the first version's size: the appended rotation is left as it was.
  th_frame frame;
  std::memset(&frame, 0x7f, sizeof frame);
  ASSERT_EQ(th_frame_init_sized(&frame, offsetof(th_frame, head_rotation_unity)), TH_OK);
  const float untouched = frame.head_rotation_unity[0];
  ASSERT_EQ(th_animation_frame(animation, 10, &frame), TH_OK) << th_last_error();
  EXPECT_EQ(frame.index, 10);
  EXPECT_EQ(std::memcmp(&frame.head_rotation_unity[0], &untouched, sizeof untouched), 0);
  // The whole frame: the rotation is a unit quaternion.
  th_frame_init(&frame);
  ASSERT_EQ(th_animation_frame(animation, 10, &frame), TH_OK);
  const float* q = frame.head_rotation_unity;
  EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, 1e-5f);
  th_animation_free(animation);
}

#pragma GCC diagnostic pop

struct Recorded {
  std::vector<double> fractions;
  double cancelAt = 2.0;  // cancel at the first report at or past this fraction
};

int record(double fraction, void* userData) {
  auto* recorded = static_cast<Recorded*>(userData);
  recorded->fractions.push_back(fraction);
  return fraction >= recorded->cancelAt ? 1 : 0;
}

TEST(LibraryProgress, AnExportReportsItsFramesInOrderToTheEnd) {
  th::TemporaryFolder folder;
  const fs::path mp4 = folder.path() / "talk.mp4";
  Recorded recorded;
  th_export_options options;
  ASSERT_EQ(th_export_options_init(&options), TH_OK);
  options.width = 160;
  options.height = 120;
  options.progress = record;
  options.user_data = &recorded;
  ASSERT_EQ(th_export(speech().c_str(), mp4.c_str(), &options), TH_OK) << th_last_error();
  EXPECT_TRUE(fs::is_regular_file(mp4));
  ASSERT_GT(recorded.fractions.size(), 10u);
  EXPECT_EQ(recorded.fractions.front(), 0.0);
  EXPECT_EQ(recorded.fractions.back(), 1.0);
  for (std::size_t i = 1; i < recorded.fractions.size(); ++i)
    EXPECT_LE(recorded.fractions[i - 1], recorded.fractions[i]);
}

TEST(LibraryProgress, CancellingAnExportStopsItAndLeavesNoFile) {
  for (const double cancelAt : {0.0, 0.3}) {
    th::TemporaryFolder folder;
    const fs::path mp4 = folder.path() / "talk.mp4";
    Recorded recorded;
    recorded.cancelAt = cancelAt;
    th_export_options options;
    th_export_options_init(&options);
    options.width = 160;
    options.height = 120;
    options.progress = record;
    options.user_data = &recorded;
    EXPECT_EQ(th_export(speech().c_str(), mp4.c_str(), &options), TH_ERROR_CANCELLED) << cancelAt;
    EXPECT_NE(std::string(th_last_error()).find("cancelled"), std::string::npos) << th_last_error();
    EXPECT_TRUE(filesIn(folder.path()).empty()) << cancelAt;  // neither the video nor a temporary one
    ASSERT_FALSE(recorded.fractions.empty());
    EXPECT_GE(recorded.fractions.back(), cancelAt);
    EXPECT_LT(recorded.fractions.back(), 0.5) << "stopped promptly";
  }
}

TEST(LibraryExport, OnSharedModelsTheVideoIsTheOneMadeAlone) {
  th::TemporaryFolder folder;
  th_export_options options;
  th_export_options_init(&options);
  options.width = 96;
  options.height = 64;
  options.frames_per_second = 10;
  const fs::path alone = folder.path() / "alone.mp4", shared = folder.path() / "shared.mp4";
  ASSERT_EQ(th_export(speech().c_str(), alone.c_str(), &options), TH_OK) << th_last_error();
  ASSERT_EQ(th_models_load(nullptr, const_cast<th_models**>(&options.models)), TH_OK) << th_last_error();
  ASSERT_EQ(th_export(speech().c_str(), shared.c_str(), &options), TH_OK) << th_last_error();
  th_models_free(const_cast<th_models*>(options.models));
  EXPECT_GT(fs::file_size(alone), 1000u);
  EXPECT_EQ(th::readTextFile(alone, "video"), th::readTextFile(shared, "video"));
}

TEST(LibraryProgress, CancellingAnAnimationGivesNone) {
  th_models* models = nullptr;
  ASSERT_EQ(th_models_load(nullptr, &models), TH_OK) << th_last_error();
  th_animate_options options;
  th_animate_options_init(&options);
  Recorded recorded;
  recorded.cancelAt = 0.0;
  options.progress = record;
  options.user_data = &recorded;
  th_animation* animation = nullptr;
  EXPECT_EQ(th_animate(models, speech().c_str(), &options, &animation), TH_ERROR_CANCELLED);
  EXPECT_EQ(animation, nullptr);
  recorded = {};
  ASSERT_EQ(th_animate(models, speech().c_str(), &options, &animation), TH_OK) << th_last_error();
  EXPECT_EQ(recorded.fractions, (std::vector<double>{0.0, 1.0}));
  th_animation_free(animation);
  th_models_free(models);
}

}  // namespace
