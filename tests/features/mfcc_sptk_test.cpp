// MFCC against a reference we did not write: SPTK 3.9's `frame | mfcc` (the Debian `sptk` package), run at
// test time on real speech, compared coefficient by coefficient, frame by frame. The command line is built
// from the same MfccOptions our MfccComputer uses, so the two cannot silently drift apart.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/temporary_file.h"
#include "features/mfcc.h"
#include "features/online_features.h"

namespace {

namespace fs = std::filesystem;
using th::features::MfccComputer;
using th::features::MfccOptions;

constexpr int kSampleRateHz = 16000;
constexpr int kHopSamples = 160;  // 10 ms: SPTK frame i is centred at sample 160 i (its default framing)

// |ours - SPTK| <= kTolerance * max(1, |SPTK|): measured worst 1.9e-4 (see mfcc.h), almost all of it from our
// single-precision FFT. Absolute below 1 because small coefficients carry the same absolute rounding error.
constexpr double kTolerance = 5e-4;

using TemporaryFolder = th::TemporaryFolder;

std::string quoted(const fs::path& path) {
  return "'" + path.string() + "'";
}

// What `sptk frame -l L -p P | sptk mfcc ...` prints for the options our MfccComputer is built with: c1..cN
// and, with includeC0, c0 after them (SPTK's -0), as float32 rows.
std::vector<std::vector<float>> runSptk(const std::vector<float>& samples, const MfccOptions& options, int windowLength,
                                        const fs::path& folder) {
  const fs::path input = folder / "input.f32";
  const fs::path output = folder / "mfcc.f32";
  {
    // SPTK and HTK expect samples in 16-bit integer scale; the factor is a power of two, so no rounding.
    std::ofstream out(input, std::ios::binary);
    for (float sample : samples) {
      const float scaled = sample * 32768.0f;
      out.write(reinterpret_cast<const char*>(&scaled), sizeof(scaled));
    }
  }
  std::ostringstream command;
  command << "sptk frame -l " << windowLength << " -p " << kHopSamples << " < " << quoted(input) << " | sptk mfcc -l "
          << windowLength << " -L " << options.fftSize << " -m " << options.numCoefficients << " -n "
          << options.numMelBands << " -s " << kSampleRateHz / 1000.0 << " -c " << options.lifter << " -a "
          << options.preEmphasis << " -e " << options.filterbankFloor << (options.includeC0 ? " -0" : "") << " > "
          << quoted(output);
  const int status = std::system(command.str().c_str());
  if (status != 0) throw std::runtime_error("failed (status " + std::to_string(status) + "): " + command.str());

  const size_t rowSize = static_cast<size_t>(options.numCoefficients + (options.includeC0 ? 1 : 0));
  std::ifstream in(output, std::ios::binary);
  std::vector<float> values;
  float value = 0.0f;
  while (in.read(reinterpret_cast<char*>(&value), sizeof(value))) values.push_back(value);
  if (values.size() % rowSize != 0) throw std::runtime_error("SPTK output is not a whole number of frames");
  std::vector<std::vector<float>> rows;
  for (size_t start = 0; start < values.size(); start += rowSize) {
    rows.emplace_back(values.begin() + static_cast<long>(start), values.begin() + static_cast<long>(start + rowSize));
  }
  return rows;
}

// Our MfccComputer with SPTK's framing: frame i covers samples 160 i - L/2 .. 160 i + L/2 - 1, zeros outside.
std::vector<float> ourFrame(MfccComputer& mfcc, const std::vector<float>& samples, long long frame) {
  const long long length = mfcc.windowLength();
  const long long start = frame * kHopSamples - length / 2;
  std::vector<float> window(static_cast<size_t>(length));
  for (long long n = 0; n < length; ++n) {
    const long long index = start + n;
    window[static_cast<size_t>(n)] =
        index >= 0 && index < static_cast<long long>(samples.size()) ? samples[static_cast<size_t>(index)] : 0.0f;
  }
  std::vector<float> coefficients(static_cast<size_t>(mfcc.numOutputs()));
  mfcc.compute(window, coefficients);
  return coefficients;
}

struct Agreement {
  double maxAbsolute = 0.0;
  double maxRelative = 0.0;  // |ours - sptk| / max(1, |sptk|)
  int failures = 0;
};

void compareRows(const std::vector<std::vector<float>>& sptk, const auto& ours, int numFrames, Agreement& agreement,
                 const std::string& what) {
  for (int frame = 0; frame < numFrames; ++frame) {
    const std::vector<float>& reference = sptk[static_cast<size_t>(frame)];
    const std::vector<float> mine = ours(frame);
    ASSERT_EQ(mine.size(), reference.size());
    for (size_t k = 0; k < reference.size(); ++k) {
      const double error = std::abs(static_cast<double>(mine[k]) - reference[k]);
      agreement.maxAbsolute = std::max(agreement.maxAbsolute, error);
      agreement.maxRelative = std::max(agreement.maxRelative, error / std::max(1.0, std::abs(double{reference[k]})));
      if (error > kTolerance * std::max(1.0, std::abs(double{reference[k]}))) {
        if (++agreement.failures <= 10) {
          ADD_FAILURE() << what << ": frame " << frame << " coefficient " << k << ": ours " << mine[k] << ", SPTK "
                        << reference[k];
        }
      }
    }
  }
}

struct Recording {
  const char* name;
  const char* relativePath;
  double maxSeconds;
};

class MfccSptkTest : public ::testing::TestWithParam<Recording> {
 protected:
  static void SetUpTestSuite() {
    // A missing reference must fail loudly: a skipped comparison would look like a passing one.
    ASSERT_EQ(std::system("command -v sptk > /dev/null 2>&1"), 0)
        << "the `sptk` command (Debian package sptk, SPTK 3.9) is needed for this test";
  }

