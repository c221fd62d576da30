// The head's leave-one-speaker-out protocol on made-up clips: a row's numbers for estimates whose answer is
// known (the truth itself, the truth doubled, the mean pose), the verdict flipping at its thresholds, the mean
// over seeds, another speaker's motion, the training sets and the summary over speakers.
#include "eval/head_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

using th::animation::HeadRecording;
using namespace th::eval;

// A speaker's clip of `frames` at 30 fps: the head nods and turns at a few rates (so its speed varies), and the
// sound is loud except for a 2 s pause from frame 120.
HeadRecording clipOf(const std::string& speaker, const std::string& name, int frames, double phase = 0.0) {
  HeadRecording clip;
  clip.speaker = speaker;
  clip.name = name;
  clip.rotations.resize(3, frames);
  clip.levelDb.resize(frames);
  for (int t = 0; t < frames; ++t) {
    const double s = t / kHeadFramesPerSecond;
    clip.rotations(0, t) = 5.0 + 4.0 * std::sin(2.0 * std::numbers::pi * 0.7 * s + phase) + std::sin(9.0 * s);
    clip.rotations(1, t) = -3.0 + 6.0 * std::sin(2.0 * std::numbers::pi * 0.3 * s + 2.0 * phase);
    clip.rotations(2, t) = 2.0 * std::sin(2.0 * std::numbers::pi * 1.1 * s) + 0.5 * std::cos(5.0 * s + phase);
    clip.levelDb[t] = t >= 120 && t < 180 ? -80.0 : -20.0 + 6.0 * std::sin(2.0 * std::numbers::pi * 4.0 * s);
  }
  clip.voiced = Eigen::RowVectorXd::Ones(frames);
  clip.prosody = Eigen::MatrixXd::Zero(4, frames);
  return clip;
}

TEST(HeadProtocol, TheTruthItselfScoresPerfectly) {
  const HeadRecording a = clipOf("A", "a1", 300), b = clipOf("A", "a2", 240, 1.0);
  const std::vector<HeadJudgedClip> clips{judgedClipOf(a), judgedClipOf(b)};
  EXPECT_NEAR(clips[0].truth.rowwise().mean().norm(), 0.0, 1e-9);  // about the clip's own mean
  const HeadSpeakerTruth truth = headTruthOf(clips);
  EXPECT_EQ(truth.frames, 540.0);
  EXPECT_TRUE(truth.pauses);  // 2 s of pauses in each clip
  EXPECT_GT(truth.speedP95, 0.0);
  const HeadRow row = judgeHead("truth", clips, truth, [&](std::size_t i) { return clips[i].truth; });
  EXPECT_EQ(row.name, "truth");
  EXPECT_NEAR(row.error, 0.0, 1e-12);
  EXPECT_NEAR(row.correlation.minCoeff(), 1.0, 1e-9);
  EXPECT_NEAR(row.stdRatio.minCoeff(), 1.0, 1e-9);
  EXPECT_NEAR(row.stdRatio.maxCoeff(), 1.0, 1e-9);
  EXPECT_NEAR(row.speedRatio, 1.0, 1e-9);
  EXPECT_NEAR(row.pauseRatio, truth.pauseRatio, 1e-9);
  EXPECT_NEAR(row.frechet, 0.0, 1e-3);
  EXPECT_NEAR(row.beatAlign, truth.beatAlign, 1e-12);
  EXPECT_TRUE(headVerdict(row, truth).meets());
  EXPECT_EQ(headVerdict(row, truth).text(), "meets speed, spread and pauses");
}

TEST(HeadProtocol, TheTruthDoubledMovesTwiceAsFastAndFar) {
  const HeadRecording a = clipOf("A", "a1", 300);
  const std::vector<HeadJudgedClip> clips{judgedClipOf(a)};
  const HeadSpeakerTruth truth = headTruthOf(clips);
  const HeadRow row = judgeHead("doubled", clips, truth, [&](std::size_t i) { return (2.0 * clips[i].truth).eval(); });
  EXPECT_NEAR(row.stdRatio[0], 2.0, 1e-9);
  EXPECT_NEAR(row.speedRatio, 2.0, 1e-9);
  EXPECT_NEAR(row.correlation.minCoeff(), 1.0, 1e-9);
  EXPECT_GT(row.frechet, 1.0);
  EXPECT_EQ(headVerdict(row, truth).text(), "misses: speed spread");

  const HeadRow still = judgeHead("still", clips, truth, [&](std::size_t i) {
    return Eigen::MatrixXd::Zero(3, clips[i].clip->numFrames()).eval();
  });
  EXPECT_NEAR(still.error, 1.0, 1e-9);  // the paper's E of the rest pose
  EXPECT_EQ(still.stdRatio.maxCoeff(), 0.0);
  EXPECT_FALSE(headVerdict(still, truth).spread);
}

