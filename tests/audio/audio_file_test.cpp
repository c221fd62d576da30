// Reading recordings: every container, rate and channel count we accept comes out as 16 kHz mono of the
// right length, at the right level and in the right place in time.
#include "audio/audio_file.h"

#include <gtest/gtest.h>
#include <sndfile.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "audio_test_files.h"

namespace {

using th::audio::AudioClip;
using th::audio::kEngineSampleRateHz;

double rms(const std::vector<float>& x, size_t begin, size_t end) {
  double sum = 0.0;
  for (size_t n = begin; n < end; ++n) sum += static_cast<double>(x[n]) * x[n];
  return std::sqrt(sum / static_cast<double>(end - begin));
}

// Normalised correlation of x[begin, end) with y[begin + lag, end + lag).
double correlation(const std::vector<float>& x, const std::vector<float>& y, size_t begin, size_t end, long lag = 0) {
  double xy = 0.0, xx = 0.0, yy = 0.0;
  for (size_t n = begin; n < end; ++n) {
    const double a = x[n];
    const double b = y[static_cast<size_t>(static_cast<long>(n) + lag)];
    xy += a * b;
    xx += a * a;
    yy += b * b;
  }
  return xy / std::sqrt(xx * yy);
}

size_t expectedLength(size_t inputSamples, int inputRateHz) {
  return static_cast<size_t>(
      std::llround(static_cast<double>(inputSamples) * kEngineSampleRateHz / static_cast<double>(inputRateHz)));
}

// ---- containers: the same real recording as 16-bit WAV, FLAC and Ogg Vorbis ----

class ContainerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    arctic_ = th::test::readArcticPrompt();
    ASSERT_EQ(arctic_.sampleRateHz, 24000);
    reference_ = th::audio::readAudioFile(arctic_.path);
  }
  AudioClip writeAndRead(const std::string& fileName, int format) {
    const auto path = folder_.path() / fileName;
    th::test::writeSoundFile(path, arctic_.samples, arctic_.sampleRateHz, 1, format);
    return th::audio::readAudioFile(path);
  }

  th::test::TemporaryFolder folder_;
  th::test::RawRecording arctic_;
  AudioClip reference_;
};

TEST_F(ContainerTest, RealWavIs16kMonoOfTheRightLength) {
  EXPECT_EQ(reference_.sampleRateHz, kEngineSampleRateHz);
  EXPECT_EQ(reference_.sourceRateHz, 24000);
  EXPECT_EQ(reference_.sourceChannels, 1);
  // 80520 samples at 24 kHz = 3.355 s = 53680 samples at 16 kHz.
  EXPECT_NEAR(static_cast<double>(reference_.samples.size()), 53680.0, 1.0);
  EXPECT_NEAR(reference_.durationSeconds(), 3.355, 1e-4);
  // Resampling keeps the level of speech (its energy is far below the 8 kHz cut-off).
  const double before = rms(arctic_.samples, 0, arctic_.samples.size());
  EXPECT_NEAR(rms(reference_.samples, 0, reference_.samples.size()) / before, 1.0, 0.01);
}

TEST_F(ContainerTest, Wav16WrittenByLibsndfileReadsBackIdentically) {
  const AudioClip clip = writeAndRead("copy.wav", SF_FORMAT_WAV | SF_FORMAT_PCM_16);
  EXPECT_EQ(clip.samples, reference_.samples);  // 16-bit in, 16-bit out: bit for bit
}

TEST_F(ContainerTest, FlacIsLosslessSoReadsBackIdentically) {
  const AudioClip clip = writeAndRead("copy.flac", SF_FORMAT_FLAC | SF_FORMAT_PCM_16);
  EXPECT_EQ(clip.sourceRateHz, 24000);
  EXPECT_EQ(clip.samples, reference_.samples);
}

