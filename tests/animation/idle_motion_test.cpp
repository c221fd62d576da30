// IdleMotion: blinks at a human rate and shape, gaze shifts within bounds, the head at rest in silence.
#include "animation/idle_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "core/error.h"
#include "face/fap.h"

namespace {

using th::animation::IdleMotion;
using th::animation::IdleSwitches;

constexpr double kDisplayHz = 60.0;

double degreesOf(double angleUnits) {
  return angleUnits * th::face::kAngleUnit * 180.0 / std::numbers::pi;
}

// Ten minutes at 60 Hz in silence: 17 blinks a minute on average (the gamma intervals' spread allows about
// ±25 % over ten minutes), each a short closure, never closer than a second; the gaze moves within ±4°.
TEST(IdleMotion, BlinksAtAHumanRateAndShiftsTheGazeALittle) {
  IdleMotion idle({.seed = 7});
  int closedRuns = 0;
  int closedFrames = 0;
  int longestClosed = 0;
  int run = 0;
  double lastBlinkStart = -10.0;
  double shortestGap = 1e9;
  double largestYaw = 0.0;
  double largestPitch = 0.0;
  int gazeMoves = 0;
  double lastYaw = 0.0;
  for (int f = 0; f < static_cast<int>(600 * kDisplayHz); ++f) {
    const double t = f / kDisplayHz;
    th::face::FapFrame faps{};
    idle.apply(t, -90.0, {}, faps);
    EXPECT_EQ(faps[19], faps[20]);
    const bool closed = faps[19] > 900.0;
    if (closed) {
      ++closedFrames;
      if (run++ == 0) {
        ++closedRuns;
        shortestGap = std::min(shortestGap, t - lastBlinkStart);
        lastBlinkStart = t;
      }
      longestClosed = std::max(longestClosed, run);
    } else {
      run = 0;
    }
    largestYaw = std::max(largestYaw, std::abs(degreesOf(faps[23])));
    largestPitch = std::max(largestPitch, std::abs(degreesOf(faps[25])));
    EXPECT_EQ(faps[23], faps[24]);
    if (std::abs(faps[23] - lastYaw) > 1.0 && std::abs(degreesOf(faps[23] - lastYaw)) > 0.5) ++gazeMoves;
    lastYaw = faps[23];
  }
  EXPECT_EQ(idle.blinks(), closedRuns) << "every blink closes the lids";
  EXPECT_GT(closedRuns, 0.75 * 170);
  EXPECT_LT(closedRuns, 1.25 * 170);
  EXPECT_GE(shortestGap, 1.0);
  EXPECT_LE(longestClosed, 10) << "a blink, not a nap: ~0.1 s closed at 60 Hz";
  EXPECT_LT(closedFrames, static_cast<int>(0.05 * 600 * kDisplayHz)) << "the eyes are open 95 % of the time";
  EXPECT_LE(largestYaw, 4.0 + 1e-9);
  EXPECT_GT(largestYaw, 2.0);
  EXPECT_LE(largestPitch, 2.0 + 1e-9);
  EXPECT_GT(gazeMoves, 60) << "saccades every few seconds";
}

// Speech, then silence: the head's rotation is kept while speaking and eases to rest about a second after
// the speech stops (the floor follows the room, so the gate is relative to it), and comes back with speech.
TEST(IdleMotion, TheHeadComesToRestWhenNobodySpeaks) {
  IdleMotion idle;
  const auto headAt = [&](double t, double level) {
    th::face::FapFrame faps{};
    faps[48] = 1000.0;
    faps[49] = -500.0;
    idle.apply(t, level, {.blinks = false, .gaze = false}, faps);
    EXPECT_EQ(faps[19], 0.0);
    EXPECT_EQ(faps[23], 0.0);
    return faps[48];
  };
  double t = 0.0;
  for (; t < 2.0; t += 1.0 / kDisplayHz) headAt(t, -60.0);  // room noise: the floor
  EXPECT_FALSE(idle.speaking());
  for (; t < 6.0; t += 1.0 / kDisplayHz) headAt(t, (std::fmod(t, 0.3) < 0.2) ? -20.0 : -35.0);  // speech
  EXPECT_TRUE(idle.speaking());
  EXPECT_NEAR(headAt(t, -20.0), 1000.0, 1.0);
  double restedAt = -1.0;
  for (const double silenceStart = t; t < silenceStart + 4.0; t += 1.0 / kDisplayHz)
    if (headAt(t, -60.0) < 50.0 && restedAt < 0.0) restedAt = t - silenceStart;
  EXPECT_FALSE(idle.speaking());
  EXPECT_GT(restedAt, 0.6) << "not at the first pause between words";
  EXPECT_LT(restedAt, 2.5);
  EXPECT_LT(std::abs(headAt(t, -60.0)), 5.0);
  for (const double back = t; t < back + 2.0; t += 1.0 / kDisplayHz) headAt(t, -20.0);
  EXPECT_NEAR(headAt(t, -20.0), 1000.0, 20.0);
  EXPECT_THROW(IdleMotion({.blinksPerMinute = 0.0}), th::Error);
}

// Blinks follow speech: phrases of 2 s of voice and 1 s of quiet. Per second, more blinks start in the quiet
// (or just after a phrase ends) than while the voice is on, and the rate stays a human one.
TEST(IdleMotion, BlinksComeAtPhraseEndsMoreThanMidSpeech) {
  IdleMotion idle({.seed = 3});
  int inQuiet = 0;
  int inVoice = 0;
  double lastStart = -1.0;
  const double seconds = 1200.0;
  for (int f = 0; f < static_cast<int>(seconds * 30.0); ++f) {
    const double t = f / 30.0;
    const bool voice = std::fmod(t, 3.0) < 2.0;
    th::face::FapFrame faps{};
    idle.apply(t, voice ? -20.0 : -70.0, {}, faps);
    if (idle.blinkStart() > lastStart) {
      lastStart = idle.blinkStart();
      (voice ? inVoice : inQuiet) += 1;
    }
  }
  const double quietRate = inQuiet / (seconds / 3.0);
  const double voiceRate = inVoice / (seconds * 2.0 / 3.0);
  std::printf(
      "[ INFO     ] blinks a minute: %.1f in the quiet, %.1f in the voice, %.1f in all; %d of %d at a phrase's end\n",
      60.0 * quietRate, 60.0 * voiceRate, 60.0 * (inQuiet + inVoice) / seconds, idle.boundaryBlinks(), idle.blinks());
  EXPECT_GT(quietRate, 2.0 * voiceRate);
  EXPECT_GE(60.0 * (inQuiet + inVoice) / seconds, 8.0);
  EXPECT_LE(60.0 * (inQuiet + inVoice) / seconds, 30.0);
}

// Over a file: the idle FAPs are added in FAP order, the head eases to rest where the sound is quiet, and with no
// sound the head is left as it is.
TEST(IdleMotion, AddsItsFapsToAnAnimation) {
  th::face::FapTrack animation;
  animation.faps = {3, 48, 49, 50};
  animation.values = Eigen::MatrixXd::Constant(4, 300, 1000.0);
  Eigen::RowVectorXd level(300);  // 5 s of speech (syllables, louder and quieter), then 5 s of quiet
  for (int t = 0; t < 300; ++t) level[t] = t >= 150 ? -90.0 : (t % 9 < 6 ? -20.0 : -35.0);
  level[0] = -60.0;  // the room before the first word
  th::face::FapTrack heard = animation;
  th::animation::addIdleMotion(heard, level, {}, {});
  EXPECT_EQ(heard.faps, (std::vector<int>{3, 19, 20, 23, 24, 25, 26, 48, 49, 50}));
  EXPECT_EQ(heard.values.row(0), animation.values.row(0)) << "the jaw untouched";
  EXPECT_NEAR(heard.values(heard.rowOf(49), 140), 1000.0, 1.0);
  EXPECT_LT(heard.values(heard.rowOf(49), 299), 50.0) << "at rest 4 s into the quiet";
  th::face::FapTrack unheard = animation;
  th::animation::addIdleMotion(unheard, Eigen::RowVectorXd(), {}, {});
  EXPECT_EQ(unheard.values.row(unheard.rowOf(49)), animation.values.row(1));
  EXPECT_THROW(th::animation::addIdleMotion(unheard, Eigen::RowVectorXd::Zero(10), {}, {}), th::Error);
}

}  // namespace
