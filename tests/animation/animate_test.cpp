// animate(): a recording to FAP curves with the head and mouth models.
#include <gtest/gtest.h>

#include <vector>

#include "animation/animate.h"
#include "animation/head_data.h"
#include "animation/mouth_data.h"
#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "face/feature_points.h"

namespace {

using namespace th::animation;

struct Models {
  HeadModel head;
  MouthModel mouth;
  MouthModel mouthWithoutFaps;
};

const Models& models() {
  static const Models trained = [] {
    Models m;
    m.head = trainHeadModel({splitByTime(loadBeat2Head(), 0.75).first}, {.startStates = 8, .maxIterations = 30});
    m.mouthWithoutFaps = trainMouthModel({splitByTime(loadBeat2Mouth(), 0.75).first}, {.states = 3, .mixtures = 1});
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
  const th::video::Animation anim = animate(samples, &models().head, &models().mouth);
  EXPECT_DOUBLE_EQ(anim.framesPerSecond, 30.0);
  EXPECT_NEAR(anim.numFrames(), 300, 1);
  std::vector<int> expected = mouthFapNumbers(*models().mouth.fapMap);
  expected.insert(expected.end(), {48, 49, 50});
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(anim.faps, expected);
  EXPECT_TRUE(anim.values.allFinite());
  EXPECT_GT(anim.values.col(anim.columnOf(3)).maxCoeff(), 0.0);
  EXPECT_GE(anim.values.col(anim.columnOf(3)).minCoeff(), 0.0);  // open_jaw is unidirectional
}

TEST(Animate, EachModelAloneGivesItsOwnFaps) {
  const std::vector<float> samples = speech(3.0);
  EXPECT_EQ(animate(samples, &models().head, nullptr).faps, (std::vector<int>{48, 49, 50}));
  EXPECT_EQ(animate(samples, nullptr, &models().mouth).faps.front(), 3);
  EXPECT_EQ(animate(samples, nullptr, &models().mouth).columnOf(48), -1);
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