TEST_F(ContainerTest, OggVorbisIsLossyButAlignedAndClose) {
  const AudioClip clip = writeAndRead("copy.ogg", SF_FORMAT_OGG | SF_FORMAT_VORBIS);
  EXPECT_EQ(clip.sourceRateHz, 24000);
  ASSERT_NEAR(static_cast<double>(clip.samples.size()), static_cast<double>(reference_.samples.size()), 1.0);
  const size_t end = std::min(clip.samples.size(), reference_.samples.size()) - 16;
  const double atZero = correlation(reference_.samples, clip.samples, 16, end);
  EXPECT_GT(atZero, 0.995);  // measured 0.9985 (Vorbis at libsndfile's default quality)
  // No codec delay: lag 0 beats a sample either side.
  EXPECT_GT(atZero, correlation(reference_.samples, clip.samples, 16, end, -1));
  EXPECT_GT(atZero, correlation(reference_.samples, clip.samples, 16, end, 1));
  EXPECT_NEAR(rms(clip.samples, 0, clip.samples.size()) / rms(reference_.samples, 0, reference_.samples.size()), 1.0,
              0.05);
}

// ---- rates and channel counts: a 440 Hz sine written at every rate, read back as a 440 Hz sine at 16 kHz
// ----

struct RateAndChannels {
  int rateHz;
  int channels;
};

class RateChannelTest : public ::testing::TestWithParam<RateAndChannels> {};

TEST_P(RateChannelTest, SineComesBackAt16kMonoAlignedAndAtTheMeanLevel) {
  const auto [rateHz, channels] = GetParam();
  constexpr double kFrequencyHz = 440.0;
  const double seconds = 0.75;  // not a whole number of 16 kHz samples at 11.025 or 22.05 kHz
  const auto numFrames = static_cast<size_t>(std::llround(seconds * rateHz));
  // Channel c carries the sine at amplitude 0.2 + 0.1 c: the mean (what downmixing must give) differs from
  // every single channel, so a reader that took one channel would fail.
  std::vector<float> interleaved(numFrames * static_cast<size_t>(channels));
  double meanAmplitude = 0.0;
  for (int c = 0; c < channels; ++c) {
    const double amplitude = 0.2 + 0.1 * c;
    meanAmplitude += amplitude / channels;
    const std::vector<float> channel = th::test::sine(kFrequencyHz, amplitude, rateHz, numFrames);
    for (size_t n = 0; n < numFrames; ++n)
      interleaved[n * static_cast<size_t>(channels) + static_cast<size_t>(c)] = channel[n];
  }
  th::test::TemporaryFolder folder;
  const auto path = folder.path() / ("sine_" + std::to_string(rateHz) + "_" + std::to_string(channels) + ".wav");
  th::test::writeSoundFile(path, interleaved, rateHz, channels, SF_FORMAT_WAV | SF_FORMAT_PCM_16);

  const AudioClip clip = th::audio::readAudioFile(path);
  EXPECT_EQ(clip.sampleRateHz, kEngineSampleRateHz);
  EXPECT_EQ(clip.sourceRateHz, rateHz);
  EXPECT_EQ(clip.sourceChannels, channels);
  ASSERT_NEAR(static_cast<double>(clip.samples.size()), static_cast<double>(expectedLength(numFrames, rateHz)), 1.0);

  // The ideal: the same sine, same phase, sampled at 16 kHz. Ends are skipped: the written sine starts and
  // stops abruptly, which rings through any band-limiting filter for a few milliseconds.
  const std::vector<float> ideal =
      th::test::sine(kFrequencyHz, meanAmplitude, kEngineSampleRateHz, clip.samples.size());
  const size_t margin = kEngineSampleRateHz / 50;  // 20 ms
  const size_t end = clip.samples.size() - margin;
  // Correlation 0.9999 allows a phase error of 0.014 rad = 5 us = 0.08 samples at 16 kHz.
  EXPECT_GT(correlation(ideal, clip.samples, margin, end), 0.9999);
  EXPECT_NEAR(rms(clip.samples, margin, end) / (meanAmplitude / std::numbers::sqrt2), 1.0, 0.01);
}

