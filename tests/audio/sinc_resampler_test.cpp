// The engine's own windowed-sinc resampler (what the WebAssembly build uses): the same samples however the input
// is cut, aligned with the input, tones passed or stopped as its filter says, and speech within a small error of
// libsoxr's (the native converter).
#include "audio/sinc_resampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "audio/resampler.h"
#include "audio_test_files.h"
#include "core/error.h"

namespace {

using th::audio::SincResampler;

std::vector<float> convert(const std::vector<float>& input, double from, double to, std::size_t chunk,
                           unsigned seed = 0) {
  SincResampler resampler(from, to);
  std::vector<float> output;
  std::vector<float> block;
  std::mt19937 random(seed);
  for (std::size_t start = 0; start < input.size();) {
    const std::size_t length =
        std::min(input.size() - start, seed == 0 ? chunk : 1 + random() % static_cast<unsigned>(chunk));
    block.resize(resampler.maxOutput(length));
    const std::size_t n = resampler.process(std::span<const float>(input).subspan(start, length), block);
    output.insert(output.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(n));
    start += length;
  }
  block.resize(resampler.maxOutput(0));
  const std::size_t n = resampler.finish(block);
  output.insert(output.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(n));
  return output;
}

std::vector<float> tone(double hz, double rate, double seconds) {
  std::vector<float> samples(static_cast<std::size_t>(seconds * rate));
  for (std::size_t n = 0; n < samples.size(); ++n)
    samples[n] = static_cast<float>(0.5 * std::sin(2.0 * std::numbers::pi * hz * static_cast<double>(n) / rate));
  return samples;
}

// RMS of a - b over the middle (away from the ends, where both filters see the edge), over RMS of b, in dB.
double errorDb(const std::vector<float>& a, const std::vector<float>& b, std::size_t margin) {
  double error = 0.0, power = 0.0;
  for (std::size_t n = margin; n + margin < std::min(a.size(), b.size()); ++n) {
    error += (a[n] - b[n]) * (a[n] - b[n]);
    power += b[n] * b[n];
  }
  return 10.0 * std::log10(error / power);
}

TEST(SincResampler, GivesTheSameSamplesHoweverTheInputIsCut) {
  const std::vector<float> input = tone(440.0, 48000.0, 1.3);
  const std::vector<float> whole = convert(input, 48000.0, 16000.0, input.size());
  EXPECT_EQ(whole.size(), static_cast<std::size_t>(std::llround(static_cast<double>(input.size()) / 3.0)));
  for (const unsigned seed : {1u, 2u}) EXPECT_EQ(convert(input, 48000.0, 16000.0, 300, seed), whole);
  EXPECT_EQ(convert(input, 48000.0, 16000.0, 128), whole);    // an AudioWorklet's block
  EXPECT_EQ(convert(input, 48000.0, 16000.0, 20000), whole);  // more than a call takes at once
}

TEST(SincResampler, IsAlignedWithTheInputAndPassesOrStopsTonesAsItsFilterSays) {
  for (const double rate : {44100.0, 48000.0, 96000.0, 8000.0}) {
    // A tone in the passband comes out as the same tone at the output's sample times.
    const double hz = 1000.0;
    const std::vector<float> out = convert(tone(hz, rate, 1.0), rate, 16000.0, 128);
    double largest = 0.0;
    for (std::size_t n = 200; n + 200 < out.size(); ++n)
      largest = std::max(
          largest, std::abs(out[n] - 0.5 * std::sin(2.0 * std::numbers::pi * hz * static_cast<double>(n) / 16000.0)));
    EXPECT_LT(largest, 2e-3) << rate << " Hz";
  }
  // Above the output's Nyquist frequency, a tone would alias: it is stopped.
  const std::vector<float> out = convert(tone(9000.0, 48000.0, 1.0), 48000.0, 16000.0, 128);
  double power = 0.0;
  for (std::size_t n = 200; n + 200 < out.size(); ++n) power += out[n] * out[n];
  EXPECT_LT(10.0 * std::log10(power / static_cast<double>(out.size() - 400) / 0.125), -70.0);
}

TEST(SincResampler, ConvertsSpeechAsLibsoxrDoes) {
  const auto arctic = th::test::readArcticPrompt();
  for (const double rate : {44100.0, 48000.0, 22050.0}) {
    const std::vector<float> input = th::audio::resample(arctic.samples, arctic.sampleRateHz, rate);
    const std::vector<float> ours = convert(input, rate, 16000.0, 128);
    const std::vector<float> soxr = th::audio::resample(input, rate, 16000.0);
    EXPECT_LE(ours.size(), soxr.size() + 1);
    EXPECT_GE(ours.size() + 1, soxr.size());
    const double db = errorDb(ours, soxr, 400);
    std::cout << rate << " Hz: " << db << " dB from libsoxr's\n";
    EXPECT_LT(db, -60.0) << rate << " Hz";
  }
}

TEST(SincResampler, RefusesRatesItCannotConvert) {
  EXPECT_THROW(SincResampler(0.0, 16000.0), th::Error);
  EXPECT_THROW(SincResampler(48000.0, std::nan("")), th::Error);
  EXPECT_THROW(SincResampler(2e6, 16000.0), th::Error);
  SincResampler resampler(48000.0, 16000.0);
  std::vector<float> out(resampler.maxOutput(0));
  resampler.finish(out);
  std::vector<float> in(10);
  out.resize(resampler.maxOutput(10));
  EXPECT_THROW(resampler.process(in, out), th::Error);
}

}  // namespace
