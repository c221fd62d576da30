// Visemes from speech on speakers the model never heard (leave one speaker out over BEAT2's and StyleTalk's
// phone-aligned speech): well above the most frequent class, each viseme held for the model's minimum in both
// the whole-recording and the streamed decoding, where each frame decided alone flickers.
#include <gtest/gtest.h>

#include <cstdio>

#include "eval/viseme_corpus.h"

namespace {

TEST(VisemeAccuracy, HeldOutSpeakersBeatTheBaselinesWithoutFlicker) {
  const std::vector<th::eval::VisemeRecording> corpus = th::eval::loadVisemeCorpus();
  ASSERT_EQ(corpus.size(), 9U);
  const th::eval::VisemeEvaluation result = th::eval::leaveOneSpeakerOut(corpus, {}, 2);
  EXPECT_EQ(result.speakers.size(), 4U);
  const double majority = result.majority.oculusAccuracy();
  std::printf(
      "[ INFO     ] Oculus visemes: whole recording %.3f, streamed %.3f, each frame alone %.3f, most frequent "
      "%.3f; Rhubarb shapes %.3f\n",
      result.batch.oculusAccuracy(), result.stream.oculusAccuracy(), result.frameByFrame.oculusAccuracy(), majority,
      result.batch.rhubarbAccuracy());
  EXPECT_GT(result.batch.oculusAccuracy(), 2.0 * majority);
  EXPECT_GT(result.stream.oculusAccuracy(), 2.0 * majority);
  EXPECT_GT(result.batch.rhubarbAccuracy(), result.majority.rhubarbAccuracy() + 0.2);
  // No viseme is shown for less than the minimum hold (3 frames, 100 ms).
  EXPECT_EQ(result.batch.holds().shortest(), 3);
  EXPECT_EQ(result.stream.holds().shortest(), 3);
  EXPECT_GT(result.frameByFrame.holds().shortRunShare(2), 0.5);
}

}  // namespace