INSTANTIATE_TEST_SUITE_P(
    AllRatesAndLayouts, RateChannelTest,
    ::testing::Values(RateAndChannels{8000, 1}, RateAndChannels{11025, 1}, RateAndChannels{16000, 1},
                      RateAndChannels{22050, 1}, RateAndChannels{44100, 1}, RateAndChannels{48000, 1},
                      RateAndChannels{96000, 1}, RateAndChannels{8000, 2}, RateAndChannels{11025, 2},
                      RateAndChannels{22050, 2}, RateAndChannels{44100, 2}, RateAndChannels{48000, 2},
                      RateAndChannels{96000, 2}, RateAndChannels{8000, 6}, RateAndChannels{11025, 6},
                      RateAndChannels{22050, 6}, RateAndChannels{44100, 6}, RateAndChannels{48000, 6},
                      RateAndChannels{96000, 6}),
    [](const auto& testInfo) {
      return std::to_string(testInfo.param.rateHz) + "Hz_" + std::to_string(testInfo.param.channels) + "ch";
    });

// The same decoder from memory: a FLAC held in a buffer decodes exactly as the file does.
TEST(DecodeAudio, BytesInMemoryDecodeLikeTheFile) {
  th::test::TemporaryFolder folder;
  const auto arctic = th::test::readArcticPrompt();
  const auto path = folder.path() / "arctic.flac";
  th::test::writeSoundFile(path, arctic.samples, arctic.sampleRateHz, 1, SF_FORMAT_FLAC | SF_FORMAT_PCM_16);
  const std::vector<char> bytes = th::test::readBytes(path);
  const AudioClip fromMemory = th::audio::decodeAudio(bytes.data(), bytes.size(), "arctic.flac");
  const AudioClip fromFile = th::audio::readAudioFile(path);
  EXPECT_EQ(fromMemory.samples, fromFile.samples);
  EXPECT_EQ(fromMemory.sourceRateHz, 24000);
}

// outputRateHz = 0 keeps the file's own rate and does not touch the samples.
TEST(ReadOptions, ZeroOutputRateKeepsTheSourceRate) {
  const auto arctic = th::test::readArcticPrompt();
  th::audio::AudioReadOptions options;
  options.outputRateHz = 0;
  const AudioClip clip = th::audio::readAudioFile(arctic.path, options);
  EXPECT_EQ(clip.sampleRateHz, 24000);
  EXPECT_EQ(clip.samples, arctic.samples);
}

// Float files may hold levels beyond full scale (some hold 16-bit integer values as floats): passed on as
// they are, not clipped and not rejected.
TEST(FloatFiles, LevelsBeyondFullScaleArePassedOn) {
  th::test::TemporaryFolder folder;
  const auto path = folder.path() / "loud_float.wav";
  const std::vector<float> samples = {2.0f, -3.5f, 32767.0f, -32768.0f, 0.25f};
  th::test::writeSoundFile(path, samples, 16000, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT);
  EXPECT_EQ(th::audio::readAudioFile(path).samples, samples);
}

// writeWav16 quantises with the reader's factor, so 16-bit audio survives a write and read bit for bit (with
// libsndfile's own float writer it would shrink by 32767/32768 on every pass).
TEST(WriteWav16, RoundTripOf16BitSamplesIsExact) {
  th::test::TemporaryFolder folder;
  const auto arctic = th::test::readArcticPrompt();
  const auto path = folder.path() / "copy.wav";
  th::audio::writeWav16(path, arctic.samples, arctic.sampleRateHz);
  th::audio::AudioReadOptions keepRate;
  keepRate.outputRateHz = 0;
  EXPECT_EQ(th::audio::readAudioFile(path, keepRate).samples, arctic.samples);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".partial"));
}

TEST(WriteWav16, FullScaleClipsInsteadOfWrapping) {
  th::test::TemporaryFolder folder;
  const auto path = folder.path() / "loud.wav";
  th::audio::writeWav16(path, {1.5f, 1.0f, -1.0f, -2.0f, 0.5f}, 16000);
  th::audio::AudioReadOptions keepRate;
  keepRate.outputRateHz = 0;
  const std::vector<float> back = th::audio::readAudioFile(path, keepRate).samples;
  EXPECT_EQ(back, (std::vector<float>{32767.0f / 32768.0f, 32767.0f / 32768.0f, -1.0f, -1.0f, 0.5f}));
}

}  // namespace
