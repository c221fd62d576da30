// The feature frame: its layout, deltas, context stacking, energy normalisation and frame clock.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

#include "core/error.h"
#include "feature_test_audio.h"
#include "features/online_features.h"

namespace th::features {
namespace {

TEST(FeatureLayout, NamesEveryColumnInOrder) {
  FeatureLayout layout;
  layout.numMfcc = 11;
  layout.contextFrames = 5;
  const auto names = layout.columnNames();
  ASSERT_EQ(static_cast<int>(names.size()), layout.size());
  EXPECT_EQ(layout.size(), 4 + 11 + 11 * 11);
  EXPECT_EQ(names[FeatureLayout::kF0Hz], "f0_hz");
  EXPECT_EQ(names[FeatureLayout::kEnergy], "energy");
  EXPECT_EQ(names[FeatureLayout::kDeltaF0], "d_f0");
  EXPECT_EQ(names[FeatureLayout::kDeltaEnergy], "d_energy");
  EXPECT_EQ(names[FeatureLayout::kMfccBegin], "mfcc1");
  EXPECT_EQ(names[layout.contextBegin()], "ctx_mfcc1_m5");
  EXPECT_EQ(names.back(), "ctx_mfcc11_p5");

  FeatureOptions withC0;
  withC0.mfcc.includeC0 = true;
  const auto c0Names = OnlineFeatureExtractor(withC0).layout().columnNames();
  EXPECT_EQ(c0Names[FeatureLayout::kMfccBegin + 11], "mfcc0");
  EXPECT_EQ(c0Names.back(), "ctx_mfcc0_p5");
}

TEST(Features, OneFramePerAnimationFrameAtAnyRate) {
  const auto& speech = test::beat2Speech(4.0);  // 64000 samples
  for (double fps : {10.0, 25.0, 30.0, 60.0, 200.0}) {
    FeatureOptions options = batchFeatureOptions();
    options.framesPerSecond = fps;
    const auto matrix = computeFeatures(speech, options);
    EXPECT_EQ(matrix.numFrames(), static_cast<int>(std::floor(63999.0 / 16000.0 * fps)) + 1) << fps;
  }
  FeatureOptions tooFast;
  tooFast.framesPerSecond = 250.0;
  EXPECT_THROW(OnlineFeatureExtractor{tooFast}, Error);
  FeatureOptions tooSlow;
  tooSlow.framesPerSecond = 5.0;
  EXPECT_THROW(OnlineFeatureExtractor{tooSlow}, Error);
}

TEST(Features, ContextStacksNeighbouringMfccsWithEdgesReplicated) {
  const auto& speech = test::beat2Speech(2.0);
  const auto matrix = computeFeatures(speech);
  const FeatureLayout& layout = matrix.layout;
  const int tc = layout.contextFrames;
  const int numMfcc = layout.numMfcc;
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    for (int offset = -tc; offset <= tc; ++offset) {
      const int source = std::clamp(frame + offset, 0, matrix.numFrames() - 1);
      for (int k = 0; k < numMfcc; ++k) {
        ASSERT_EQ(matrix.row(frame)[static_cast<size_t>(layout.contextBegin() + (offset + tc) * numMfcc + k)],
                  matrix.row(source)[static_cast<size_t>(FeatureLayout::kMfccBegin + k)]);
      }
    }
  }
}

TEST(Features, DeltasAreHtkRegressionOverTwoFrames) {
  const auto& speech = test::beat2Speech(3.0);
  const auto matrix = computeFeatures(speech);
  const auto at = [&](int frame, int column) {
    return static_cast<double>(matrix.row(std::clamp(frame, 0, matrix.numFrames() - 1))[static_cast<size_t>(column)]);
  };
  for (int t = 0; t < matrix.numFrames(); ++t) {
    const double expected = (at(t + 1, FeatureLayout::kEnergy) - at(t - 1, FeatureLayout::kEnergy) +
                             2.0 * (at(t + 2, FeatureLayout::kEnergy) - at(t - 2, FeatureLayout::kEnergy))) /
                            10.0;
    EXPECT_NEAR(at(t, FeatureLayout::kDeltaEnergy), expected, 1e-5) << t;
    if (at(t, FeatureLayout::kF0Hz) == 0.0) {
      EXPECT_EQ(at(t, FeatureLayout::kDeltaF0), 0.0) << t;
    }
    // Inside a voiced stretch the F0 delta is the plain regression too.
    bool allVoiced = true;
    for (int n = -2; n <= 2; ++n)
      allVoiced = allVoiced && at(t + n, FeatureLayout::kF0Hz) > 0.0 && t + n >= 0 && t + n < matrix.numFrames();
    if (allVoiced) {
      const double f0Delta = (at(t + 1, 0) - at(t - 1, 0) + 2.0 * (at(t + 2, 0) - at(t - 2, 0))) / 10.0;
      EXPECT_NEAR(at(t, FeatureLayout::kDeltaF0), f0Delta, 1e-3) << t;
    }
  }
}

TEST(Features, UtteranceNormalisedEnergyHasZeroMeanAndUnitSpread) {
  const auto& speech = test::beat2Speech(10.0);
  const auto matrix = computeFeatures(speech);  // batch: utterance normalisation
  double sum = 0.0;
  double squares = 0.0;
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    const double e = matrix.row(frame)[FeatureLayout::kEnergy];
    sum += e;
    squares += e * e;
  }
  const double mean = sum / matrix.numFrames();
  EXPECT_NEAR(mean, 0.0, 1e-4);
  EXPECT_NEAR(std::sqrt(squares / matrix.numFrames() - mean * mean), 1.0, 1e-3);
}