TEST(HeadProtocol, VerdictFlipsAtItsThresholds) {
  HeadSpeakerTruth truth;
  truth.pauses = true;
  truth.pauseRatio = 0.3;
  HeadRow row;
  row.stdRatio = Eigen::Vector3d(1.0, 0.9, 1.1);
  row.speedRatio = 1.24;
  row.pauseRatio = 0.44;
  EXPECT_TRUE(headVerdict(row, truth).meets());
  row.speedRatio = 1.26;
  EXPECT_EQ(headVerdict(row, truth).text(), "misses: speed");
  row.speedRatio = 1.0;
  row.stdRatio[1] = 0.69;
  EXPECT_EQ(headVerdict(row, truth).text(), "misses: spread");
  row.stdRatio[1] = 1.31;
  EXPECT_EQ(headVerdict(row, truth).text(), "misses: spread");
  row.stdRatio[1] = 1.0;
  row.pauseRatio = 0.46;
  EXPECT_EQ(headVerdict(row, truth).text(), "misses: pauses");
  truth.pauses = false;  // without pauses the ratio means nothing
  EXPECT_TRUE(headVerdict(row, truth).meets());
  // Targets of one's own.
  truth.pauses = true;
  EXPECT_TRUE(headVerdict(row, truth, {.maxPauseExcess = 0.2}).meets());
}

TEST(HeadProtocol, MeanOverSeedsAndItsSpread) {
  HeadRow a, b;
  a.beatAlign = 0.4;
  b.beatAlign = 0.6;
  a.speedRatio = 1.0;
  b.speedRatio = 2.0;
  a.stdRatio = Eigen::Vector3d(1.0, 2.0, 3.0);
  b.stdRatio = Eigen::Vector3d(3.0, 2.0, 1.0);
  a.pauses = b.pauses = false;
  const HeadRow mean = meanHeadRow("mean", {a, b});
  EXPECT_EQ(mean.name, "mean");
  EXPECT_FALSE(mean.pauses);
  EXPECT_NEAR(mean.beatAlign, 0.5, 1e-12);
  EXPECT_NEAR(mean.speedRatio, 1.5, 1e-12);
  EXPECT_NEAR((mean.stdRatio - Eigen::Vector3d(2.0, 2.0, 2.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(mean.beatAlignSpread, std::sqrt(0.02), 1e-12);  // sample standard deviation
  EXPECT_EQ(meanHeadRow("one", {a}).beatAlignSpread, 0.0);
}

TEST(HeadProtocol, AnotherSpeakersMotionIsCentredAndRepeated) {
  const HeadRecording other = clipOf("B", "b1", 100);
  const Eigen::MatrixXd motion = otherSpeakersMotion(other, 250);
  ASSERT_EQ(motion.cols(), 250);
  const Eigen::Vector3d mean = other.rotations.rowwise().mean();
  EXPECT_NEAR((motion.col(0) - (other.rotations.col(0) - mean)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((motion.col(237) - motion.col(37)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(motion.leftCols(100).rowwise().mean().norm(), 0.0, 1e-9);
}

TEST(HeadProtocol, TrainingSetsLeaveTheSpeakerOut) {
  HeadCorpus corpus;
  corpus.beat2Train = clipOf("scott", "beat2", 60);
  corpus.beat2Test = clipOf("scott", "beat2 held out", 30);
  corpus.styleTalk = {clipOf("Obama", "o1", 40), clipOf("Noem", "n1", 40), clipOf("Obama", "o2", 40)};
  const auto names = [](const std::vector<HeadRecording>& parts) {
    std::vector<std::string> out;
    for (const auto& p : parts) out.push_back(p.name);
    return out;
  };
  EXPECT_EQ(names(headTrainingSet(corpus, "")), (std::vector<std::string>{"beat2", "o1", "n1", "o2"}));
  EXPECT_EQ(names(headTrainingSet(corpus, "Obama")), (std::vector<std::string>{"beat2", "n1"}));
  EXPECT_EQ(names(headTrainingSet(corpus, "scott")), (std::vector<std::string>{"o1", "n1", "o2"}));
}

TEST(HeadProtocol, SummaryOverSpeakersByName) {
  const auto speaker = [](const std::string& name, Eigen::Vector3d stdRatio, double speed, bool pauses) {
    HeadSpeakerResult result;
    result.speaker = name;
    result.truth.pauses = pauses;
    result.truth.pauseRatio = 0.2;
    result.truth.beatAlign = 0.5;
    result.truth.chanceAlign = 0.4;
    HeadRow row;
    row.stdRatio = stdRatio;
    row.speedRatio = speed;
    row.pauseRatio = 0.3;
    row.beatAlign = 0.55;
    row.beatAlignSpread = 0.05;
    result.rows.push_back(row);
    return result;
  };
  const HeadSummary summary = summariseHeadSpeakers(
      {speaker("scott", {2.0, 2.0, 2.0}, 1.1, true), speaker("Obama", {0.5, 0.5, 0.5}, 0.9, false)});
  ASSERT_EQ(summary.speakers.size(), 2U);
  EXPECT_EQ(summary.speakers[0].speaker, "Obama");  // by name, as the summary prints them
  EXPECT_NEAR(summary.spreadGeometricMean, 1.0, 1e-12);
  EXPECT_EQ(summary.spreadLowest, 0.5);
  EXPECT_EQ(summary.spreadHighest, 2.0);
  EXPECT_EQ(summary.speakers[1].speedRatio, 1.1);
  EXPECT_TRUE(summary.speakers[1].pauses);
  EXPECT_NEAR(summary.speakers[1].pauseExcess, 0.1, 1e-12);
  EXPECT_NEAR(summary.speakers[1].beatAlignChange, 0.1, 1e-12);
  EXPECT_NEAR(summary.speakers[1].beatAlignSpread, 0.1, 1e-12);
  EXPECT_NEAR(summary.speakers[1].truthOverChance, 0.25, 1e-12);
}

}  // namespace
