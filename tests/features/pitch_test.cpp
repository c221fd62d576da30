// The pitch tracker on signals whose F0 we know, and on inputs that must not confuse it.
#include "features/pitch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"

namespace th::features {
namespace {

constexpr int kRate = 16000;

// A glottal-like harmonic tone: harmonics 1..N with 1/k amplitudes, F0 following `f0At(t)`.
template <typename F0At>
std::vector<float> harmonicTone(double seconds, F0At f0At, double amplitude = 0.3) {
  std::vector<float> samples(static_cast<size_t>(seconds * kRate));
  double phase = 0.0;
  for (size_t n = 0; n < samples.size(); ++n) {
    const double f0 = f0At(static_cast<double>(n) / kRate);
    phase += 2.0 * std::numbers::pi * f0 / kRate;
    double value = 0.0;
    for (int k = 1; k * f0 < 4000.0; ++k) value += std::sin(k * phase) / k;
    samples[n] = static_cast<float>(amplitude * value / 2.0);
  }
  return samples;
}

struct VoicedSummary {
  double voicedFraction;
  double worstRelativeError;
};

template <typename F0At>
VoicedSummary summarise(const std::vector<PitchFrame>& frames, F0At f0At, double fromSeconds, double toSeconds) {
  int voiced = 0;
  int counted = 0;
  double worst = 0.0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const double t = static_cast<double>(k) * 0.005;
    if (t < fromSeconds || t > toSeconds) continue;
    ++counted;
    if (frames[k].f0Hz <= 0.0f) continue;
    ++voiced;
    worst = std::max(worst, std::abs(frames[k].f0Hz / f0At(t) - 1.0));
  }
  return {counted ? static_cast<double>(voiced) / counted : 0.0, worst};
}

TEST(Pitch, SteadyTonesAreVoicedAtTheirF0) {
  for (double f0 : {70.0, 110.0, 220.0, 330.0, 450.0}) {
    const auto f0At = [f0](double) { return f0; };
    const auto frames = trackPitch(harmonicTone(1.0, f0At), kRate);
    ASSERT_EQ(frames.size(), 200u);  // centres at 0, 5, ..., 995 ms
    const auto summary = summarise(frames, f0At, 0.05, 0.95);
    EXPECT_EQ(summary.voicedFraction, 1.0) << f0 << " Hz";
    EXPECT_LT(summary.worstRelativeError, 0.005) << f0 << " Hz";  // under 9 cents
  }
}

TEST(Pitch, FollowsAGlideWithoutOctaveJumps) {
  // One octave up and back down over a second, as in an exclamation.
  const auto f0At = [](double t) { return 120.0 * std::pow(2.0, std::sin(std::numbers::pi * t)); };
  const auto frames = trackPitch(harmonicTone(1.0, f0At), kRate);
  const auto summary = summarise(frames, f0At, 0.05, 0.95);
  EXPECT_EQ(summary.voicedFraction, 1.0);
  EXPECT_LT(summary.worstRelativeError, 0.02);
}

TEST(Pitch, SilenceAndNoiseAreUnvoiced) {
  const std::vector<float> silence(kRate, 0.0f);
  for (const auto& frame : trackPitch(silence, kRate)) EXPECT_EQ(frame.f0Hz, 0.0f);

  std::mt19937 random(7);
  std::normal_distribution<float> gaussian(0.0f, 0.1f);
  std::vector<float> noise(kRate);
  for (float& sample : noise) sample = gaussian(random);
  int voiced = 0;
  const auto frames = trackPitch(noise, kRate);
  for (const auto& frame : frames) voiced += frame.f0Hz > 0.0f;
  EXPECT_LT(voiced, static_cast<int>(frames.size()) / 20) << "white noise is not voiced speech";
}

TEST(Pitch, VoicingStartsAndEndsWhereTheToneDoes) {
  // 0.3 s silence, 0.4 s of 150 Hz, 0.3 s silence: boundaries found within 15 ms.
  auto samples = harmonicTone(1.0, [](double) { return 150.0; });
  for (size_t n = 0; n < samples.size(); ++n) {
    const double t = static_cast<double>(n) / kRate;
    if (t < 0.3 || t >= 0.7) samples[n] = 0.0f;
  }
  const auto frames = trackPitch(samples, kRate);
  for (size_t k = 0; k < frames.size(); ++k) {
    const double t = static_cast<double>(k) * 0.005;
    if (t < 0.285 || t > 0.715) {
      EXPECT_EQ(frames[k].f0Hz, 0.0f) << "t = " << t;
    }
    if (t > 0.315 && t < 0.685) {
      EXPECT_NEAR(frames[k].f0Hz, 150.0f, 1.0f) << "t = " << t;
    }
  }
}

TEST(Pitch, EmptyAndTinyInputs) {
  EXPECT_TRUE(trackPitch({}, kRate).empty());
  const std::vector<float> one(1, 0.5f);
  EXPECT_EQ(trackPitch(one, kRate).size(), 1u);
  const std::vector<float> short_(100, 0.1f);  // shorter than the window: zero-padded, no crash
  EXPECT_EQ(trackPitch(short_, kRate).size(), 2u);
}

TEST(Pitch, LookaheadIsHalfTheWindowPlusTheDecisionLag) {
  OnlinePitchTracker tracker({}, kRate);
  const PitchOptions defaults;
  EXPECT_EQ(tracker.lookaheadSamples(), static_cast<int>(defaults.windowMs * 16 / 2) + defaults.decisionLagFrames * 80);
  // Streaming: a frame is released exactly when its look-ahead has arrived.
  const auto tone = harmonicTone(0.5, [](double) { return 200.0; });
  for (size_t fed = 1; fed <= tone.size(); ++fed) {
    tracker.acceptWaveform(std::span(tone).subspan(fed - 1, 1));
    const auto available = static_cast<long long>(fed);
    const long long expected =
        available >= tracker.lookaheadSamples() ? (available - tracker.lookaheadSamples()) / 80 + 1 : 0;
    ASSERT_EQ(tracker.numFramesReady(), expected) << "after " << fed << " samples";
  }
}

TEST(Pitch, RejectsImpossibleOptions) {
  PitchOptions inverted;
  inverted.minF0Hz = 300.0;
  inverted.maxF0Hz = 100.0;
  EXPECT_THROW(OnlinePitchTracker(inverted, kRate), Error);
  PitchOptions tooLow;
  tooLow.minF0Hz = 20.0;  // a 50 ms period does not fit the 30 ms window
  EXPECT_THROW(OnlinePitchTracker(tooLow, kRate), Error);
}

}  // namespace
}  // namespace th::features
