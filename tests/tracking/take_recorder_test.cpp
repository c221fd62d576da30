// Recording a take where the devices are missing or the names are taken: one message that says what is wrong,
// and nothing written. (A camera and a microphone are not there on CI machines; the recording itself needs both.)
#include "tracking/take_recorder.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "core/temporary_file.h"

namespace {

namespace fs = std::filesystem;
using th::tracking::RecordingOptions;

// The error recordTalkingVideo throws, or "" if it recorded.
std::string errorOf(const RecordingOptions& options) {
  try {
    th::tracking::recordTalkingVideo(options, [] { return true; });
  } catch (const th::Error& error) {
    return error.what();
  }
  return "";
}

bool isEmpty(const fs::path& folder) {
  return fs::directory_iterator(folder) == fs::directory_iterator();
}

TEST(TakeRecorder, SaysWhichDeviceIsMissingAndWritesNothing) {
  th::TemporaryFolder folder;
  bool started = false;
  const RecordingOptions options{.folder = folder.path(), .name = "take", .camera = 63, .seconds = 1.0};
  std::string error;
  try {
    th::tracking::recordTalkingVideo(
        options, [] { return false; }, [&](const auto&) { started = true; });
  } catch (const th::Error& e) {
    error = e.what();
  }
  EXPECT_EQ(error.rfind("record: no camera (/dev/video63 cannot be opened", 0), 0U) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  EXPECT_FALSE(started);
  EXPECT_TRUE(isEmpty(folder.path()));
}

TEST(TakeRecorder, RefusesAMissingFolderAndATakeThatExists) {
  th::TemporaryFolder folder;
  const std::string missing = errorOf({.folder = folder.path() / "missing", .camera = 63});
  EXPECT_NE(missing.find("missing"), std::string::npos) << missing;
  EXPECT_NE(missing.find("is not a folder"), std::string::npos) << missing;

  std::ofstream(folder.path() / "take.wav") << "already here";
  const std::string exists = errorOf({.folder = folder.path(), .name = "take", .camera = 63});
  EXPECT_NE(exists.find("take.wav"), std::string::npos) << exists;
  EXPECT_NE(exists.find("exists already"), std::string::npos) << exists;
  EXPECT_EQ(std::distance(fs::directory_iterator(folder.path()), fs::directory_iterator()), 1);
}

}  // namespace
