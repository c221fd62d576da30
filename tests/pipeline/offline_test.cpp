// animate(): a recording to FAP curves with the head and mouth models.
#include "pipeline/offline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "animation/head_data.h"
#include "animation/mouth_data.h"
#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "eval/head_corpus.h"
#include "eval/mouth_corpus.h"
#include "face/feature_points.h"

namespace {

using namespace th::animation;
using th::pipeline::animate;
using th::pipeline::AnimateOptions;

struct Models {
  HeadModel head;
  MouthModel mouth;
  MouthModel mouthWithoutFaps;
};

const Models& models() {
  static const Models trained = [] {
    Models m;
    m.head =
        trainHeadModel({splitByTime(th::eval::loadBeat2Head(), 0.75).first}, {.startStates = 8, .maxIterations = 30});
    m.mouthWithoutFaps =
        trainMouthModel({splitByTime(th::eval::loadBeat2Mouth(), 0.75).first}, {.states = 3, .mixtures = 1});
    m.mouth = m.mouthWithoutFaps;
    m.mouth.fapMap = defineMouthFapMap(th::face::loadIctFace(th::face::ictFaceDirectory()));
    return m;
  }();
  return trained;
}

std::vector<float> speech(double seconds) {
  const auto clip = th::audio::readAudioFile(th::sharedDataPath("beat2/audio_only/2_scott_0_4_4.wav"));
  return {clip.samples.begin(), clip.samples.begin() + static_cast<long>(seconds * clip.sampleRateHz)};
}

TEST(Animate, HeadAndMouthFapsInFapOrderAt30FramesPerSecond) {
  const std::vector<float> samples = speech(10.0);
  const th::face::FapTrack anim = animate(samples, &models().head, &models().mouth);
  EXPECT_DOUBLE_EQ(anim.framesPerSecond, 30.0);
  EXPECT_NEAR(anim.numFrames(), 300, 1);
  std::vector<int> expected = mouthFapNumbers(*models().mouth.fapMap);
  expected.insert(expected.end(), {19, 20, 23, 24, 25, 26, 48, 49, 50});  // the model's, and blinks and gaze
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(anim.faps, expected);
  EXPECT_TRUE(anim.values.allFinite());
  EXPECT_GT(anim.values.row(anim.rowOf(3)).maxCoeff(), 0.0);
  EXPECT_GE(anim.values.row(anim.rowOf(3)).minCoeff(), 0.0);  // open_jaw is unidirectional
}

TEST(Animate, EachModelAloneGivesItsOwnFaps) {
  const std::vector<float> samples = speech(3.0);
  const AnimateOptions noIdle{.idle = false};
  EXPECT_EQ(animate(samples, &models().head, nullptr, noIdle).faps, (std::vector<int>{48, 49, 50}));
  EXPECT_EQ(animate(samples, nullptr, &models().mouth, noIdle).faps.front(), 3);
  EXPECT_EQ(animate(samples, nullptr, &models().mouth, noIdle).rowOf(48), -1);
  EXPECT_GE(animate(samples, nullptr, &models().mouth).rowOf(19), 0) << "blinks come with the mouth alone too";
}

// Blinks, gaze shifts and the head at rest in silence are in the file, the same for a seed, other for another.
TEST(Animate, IdleBehaviourIsInTheFileAndFollowsTheSeed) {
  std::vector<float> samples = speech(20.0);
  samples.resize(samples.size() + 16000 * 4, 0.0f);  // 4 s of silence at the end
  const th::face::FapTrack a = animate(samples, &models().head, &models().mouth);
  const th::face::FapTrack b = animate(samples, &models().head, &models().mouth);
  AnimateOptions otherSeed;
  otherSeed.idleOptions.seed = 7;
  const th::face::FapTrack c = animate(samples, &models().head, &models().mouth, otherSeed);
  EXPECT_EQ(a.values, b.values);
  const Eigen::RowVectorXd lidA = a.values.row(a.rowOf(19));
  const Eigen::RowVectorXd lidC = c.values.row(c.rowOf(19));
  double largestDifference = 0.0;
  for (Eigen::Index t = 0; t < lidA.size(); ++t)
    largestDifference = std::max(largestDifference, std::abs(lidA[t] - lidC[t]));
  EXPECT_GT(largestDifference, 100.0) << "another seed blinks at other times";
  int blinks = 0;
  for (Eigen::Index t = 1; t < lidA.size(); ++t) blinks += lidA[t] > 512.0 && lidA[t - 1] <= 512.0;
  const double minutes = a.numFrames() / 30.0 / 60.0;
  EXPECT_GE(blinks / minutes, 8.0);
  EXPECT_LE(blinks / minutes, 30.0);
  // The last second is silence: the head has come to rest there, and no FAP in it is far from it.
  const int last = a.numFrames() - 1;
  for (const int fap : {48, 49, 50}) EXPECT_LT(std::abs(a.values(a.rowOf(fap), last)), 1e-3 * 1e5) << fap;
  const AnimateOptions noIdle{.idle = false};
  const th::face::FapTrack still = animate(samples, &models().head, &models().mouth, noIdle);
  EXPECT_EQ(still.rowOf(19), -1);
  EXPECT_GT(std::abs(still.values(still.rowOf(49), last)), std::abs(a.values(a.rowOf(49), last)));
}

TEST(Animate, RefusesWhatItCannotAnimate) {
  const std::vector<float> samples = speech(1.0);
  EXPECT_THROW(animate(samples, nullptr, nullptr), th::Error);
  try {
    animate(samples, nullptr, &models().mouthWithoutFaps);
    FAIL();
  } catch (const th::Error& e) {
    EXPECT_NE(std::string(e.what()).find("drives no FAPs"), std::string::npos) << e.what();
  }
  const std::vector<float> tooShort;
  EXPECT_THROW(animate(tooShort, &models().head, &models().mouth), th::Error);
}

}  // namespace
