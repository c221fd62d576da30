// Streaming == batch: the same real recording fed in chunks of any size gives the same frames, bit for bit,
// and frames are released as soon as (and not before) their look-ahead has arrived.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "feature_test_audio.h"
#include "features/online_features.h"

namespace th::features {
namespace {

// Feeds `samples` in chunks produced by `nextChunkSize`, reading frames as they become ready (as the live
// pipeline does), then finishes. Returns all frames, row-major.
template <typename ChunkSize>
std::vector<float> runStreaming(const std::vector<float>& samples, const FeatureOptions& options,
                                ChunkSize nextChunkSize) {
  OnlineFeatureExtractor extractor(options);
  const int width = extractor.layout().size();
  std::vector<float> frames;
  std::vector<float> row(static_cast<size_t>(width));
  int next = 0;
  size_t position = 0;
  while (position < samples.size()) {
    const size_t count = std::min(nextChunkSize(), samples.size() - position);
    extractor.acceptWaveform(std::span(samples).subspan(position, count));
    position += count;
    for (; next < extractor.numFramesReady(); ++next) {
      extractor.getFrame(next, row);
      frames.insert(frames.end(), row.begin(), row.end());
    }
  }
  extractor.inputFinished();
  for (; next < extractor.numFramesReady(); ++next) {
    extractor.getFrame(next, row);
    frames.insert(frames.end(), row.begin(), row.end());
  }
  return frames;
}

void expectBitIdentical(const std::vector<float>& expected, const std::vector<float>& actual, const char* what) {
  ASSERT_EQ(expected.size(), actual.size()) << what;
  EXPECT_EQ(0, std::memcmp(expected.data(), actual.data(), expected.size() * sizeof(float))) << what;
}

class StreamingEqualsBatch : public ::testing::TestWithParam<EnergyNormalisation> {};

TEST_P(StreamingEqualsBatch, FixedChunkSizesGiveBitIdenticalFrames) {
  const auto& speech = test::beat2Speech(12.0);
  FeatureOptions options;
  options.energyNormalisation = GetParam();
  const FeatureMatrix batch = computeFeatures(speech, options);
  ASSERT_GT(batch.numFrames(), 300);
  for (size_t chunk : {size_t{1}, size_t{7}, size_t{160}, size_t{4096}}) {
    const auto streamed = runStreaming(speech, options, [chunk] { return chunk; });
    expectBitIdentical(batch.values, streamed, ("chunk size " + std::to_string(chunk)).c_str());
  }
}

TEST_P(StreamingEqualsBatch, RandomChunkSizesGiveBitIdenticalFrames) {
  const auto& speech = test::beat2Speech(12.0);
  FeatureOptions options;
  options.energyNormalisation = GetParam();
  options.framesPerSecond = 47.0;  // a rate whose frame centres fall between samples
  const FeatureMatrix batch = computeFeatures(speech, options);
  std::mt19937 random(1234);
  std::uniform_int_distribution<size_t> size(0, 3000);  // including empty chunks
  const auto streamed = runStreaming(speech, options, [&] { return size(random); });
  expectBitIdentical(batch.values, streamed, "random chunks");
}

INSTANTIATE_TEST_SUITE_P(EnergyModes, StreamingEqualsBatch,
                         ::testing::Values(EnergyNormalisation::kRunning, EnergyNormalisation::kUtterance,
                                           EnergyNormalisation::kNone));

TEST(Streaming, FramesAreReleasedOnceTheirLookaheadHasArrived) {
  const auto& speech = test::beat2Speech(6.0);
  FeatureOptions options;  // running normalisation: frames flow before the input ends
  OnlineFeatureExtractor extractor(options);
  const FeatureLookahead lookahead = extractor.lookahead();
  const double sampleRate = OnlineFeatureExtractor::kSampleRateHz;
  const double frameSeconds = 1.0 / options.framesPerSecond;
  size_t fed = 0;
  int released = 0;
  while (fed < speech.size()) {
    const size_t count = std::min<size_t>(160, speech.size() - fed);
    extractor.acceptWaveform(std::span(speech).subspan(fed, count));
    fed += count;
    const int ready = extractor.numFramesReady();
    ASSERT_GE(ready, released) << "frames are never withdrawn";
    released = ready;
    const double inputSeconds = static_cast<double>(fed) / sampleRate;
    if (ready > 0) {
      // The newest released frame's look-ahead is covered by the input (its F0 comes from the pitch frame
      // nearest its time, which may lie up to one pitch hop earlier than the worst case the total assumes)...
      const double pitchHopSeconds = options.pitch.hopMs / 1000.0;
      EXPECT_LE(extractor.frameTimeSeconds(ready - 1) + lookahead.totalMs / 1000.0 - pitchHopSeconds,
                inputSeconds + 1e-9);
    }
    // ...and a frame is not held back longer than its look-ahead plus one frame and one chunk.
    const double latestDue = inputSeconds - lookahead.totalMs / 1000.0 - frameSeconds - 0.01;
    if (latestDue > 0) {
      EXPECT_GE(extractor.frameTimeSeconds(ready), latestDue);
    }
  }
  EXPECT_LE(lookahead.f0Ms, 50.0) << "the F0 tracker's look-ahead budget";
}

// Without the pitch tracker (the live mouth's extractor), a frame's MFCCs and energy are the same values, and
// they can be read as soon as the frame's own MFCC window has arrived.
TEST(Streaming, WithoutPitchTheMfccsComeAsSoonAsTheirWindow) {
  const auto& speech = test::beat2Speech(4.0);
  FeatureOptions withPitch;
  FeatureOptions withoutPitch;
  withoutPitch.trackPitch = false;
  OnlineFeatureExtractor reference(withPitch);
  OnlineFeatureExtractor early(withoutPitch);
  const double mfccSeconds = early.lookahead().mfccMs / 1000.0;
  EXPECT_EQ(early.lookahead().f0Ms, 0.0);
  const int numMfcc = early.layout().numMfcc;
  std::vector<float> a(static_cast<size_t>(numMfcc));
  std::vector<float> b(static_cast<size_t>(numMfcc));
  int compared = 0;
  for (size_t fed = 0; fed < speech.size();) {
    const size_t count = std::min<size_t>(160, speech.size() - fed);
    reference.acceptWaveform(std::span(speech).subspan(fed, count));
    early.acceptWaveform(std::span(speech).subspan(fed, count));
    fed += count;
    const double inputSeconds = static_cast<double>(fed) / OnlineFeatureExtractor::kSampleRateHz;
    const int ready = early.numBaseFramesReady();
    // Released no later than its window allows (one chunk of 10 ms), and not before.
    EXPECT_GE(early.frameTimeSeconds(ready), inputSeconds - mfccSeconds - 0.0101);
    if (ready > 0) {
      EXPECT_LE(early.frameTimeSeconds(ready - 1) + mfccSeconds, inputSeconds + 1e-9);
    }
    EXPECT_GT(ready, reference.numBaseFramesReady() - 1) << "never later than with the pitch tracker";
  }
  reference.inputFinished();
  early.inputFinished();
  ASSERT_EQ(early.numBaseFramesReady(), reference.numBaseFramesReady());
  for (int f = 0; f < early.numBaseFramesReady(); ++f, ++compared) {
    reference.getMfcc(f, a);
    early.getMfcc(f, b);
    ASSERT_EQ(a, b) << "frame " << f;
    ASSERT_EQ(reference.getEnergy(f), early.getEnergy(f)) << "frame " << f;
  }
  EXPECT_EQ(compared, 120);
}

TEST(Streaming, UtteranceNormalisationReleasesFramesOnlyAtTheEnd) {
  const auto& speech = test::beat2Speech(3.0);
  FeatureOptions options;
  options.energyNormalisation = EnergyNormalisation::kUtterance;
  OnlineFeatureExtractor extractor(options);
  extractor.acceptWaveform(speech);
  EXPECT_EQ(0, extractor.numFramesReady());
  extractor.inputFinished();
  EXPECT_EQ(90, extractor.numFramesReady());  // frames at 0, 1/30, ... up to the last sample (2.9999 s)
  EXPECT_TRUE(extractor.isLastFrame(89));
}

}  // namespace
}  // namespace th::features
