// The streaming resampler: chunked input gives the whole-buffer result, and output sample n is at time
// n / outputRate (no filter delay).
#include "audio/resampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "audio_test_files.h"
#include "core/error.h"

namespace {

using th::audio::Resampler;

std::vector<float> resampleInChunks(const std::vector<float>& input, double inputRateHz, double outputRateHz,
                                    size_t chunkSize) {
  Resampler resampler(inputRateHz, outputRateHz);
  std::vector<float> output;
  for (size_t start = 0; start < input.size(); start += chunkSize) {
    const size_t length = std::min(chunkSize, input.size() - start);
    resampler.process(std::span<const float>(input).subspan(start, length), output);
  }
  resampler.finish(output);
  return output;
}

// ---- chunked == whole buffer ----

struct ChunkCase {
  int inputRateHz;
  size_t chunkSize;
};

class ResamplerChunkTest : public ::testing::TestWithParam<ChunkCase> {};

TEST_P(ResamplerChunkTest, ChunkedEqualsWholeBuffer) {
  const auto [inputRateHz, chunkSize] = GetParam();
  // Real speech at its own rate (24 kHz), resampled to the input rate under test first.
  const auto arctic = th::test::readArcticPrompt();
  const std::vector<float> input = inputRateHz == arctic.sampleRateHz
                                       ? arctic.samples
                                       : th::audio::resample(arctic.samples, arctic.sampleRateHz, inputRateHz);
  const std::vector<float> whole = th::audio::resample(input, inputRateHz, 16000);
  const std::vector<float> chunked = resampleInChunks(input, inputRateHz, 16000, chunkSize);
  // The whole-buffer helper trims soxr's rounding surplus; the stream may end up to one sample longer.
  ASSERT_GE(chunked.size(), whole.size());
  ASSERT_LE(chunked.size(), whole.size() + 1);
  size_t differing = 0;
  for (size_t n = 0; n < whole.size(); ++n) differing += chunked[n] != whole[n] ? 1 : 0;
  // soxr is bit-exact under chunking: its filter state does not depend on how the input was cut.
  EXPECT_EQ(differing, 0u) << "of " << whole.size() << " samples";
}

INSTANTIATE_TEST_SUITE_P(Chunks, ResamplerChunkTest,
                         ::testing::Values(ChunkCase{44100, 1}, ChunkCase{44100, 7}, ChunkCase{44100, 160},
                                           ChunkCase{44100, 4096}, ChunkCase{24000, 1}, ChunkCase{24000, 7},
                                           ChunkCase{24000, 160}, ChunkCase{24000, 4096}, ChunkCase{8000, 1},
                                           ChunkCase{8000, 7}, ChunkCase{8000, 160}, ChunkCase{8000, 4096},
                                           ChunkCase{11025, 7}, ChunkCase{96000, 7}),
                         [](const auto& testInfo) {
                           return std::to_string(testInfo.param.inputRateHz) + "Hz_chunk" +
                                  std::to_string(testInfo.param.chunkSize);
                         });

// ---- time alignment ----

// Position of the largest |x| refined by a parabola through it and its neighbours (in samples).
double peakPosition(const std::vector<float>& x) {
  size_t best = 1;
  for (size_t n = 1; n + 1 < x.size(); ++n) {
    if (std::abs(x[n]) > std::abs(x[best])) best = n;
  }
  const double left = x[best - 1], centre = x[best], right = x[best + 1];
  const double curvature = left - 2.0 * centre + right;
  return static_cast<double>(best) + (curvature != 0.0 ? 0.5 * (left - right) / curvature : 0.0);
}

struct ClickCase {
  int inputRateHz;
  size_t clickSample;
};

class ResamplerAlignmentTest : public ::testing::TestWithParam<ClickCase> {};

TEST_P(ResamplerAlignmentTest, ClickStaysAtItsTime) {
  const auto [inputRateHz, clickSample] = GetParam();
  std::vector<float> input(static_cast<size_t>(inputRateHz), 0.0f);  // one second
  ASSERT_LT(clickSample, input.size());
  input[clickSample] = 0.9f;
  const double expected = static_cast<double>(clickSample) * 16000.0 / inputRateHz;
  for (size_t chunkSize : {size_t{160}, input.size()}) {
    const std::vector<float> output = resampleInChunks(input, inputRateHz, 16000, chunkSize);
    // The band-limited click is a sinc; its peak, refined between samples, sits where the click was.
    EXPECT_NEAR(peakPosition(output), expected, 0.01) << "chunks of " << chunkSize;
  }
}

// Clicks at times that fall on a 16 kHz sample: a parabola through a sampled sinc peak is biased (by up to
// 0.1 sample) when the true peak lies between samples, so sub-sample delay is checked with sines below.
INSTANTIATE_TEST_SUITE_P(Clicks, ResamplerAlignmentTest,
                         ::testing::Values(ClickCase{44100, 22050}, ClickCase{48000, 24000}, ClickCase{48000, 24003},
                                           ClickCase{8000, 4000}, ClickCase{8000, 4001}, ClickCase{22050, 11025},
                                           ClickCase{96000, 48006}, ClickCase{11025, 2205}),
                         [](const auto& testInfo) {
                           return std::to_string(testInfo.param.inputRateHz) + "Hz_at" +
                                  std::to_string(testInfo.param.clickSample);
                         });

// The phase of a sine measures the delay to a small fraction of a sample: fit a sin + b cos over the middle
// of the output (away from the start and end transients) and turn the phase into time.
TEST(Resampler, SinePhaseShowsNoDelay) {
  for (int inputRateHz : {8000, 11025, 22050, 24000, 44100, 48000, 96000}) {
    for (double frequencyHz : {150.0, 1000.0, 3000.0}) {
      const std::vector<float> input = th::test::sine(frequencyHz, 0.5, inputRateHz, static_cast<size_t>(inputRateHz));
      for (size_t chunkSize : {size_t{7}, input.size()}) {
        const std::vector<float> output = resampleInChunks(input, inputRateHz, 16000, chunkSize);
        double sinPart = 0.0, cosPart = 0.0;
        for (size_t n = 2000; n < 14000; ++n) {
          const double phase = 2.0 * std::numbers::pi * frequencyHz * static_cast<double>(n) / 16000.0;
          sinPart += output[n] * std::sin(phase);
          cosPart += output[n] * std::cos(phase);
        }
        // output ~ A sin(w (t - delay)) = A (sin wt cos wd - cos wt sin wd). Measured: below 1e-6 samples at
        // every rate and frequency here (soxr removes its linear-phase filter's delay exactly).
        const double delaySamples = std::atan2(-cosPart, sinPart) / (2.0 * std::numbers::pi * frequencyHz) * 16000.0;
        EXPECT_NEAR(delaySamples, 0.0, 1e-3)
            << inputRateHz << " Hz in, " << frequencyHz << " Hz sine, chunks of " << chunkSize;
      }
    }
  }
}

TEST(Resampler, StreamLengthFollowsTheRatio) {
  for (int inputRateHz : {8000, 11025, 22050, 44100, 48000, 96000}) {
    const std::vector<float> input = th::test::sine(300.0, 0.5, inputRateHz, 12345);
    const auto output = resampleInChunks(input, inputRateHz, 16000, 1000);
    EXPECT_NEAR(static_cast<double>(output.size()), 12345.0 * 16000.0 / inputRateHz, 1.0) << inputRateHz;
  }
}

TEST(Resampler, NonPositiveRatesAreRejected) {
  EXPECT_THROW(Resampler(0.0, 16000.0), th::Error);
  EXPECT_THROW(Resampler(44100.0, -1.0), th::Error);
  EXPECT_THROW(Resampler(std::nan(""), 16000.0), th::Error);
}

TEST(Resampler, EmptyInputGivesNoOutput) {
  Resampler resampler(44100, 16000);
  std::vector<float> output;
  resampler.process({}, output);
  resampler.finish(output);
  EXPECT_TRUE(output.empty());
  EXPECT_TRUE(th::audio::resample({}, 44100, 16000).empty());
}

}  // namespace
