// The progress bar: off a terminal it prints nothing but one final line; on one it redraws in place at most
// ten times a second, padding over a longer previous line; the line shows the bar, the percentage, the elapsed
// time and the real-time factor.
#include "core/progress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>

namespace th {
namespace {

struct FakeClock {
  double now = 100.0;
};

ProgressOptions withClock(FakeClock& clock, bool terminal, int width = 10) {
  ProgressOptions options;
  options.terminal = terminal;
  options.barWidth = width;
  options.clock = [&clock] { return clock.now; };
  return options;
}

TEST(ProgressBar, LineShowsBarPercentageTimeAndRealTimeFactor) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar bar(10.0, "export", out, withClock(clock, true));
  clock.now += 2.0;
  EXPECT_EQ(bar.line(5.0), "export [#####.....]  50% 2.0 s elapsed, 2.5x real time");
  EXPECT_EQ(bar.line(10.0), "export [##########] 100% 2.0 s elapsed, 5.0x real time");
  EXPECT_EQ(bar.line(20.0), "export [##########] 100% 2.0 s elapsed, 5.0x real time");  // clamped
  EXPECT_EQ(bar.line(0.0), "export [..........]   0% 2.0 s elapsed, 0.0x real time");
}

TEST(ProgressBar, FramesAsUnits) {
  FakeClock clock;
  std::ostringstream out;
  ProgressOptions options = withClock(clock, false);
  options.unitsPerSecond = 30.0;  // done counts frames at 30 fps
  ProgressBar bar(300.0, "export", out, options);
  clock.now += 4.0;
  EXPECT_EQ(bar.line(150.0), "export [#####.....]  50% 4.0 s elapsed, 1.2x real time");
  options.unitsPerSecond = 0.0;
  ProgressBar plain(300.0, "train", out, options);
  EXPECT_EQ(plain.line(30.0), "train [#.........]  10% 0.0 s elapsed");
}

TEST(ProgressBar, OffATerminalPrintsOnlyTheFinalLine) {
  FakeClock clock;
  std::ostringstream out;
  {
    ProgressBar bar(10.0, "export", out, withClock(clock, false));
    EXPECT_FALSE(bar.drawsInPlace());
    for (int i = 1; i <= 100; ++i) {
      clock.now += 0.5;
      bar.update(i * 0.1);
    }
    EXPECT_EQ(out.str(), "");
    bar.finish();
    bar.finish();  // once only
  }
  EXPECT_EQ(out.str(), "export [##########] 100% 50.0 s elapsed, 0.2x real time\n");
}

TEST(ProgressBar, StringStreamsAreNotTerminals) {
  std::ostringstream out;
  ProgressBar bar(1.0, "x", out);
  EXPECT_FALSE(bar.drawsInPlace());
  bar.update(0.5);
  EXPECT_EQ(out.str(), "");
}

TEST(ProgressBar, OnATerminalRedrawsAtMostTenTimesASecond) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar bar(100.0, "export", out, withClock(clock, true));
  EXPECT_TRUE(bar.drawsInPlace());
  // 1000 updates over 2 s: the first draws, then one every 0.1 s.
  for (int i = 1; i <= 1000; ++i) {
    clock.now += 0.002;
    bar.update(i * 0.1);
  }
  const std::string drawn = out.str();
  const auto redraws = std::count(drawn.begin(), drawn.end(), '\r');
  EXPECT_GE(redraws, 19);
  EXPECT_LE(redraws, 21);
  EXPECT_EQ(drawn.find('\n'), std::string::npos);
  bar.finish();
  const std::string text = out.str();
  EXPECT_EQ(text.back(), '\n');
  const std::string last = text.substr(text.rfind('\r') + 1);
  EXPECT_EQ(last, "export [##########] 100% 2.0 s elapsed, 50.0x real time\n");
}

TEST(ProgressBar, PadsOverALongerPreviousLine) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar bar(10.0, "export", out, withClock(clock, true));
  clock.now += 1.0;
  bar.update(9.0);  // "... 9.0x real time"
  clock.now += 1.0;
  bar.update(9.5);  // "... 4.8x real time": as long
  const std::string before = out.str();
  ProgressOptions options = withClock(clock, true);
  std::ostringstream second;
  ProgressBar shrinking(10.0, "export", second, options);
  clock.now += 0.05;
  shrinking.update(10.0);  // 200.0x real time
  clock.now += 0.15;
  shrinking.update(10.0);  // 50.0x: shorter, padded
  const std::string text = second.str();
  const std::string firstLine = text.substr(1, text.find('\r', 1) - 1);
  const std::string secondLine = text.substr(text.rfind('\r') + 1);
  EXPECT_EQ(secondLine.size(), firstLine.size());
  EXPECT_EQ(secondLine.back(), ' ');
  EXPECT_FALSE(before.empty());
}

TEST(ProgressBar, UnfinishedBarOnATerminalEndsItsLine) {
  FakeClock clock;
  std::ostringstream out;
  {
    ProgressBar bar(10.0, "export", out, withClock(clock, true));
    bar.update(3.0);
  }
  EXPECT_EQ(out.str().back(), '\n');
  std::ostringstream quiet;
  {
    ProgressBar bar(10.0, "export", quiet, withClock(clock, false));
    bar.update(3.0);
  }
  EXPECT_EQ(quiet.str(), "");
}

TEST(ProgressBar, ZeroTotalIsComplete) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar bar(0.0, "empty", out, withClock(clock, false));
  bar.finish();
  EXPECT_EQ(out.str(), "empty [##########] 100% 0.0 s elapsed\n");
}

}  // namespace
}  // namespace th
