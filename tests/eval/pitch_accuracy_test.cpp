// F0 accuracy on FDA-UE (laryngograph reference) must not regress. `talkinghead eval pitch` prints the full
// table beside Praat, RAPT, SWIPE and aubio; this test guards our own numbers.
#include <gtest/gtest.h>

#include "core/data_path.h"
#include "eval/pitch_corpus.h"

namespace th::features {
namespace {

th::eval::PitchScore scoreAt(double framesPerSecond) {
  const auto corpus = th::eval::loadPitchCorpus(sharedDataPath("speech/fda-ue"), 0.015);
  EXPECT_EQ(corpus.size(), 20u);
  FeatureOptions options = batchFeatureOptions();
  options.framesPerSecond = framesPerSecond;
  return th::eval::scoreOurTracker(corpus, options);
}

TEST(PitchAccuracy, FdaUeAtThirtyFramesPerSecond) {
  const th::eval::PitchScore score = scoreAt(30.0);
  EXPECT_EQ(score.frames(), 3220);
  EXPECT_LT(score.ffe(), 0.075);  // Praat scores 7.5 %, SWIPE 8.6 %, RAPT 9.8 % here
  EXPECT_LT(score.gpe(), 0.015);
}

TEST(PitchAccuracy, FdaUeAtFiveMilliseconds) {
  const th::eval::PitchScore score = scoreAt(200.0);
  EXPECT_LT(score.ffe(), 0.055);  // Praat 5.9 %, RAPT 6.2 %, SWIPE 7.1 %
  EXPECT_LT(score.gpe(), 0.01);
  EXPECT_LT(score.fineMeanAbsCents(), 35.0);
}

}  // namespace
}  // namespace th::features
