// The viseme model on speech frames made up so that each mouth class sounds its own way: it learns them, holds
// each class at least its minimum, streams what the batch decoder gives, and its file reads back.
#include "animation/viseme_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "core/error.h"
#include "core/temporary_file.h"
#include "hmm/model_file.h"

namespace {

using th::animation::LabelledSpeech;
using th::face::kNumMouthClasses;

// Runs of random classes, 3-8 frames each; each class's MFCCs scattered around its own point.
LabelledSpeech madeUpSpeech(int frames, unsigned seed, const Eigen::MatrixXd& classMeans) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> pickClass(0, kNumMouthClasses - 1), pickLength(3, 8);
  std::normal_distribution<double> noise(0.0, 1.0);
  LabelledSpeech speech;
  speech.speech.mfcc.resize(11, frames);
  speech.speech.levelDb.resize(frames);
  while (static_cast<int>(speech.classes.size()) < frames) {
    const int c = pickClass(random);
    for (int k = pickLength(random); k > 0 && static_cast<int>(speech.classes.size()) < frames; --k)
      speech.classes.push_back(c);
  }
  for (int t = 0; t < frames; ++t) {
    const int c = speech.classes[static_cast<std::size_t>(t)];
    for (int d = 0; d < 11; ++d) speech.speech.mfcc(d, t) = classMeans(d, c) + noise(random);
    speech.speech.levelDb[t] = (c == 0 ? -55.0 : -20.0) + noise(random);
  }
  return speech;
}

class VisemeModelTest : public testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(7);
    std::normal_distribution<double> spread(0.0, 0.6);
    means_ = Eigen::MatrixXd::NullaryExpr(11, kNumMouthClasses, [&] { return spread(random); });
    for (unsigned seed = 1; seed <= 4; ++seed) training_.push_back(madeUpSpeech(1500, seed, means_));
    heldOut_ = madeUpSpeech(600, 99, means_);
    model_ = th::animation::trainVisemeModel(training_, options_);
  }

  double accuracy(const std::vector<int>& decoded) const {
    int hits = 0;
    for (std::size_t t = 0; t < decoded.size(); ++t) hits += decoded[t] == heldOut_.classes[t] ? 1 : 0;
    return static_cast<double>(hits) / static_cast<double>(decoded.size());
  }

  Eigen::MatrixXd means_;
  std::vector<LabelledSpeech> training_;
  LabelledSpeech heldOut_;
  th::animation::VisemeModelOptions options_{.minHoldFrames = 3};
  th::animation::VisemeModel model_;
};

TEST_F(VisemeModelTest, LearnsTheClassesAndHoldsEachAtLeastItsMinimum) {
  const th::face::VisemeTrack track = th::animation::decodeVisemes(model_, heldOut_.speech);
  ASSERT_EQ(track.numFrames(), heldOut_.speech.numFrames());
  EXPECT_GT(accuracy(track.classes), 0.75);
  const std::vector<th::face::Run> runs = th::face::runsOf(track.classes);
  for (std::size_t r = 0; r + 1 < runs.size(); ++r) EXPECT_GE(runs[r].length, 3) << "run " << r;
  for (int t = 0; t < track.numFrames(); ++t) EXPECT_NEAR(track.posteriors.col(t).sum(), 1.0, 1e-9);
  // Each frame decided alone flickers: runs shorter than the minimum hold, which the HMM never shows.
  const std::vector<int> alone = th::animation::classifyFrames(model_, heldOut_.speech);
  const std::vector<th::face::Run> aloneRuns = th::face::runsOf(alone);
  EXPECT_GT(std::count_if(aloneRuns.begin(), aloneRuns.end(), [](const th::face::Run& run) { return run.length < 3; }),
            20);
  std::printf("[ INFO     ] accuracy: HMM %.3f, each frame alone %.3f\n", accuracy(track.classes), accuracy(alone));
}