  std::vector<float> load() const {
    const Recording& recording = GetParam();
    th::audio::AudioClip clip = th::audio::readAudioFile(th::sharedDataPath(recording.relativePath));
    EXPECT_EQ(clip.sampleRateHz, kSampleRateHz);
    const auto limit = static_cast<size_t>(recording.maxSeconds * kSampleRateHz);
    if (clip.samples.size() > limit) clip.samples.resize(limit);
    return clip.samples;
  }

  TemporaryFolder folder_;
};

TEST_P(MfccSptkTest, EveryCoefficientOfEveryFrameMatches) {
  const std::vector<float> samples = load();
  for (bool includeC0 : {false, true}) {
    MfccOptions options;
    options.includeC0 = includeC0;
    MfccComputer mfcc(options, kSampleRateHz);
    const auto sptk = runSptk(samples, options, mfcc.windowLength(), folder_.path());
    // SPTK's frame emits one frame per hop from sample 0 until the hop passes the end of the input.
    const auto expectedFrames = static_cast<long long>((samples.size() + kHopSamples - 1) / kHopSamples);
    ASSERT_NEAR(static_cast<double>(sptk.size()), static_cast<double>(expectedFrames), 1.0);

    Agreement agreement;
    compareRows(
        sptk, [&](int frame) { return ourFrame(mfcc, samples, frame); }, static_cast<int>(sptk.size()), agreement,
        std::string(GetParam().name) + (includeC0 ? " (with c0)" : ""));
    EXPECT_EQ(agreement.failures, 0);
    std::printf("%s%s: %zu frames, max |error| %.3g, max relative %.3g\n", GetParam().name, includeC0 ? " with c0" : "",
                sptk.size(), agreement.maxAbsolute, agreement.maxRelative);
  }
}

// The streaming extractor at 100 frames/s frames MFCCs exactly as SPTK's `frame -p 160` does.
TEST_P(MfccSptkTest, OnlineExtractorAt100FpsMatchesSptk) {
  const std::vector<float> samples = load();
  th::features::FeatureOptions options;
  options.framesPerSecond = 100.0;
  options.contextFrames = 0;
  th::features::OnlineFeatureExtractor extractor(options);
  extractor.acceptWaveform(samples);
  extractor.inputFinished();
  MfccComputer mfcc(options.mfcc, kSampleRateHz);
  const auto sptk = runSptk(samples, options.mfcc, mfcc.windowLength(), folder_.path());
  const int numFrames = std::min(extractor.numFramesReady(), static_cast<int>(sptk.size()));
  ASSERT_GE(numFrames, static_cast<int>(sptk.size()) - 1);

  const auto& layout = extractor.layout();
  std::vector<float> row(static_cast<size_t>(layout.size()));
  Agreement agreement;
  compareRows(
      sptk,
      [&](int frame) {
        extractor.getFrame(frame, row);
        return std::vector<float>(row.begin() + th::features::FeatureLayout::kMfccBegin,
                                  row.begin() + th::features::FeatureLayout::kMfccBegin + layout.numMfcc);
      },
      numFrames, agreement, GetParam().name);
  EXPECT_EQ(agreement.failures, 0);
}

INSTANTIATE_TEST_SUITE_P(RealSpeech, MfccSptkTest,
                         ::testing::Values(Recording{"beat2_scott", "beat2/2_scott_0_1_1.wav", 10.0},
                                           Recording{"fda_sb001", "speech/fda-ue/sb001.wav", 1e9},
                                           Recording{"fda_rl001", "speech/fda-ue/rl001.wav", 1e9}),
                         [](const auto& testInfo) { return std::string(testInfo.param.name); });

}  // namespace
