// The live window's summary: start-up left out by time, so a slow display's run is still summed up.
#include "pipeline/frame_stats.h"

#include <gtest/gtest.h>

#include <string>

namespace {

th::pipeline::FrameTimes framePeriod(double ms) {
  th::pipeline::FrameTimes times;
  times.periodMs = ms;
  times.busyMs = ms * 0.5;
  return times;
}

std::string summaryOf(const th::pipeline::FrameStats& stats) {
  testing::internal::CaptureStdout();
  stats.printSummary(8.0, 10);
  return testing::internal::GetCapturedStdout();
}

TEST(FrameStats, ASlowDisplaysRunIsSummedUpWithoutItsFirstHalfSecond) {
  th::pipeline::FrameStats stats;
  for (int frame = 0; frame < 32; ++frame) stats.frameDrawn(framePeriod(250.0));  // 4 frames/s for 8 s
  const std::string summary = summaryOf(stats);
  // Frames 2 and 3 end the half second; the 29 after it are summed up.
  EXPECT_NE(summary.find("display: 29 frames, median 4.0 frames/s"), std::string::npos) << summary;
}

TEST(FrameStats, NothingIsSummedUpWithinTheStartUp) {
  th::pipeline::FrameStats stats;
  for (int frame = 0; frame < 20; ++frame) stats.frameDrawn(framePeriod(10.0));  // 0.19 s
  EXPECT_EQ(summaryOf(stats), "");
}

TEST(FrameStats, SoundToLipsNeedsTenFrames) {
  th::pipeline::FrameStats stats;
  for (int frame = 0; frame < 9; ++frame) stats.soundToLips(50.0);
  testing::internal::CaptureStdout();
  stats.printSoundToLips(1.0, 30.0, 100.0, 0);
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
  stats.soundToLips(50.0);
  testing::internal::CaptureStdout();
  stats.printSoundToLips(1.0, 30.0, 100.0, 0);
  EXPECT_NE(testing::internal::GetCapturedStdout().find("+50.0 ms after it is heard (median of 10 frames"),
            std::string::npos);
}

}  // namespace