TEST_F(VisemeModelTest, AStreamWithALongLagGivesTheBatchDecoding) {
  const th::face::VisemeTrack batch = th::animation::decodeVisemes(model_, heldOut_.speech);
  th::animation::VisemeStream stream(model_, heldOut_.speech.numFrames() + 10);
  std::vector<th::animation::VisemeFrame> frames;
  th::animation::VisemeFrame frame;
  for (int t = 0; t < heldOut_.speech.numFrames(); ++t) {
    stream.accept(heldOut_.speech.levelDb[t], heldOut_.speech.mfcc.col(t));
    while (stream.next(frame)) frames.push_back(frame);
  }
  EXPECT_TRUE(frames.empty()) << "nothing is decided before the lag";
  stream.finish();
  while (stream.next(frame)) frames.push_back(frame);
  ASSERT_EQ(static_cast<int>(frames.size()), batch.numFrames());
  for (int t = 0; t < batch.numFrames(); ++t) {
    EXPECT_EQ(frames[static_cast<std::size_t>(t)].mouthClass, batch.classes[static_cast<std::size_t>(t)]) << t;
    EXPECT_LT((frames[static_cast<std::size_t>(t)].probabilities - batch.posteriors.col(t)).cwiseAbs().maxCoeff(),
              1e-6);
  }
}

TEST_F(VisemeModelTest, AShortLagStillHoldsEachClass) {
  th::animation::VisemeStream stream(model_, 2);
  std::vector<int> shown;
  th::animation::VisemeFrame frame;
  for (int t = 0; t < heldOut_.speech.numFrames(); ++t) {
    stream.accept(heldOut_.speech.levelDb[t], heldOut_.speech.mfcc.col(t));
    while (stream.next(frame)) shown.push_back(frame.mouthClass);
    EXPECT_LE(t + 1 - static_cast<int>(shown.size()), stream.latencyFrames() + 1) << "frame " << t;
  }
  stream.finish();
  while (stream.next(frame)) shown.push_back(frame.mouthClass);
  ASSERT_EQ(static_cast<int>(shown.size()), heldOut_.speech.numFrames());
  const std::vector<th::face::Run> runs = th::face::runsOf(shown);
  for (std::size_t r = 0; r + 1 < runs.size(); ++r) EXPECT_GE(runs[r].length, 3) << "run " << r;
  EXPECT_GT(accuracy(shown), 0.8);
}

TEST_F(VisemeModelTest, TheFileReadsBackToTheSameDecoding) {
  const th::TemporaryFile file(".json");
  th::animation::saveVisemeModel(file.path(), model_);
  const th::animation::VisemeModel loaded = th::animation::loadVisemeModel(file.path());
  const th::face::VisemeTrack before = th::animation::decodeVisemes(model_, heldOut_.speech);
  const th::face::VisemeTrack after = th::animation::decodeVisemes(loaded, heldOut_.speech);
  EXPECT_EQ(before.classes, after.classes);
  EXPECT_LT((before.posteriors - after.posteriors).cwiseAbs().maxCoeff(), 1e-9);
}

TEST_F(VisemeModelTest, AnHmmFileThatIsNotAVisemeModelIsRefused) {
  const th::TemporaryFile file(".json");
  th::hmm::saveModel(file.path(), model_.hmm, R"({"kind": "mouth"})");
  try {
    th::animation::loadVisemeModel(file.path());
    FAIL() << "loaded";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find("not a viseme model"), std::string::npos) << error.what();
  }
}

TEST(VisemeModel, AClassWithTooFewFramesIsNamed) {
  LabelledSpeech speech;
  speech.speech.mfcc = Eigen::MatrixXd::Random(11, 40);
  speech.speech.levelDb = Eigen::RowVectorXd::Constant(40, -20.0);
  speech.classes.assign(40, 1);
  try {
    th::animation::trainVisemeModel({speech}, {});
    FAIL() << "trained";
  } catch (const th::Error& error) {
    EXPECT_NE(std::string(error.what()).find("class sil has 0 labelled frames"), std::string::npos) << error.what();
  }
}

}  // namespace