TEST(Features, EnergyNormalisationDoesNotDependOnRecordingLevel) {
  // A microphone never gives digital silence: dither at -90 dBFS (the recording has exact zeros, whose level
  // would sit on the log floor in both versions and so not move by 20 dB).
  std::vector<float> speech = test::beat2Speech(5.0);
  std::mt19937 random(3);
  std::uniform_real_distribution<float> dither(-3e-5f, 3e-5f);
  for (float& sample : speech) sample += dither(random);
  std::vector<float> quieter(speech);
  for (float& sample : quieter) sample *= 0.1f;  // -20 dB
  for (auto mode : {EnergyNormalisation::kUtterance, EnergyNormalisation::kRunning}) {
    FeatureOptions options;
    options.energyNormalisation = mode;
    const auto loud = computeFeatures(speech, options);
    const auto quiet = computeFeatures(quieter, options);
    for (int frame = 0; frame < loud.numFrames(); ++frame) {
      EXPECT_NEAR(loud.row(frame)[FeatureLayout::kEnergy], quiet.row(frame)[FeatureLayout::kEnergy], 0.02) << frame;
    }
  }
  // Without normalisation the level is in dB re full scale: 20 dB apart.
  FeatureOptions raw;
  raw.energyNormalisation = EnergyNormalisation::kNone;
  const auto loud = computeFeatures(speech, raw);
  const auto quiet = computeFeatures(quieter, raw);
  EXPECT_NEAR(loud.row(60)[FeatureLayout::kEnergy] - quiet.row(60)[FeatureLayout::kEnergy], 20.0, 0.1);
}

TEST(Features, PausesAreFlooredBelowTheLoudestFrame) {
  std::vector<float> speech = test::beat2Speech(4.0);
  std::fill(speech.begin() + 32000, speech.begin() + 48000, 0.0f);  // one second of digital silence
  FeatureOptions raw;
  raw.energyNormalisation = EnergyNormalisation::kNone;
  const auto matrix = computeFeatures(speech, raw);
  float loudest = -1e9f;  // before the silence: the floor follows the loudest frame so far (causal)
  for (int frame = 0; frame < 60; ++frame) loudest = std::max(loudest, matrix.row(frame)[FeatureLayout::kEnergy]);
  EXPECT_LT(loudest, 0.0f);
  EXPECT_GT(loudest, -40.0f);
  const float silent = matrix.row(75)[FeatureLayout::kEnergy];  // 2.5 s, inside the silence
  EXPECT_NEAR(silent, loudest - raw.energyRangeDb, 1e-3f) << "floored relative to the loudest frame so far";
}

TEST(Features, VoicedSpeechHasPlausibleF0) {
  const auto& speech = test::beat2Speech(20.0);
  const auto matrix = computeFeatures(speech);
  int voiced = 0;
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    const float f0 = matrix.row(frame)[FeatureLayout::kF0Hz];
    if (f0 > 0.0f) {
      ++voiced;
      EXPECT_GE(f0, 60.0f);
      EXPECT_LE(f0, 500.0f);
    }
  }
  // A talkative male speaker: most frames voiced, but not all.
  EXPECT_GT(voiced, matrix.numFrames() / 3);
  EXPECT_LT(voiced, matrix.numFrames() * 9 / 10);
}

}  // namespace
}  // namespace th::features
