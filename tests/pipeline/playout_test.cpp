// Playout: the display's jitter buffer and clock, driven with made-up arrival times.
#include "pipeline/playout.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "core/error.h"

namespace {

using th::pipeline::AnimationFrame;
using th::pipeline::Playout;
using th::pipeline::PlayoutSample;

constexpr std::int64_t kMs = 1'000'000;

// Frame i has FAP 3 = 10 i and a head pitch of i degrees: linear in time, so interpolation is exact.
AnimationFrame rampFrame(int index) {
  AnimationFrame frame;
  frame.index = index;
  frame.timeSeconds = index / 30.0;
  frame.faps[3] = 10.0 * index;
  frame.faps[48] = index / th::face::kDegreesPerAngleUnit;  // the head's pitch, i degrees
  return frame;
}

// Frames arriving in bursts of two every 66.7 ms, each burst up to 20 ms late, shown at 60 Hz.
TEST(Playout, ShowsASmoothClockBehindJitteryFramesWithoutStarving) {
  Playout playout;
  std::mt19937 random(3);
  std::uniform_int_distribution<std::int64_t> jitter(0, 20 * kMs);
  const std::int64_t start = 1000 * kMs;
  const std::int64_t pipelineDelay = 120 * kMs;  // the decoder's look-ahead
  int pushed = 0;
  std::int64_t nextBurst = start + pipelineDelay + jitter(random);
  double lastStream = -1.0;
  int samples = 0;
  int starved = 0;
  double lastDelay = 0.0;
  for (std::int64_t now = start; now < start + 20'000 * kMs; now += 16'667'000) {
    while (nextBurst <= now) {
      playout.push(rampFrame(pushed++), nextBurst);
      playout.push(rampFrame(pushed++), nextBurst);
      nextBurst = start + pipelineDelay + std::llround(pushed * 1e9 / 30.0) + 33 * kMs + jitter(random);
    }
    PlayoutSample sample;
    if (!playout.sample(now, sample)) {
      EXPECT_EQ(pushed, 0);
      continue;
    }
    EXPECT_GE(sample.streamSeconds, lastStream) << "the clock never goes back";
    lastStream = sample.streamSeconds;
    if (now > start + 5000 * kMs) {
      ++samples;
      starved += sample.starved ? 1 : 0;
      // Interpolated exactly on the ramp.
      EXPECT_NEAR(sample.frame.faps[3], 300.0 * sample.streamSeconds, 1e-6);
      EXPECT_NEAR(th::face::headDegreesOf(sample.frame.faps).x(), 30.0 * sample.streamSeconds, 1e-6);
      lastDelay = std::max(lastDelay, sample.behindNewestMs);
    }
  }
  EXPECT_GT(samples, 800);
  EXPECT_EQ(starved, 0);
  // The shown instant lags the newest frame by the burst's spread and jitter (the first frame of a burst comes
  // 33 + 20 ms late at most), one frame for the interpolation and the margin, and not more.
  EXPECT_GT(lastDelay, 33.4 + 33.3);
  EXPECT_LT(lastDelay, 33.4 + 20.0 + 33.4 + 4.0 + 33.4 + 1.0);
  EXPECT_LE(playout.framesBuffered(), 4);
}

// Frames that suddenly come 100 ms later: the clock holds (no jump back) until the display is 100 ms further
// behind the wall clock; when frames come promptly again, the clock catches up at 5 % and the lag shrinks back.
TEST(Playout, HoldsWhenFramesComeLaterAndCatchesUpWhenTheyComeSooner) {
  Playout playout;
  std::int64_t extra = 0;
  int pushed = 0;
  double lastStream = -1.0;
  double largestStep = 0.0;
  double lagBefore = 0.0;
  double lagDuring = 0.0;
  double lagAfter = 0.0;
  for (std::int64_t now = 0; now < 16'000 * kMs; now += 16'667'000) {
    extra = now >= 4000 * kMs && now < 8000 * kMs ? 100 * kMs : 0;  // frames 100 ms later for 4 s
    while (50 * kMs + std::llround(pushed * 1e9 / 30.0) + extra <= now) playout.push(rampFrame(pushed++), now);
    PlayoutSample sample;
    if (!playout.sample(now, sample)) continue;
    if (lastStream >= 0.0) largestStep = std::max(largestStep, sample.streamSeconds - lastStream);
    EXPECT_GE(sample.streamSeconds, lastStream);
    lastStream = sample.streamSeconds;
    EXPECT_FALSE(sample.starved && now > 1000 * kMs && (now < 4000 * kMs || now > 4300 * kMs)) << now / kMs << " ms";
    const double lag = static_cast<double>(now) * 1e-6 - sample.streamSeconds * 1000.0;  // ms
    if (now < 4000 * kMs) lagBefore = lag;
    if (now < 8000 * kMs) lagDuring = lag;
    lagAfter = lag;
  }
  EXPECT_NEAR(lagDuring - lagBefore, 100.0, 17.0) << "the clock held for the late frames";
  EXPECT_NEAR(lagAfter, lagBefore, 1.0) << "and caught up once they came promptly for longer than the window";
  EXPECT_LT(largestStep, 0.016667 * 1.05 + 1e-6) << "never more than 5 % fast";
}

TEST(Playout, HoldsTheNewestFrameWhenStarvedAndStartsAgainAfterReset) {
  Playout playout;
  PlayoutSample sample;
  EXPECT_FALSE(playout.sample(0, sample));
  playout.push(rampFrame(0), 100 * kMs);
  playout.push(rampFrame(1), 133 * kMs);
  ASSERT_TRUE(playout.sample(140 * kMs, sample));
  EXPECT_FALSE(sample.starved);
  ASSERT_TRUE(playout.sample(1000 * kMs, sample));  // no frames for most of a second
  EXPECT_TRUE(sample.starved);
  EXPECT_EQ(sample.frame.index, 1);
  EXPECT_EQ(sample.frame.faps[3], 10.0);
  EXPECT_EQ(playout.starvedSamples(), 1u);
  playout.reset();
  EXPECT_FALSE(playout.sample(1100 * kMs, sample));
  playout.push(rampFrame(0), 1200 * kMs);
  ASSERT_TRUE(playout.sample(1200 * kMs, sample));
  EXPECT_EQ(sample.frame.index, 0);
  EXPECT_THROW(Playout(th::pipeline::PlayoutOptions{.framesPerSecond = 0.0}), th::Error);
}

TEST(Playout, WithoutInterpolationShowsTheNewestFrameAtOnce) {
  Playout playout(th::pipeline::PlayoutOptions{.interpolate = false});
  PlayoutSample sample;
  EXPECT_FALSE(playout.sample(0, sample));
  playout.push(rampFrame(0), 100 * kMs);
  playout.push(rampFrame(1), 110 * kMs);
  ASSERT_TRUE(playout.sample(111 * kMs, sample));
  EXPECT_EQ(sample.frame.index, 1);
  EXPECT_EQ(sample.frame.faps[3], 10.0);
  EXPECT_EQ(sample.behindNewestMs, 0.0);
  ASSERT_TRUE(playout.sample(500 * kMs, sample));  // held, not starved: there is no clock to run past it
  EXPECT_EQ(sample.frame.index, 1);
  EXPECT_FALSE(sample.starved);
  playout.push(rampFrame(2), 501 * kMs);
  ASSERT_TRUE(playout.sample(502 * kMs, sample));
  EXPECT_EQ(sample.frame.index, 2);
  EXPECT_EQ(playout.framesBuffered(), 1);
}

// Another clock (the sound being heard) says which instant to show: interpolated between the frames around
// it, or the frame nearest that instant without interpolation; never back; the newest frame, counted as starved,
// when the instant is past it.
TEST(Playout, ShowsTheInstantAnotherClockGives) {
  Playout smooth;
  Playout steps(th::pipeline::PlayoutOptions{.interpolate = false});
  PlayoutSample sample;
  EXPECT_FALSE(smooth.sampleAt(0.0, sample));
  for (int i = 0; i < 10; ++i) {
    smooth.push(rampFrame(i), 0);
    steps.push(rampFrame(i), 0);
  }
  ASSERT_TRUE(smooth.sampleAt(2.5 / 30.0, sample));
  EXPECT_NEAR(sample.frame.faps[3], 25.0, 1e-9);
  EXPECT_NEAR(th::face::headDegreesOf(sample.frame.faps).x(), 2.5, 1e-9);
  ASSERT_TRUE(steps.sampleAt(2.4 / 30.0, sample));
  EXPECT_EQ(sample.frame.index, 2);
  EXPECT_NEAR(sample.frame.faps[3], 20.0, 1e-9);
  EXPECT_NEAR(sample.streamSeconds, 2.0 / 30.0, 1e-12);  // the instant that frame shows
  ASSERT_TRUE(steps.sampleAt(2.6 / 30.0, sample));
  EXPECT_EQ(sample.frame.index, 3);                  // the nearer frame
  ASSERT_TRUE(smooth.sampleAt(1.0 / 30.0, sample));  // the clock went back: the instant holds
  EXPECT_NEAR(sample.frame.faps[3], 25.0, 1e-9);
  ASSERT_TRUE(smooth.sampleAt(20.0 / 30.0, sample));  // past the newest
  EXPECT_EQ(sample.frame.index, 9);
  EXPECT_TRUE(sample.starved);
  EXPECT_EQ(smooth.starvedSamples(), 1U);
}

}  // namespace
