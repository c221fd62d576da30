// The mouth's corpus protocol on made-up clips: GRID s1's every fifth clip held out per folder, the sets judged
// (GRID's samples apart, s1's own sample left out, StyleTalk's speakers), the training weights, the
// baselines, the estimators' rows, the chin-drop percentiles and the multilingual files' readers.
#include "eval/mouth_protocol.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "core/temporary_file.h"

namespace {

namespace fs = std::filesystem;
using namespace th::eval;

// A clip of `frames` whose one visual row (FAP 3) is `value` throughout, its speech as long.
TalkingClip clipOf(const fs::path& video, const std::string& speaker, int frames = 10, double value = 0.0) {
  TalkingClip clip;
  clip.clip.video = video;
  clip.speaker = speaker;
  clip.clip.recording.visual = Eigen::MatrixXd::Constant(1, frames, value);
  clip.clip.recording.speech.mfcc = Eigen::MatrixXd::Zero(11, frames);
  clip.clip.recording.speech.levelDb =
      Eigen::RowVectorXd::NullaryExpr(frames, [](Eigen::Index t) { return -20.0 - 10.0 * static_cast<double>(t % 3); });
  return clip;
}

// GRID s1 in two folders (7 and 5 clips), GRID's samples (another speaker and s1's own bbaf2n) and two
// StyleTalk speakers.
TalkingCorpus corpusOf() {
  TalkingCorpus corpus;
  corpus.faps = {3};
  for (int i = 0; i < 7; ++i) corpus.clips.push_back(clipOf("grid/s1/c" + std::to_string(i) + ".mpg", kGridSpeaker));
  for (int i = 0; i < 5; ++i)
    corpus.clips.push_back(clipOf("grid/s1-more/d" + std::to_string(i) + ".mpg", kGridSpeaker));
  corpus.clips.push_back(clipOf("grid/samples/bbaf2n.mpg", "bbaf2n"));
  corpus.clips.push_back(clipOf("grid/samples/s2.mpg", "s2"));
  corpus.clips.push_back(clipOf("talking/styletalk/Obama_clip1.mp4", "Obama"));
  corpus.clips.push_back(clipOf("talking/styletalk/Obama_clip2.mp4", "Obama"));
  corpus.clips.push_back(clipOf("talking/styletalk/andrew_clip1.mp4", "andrew"));
  return corpus;
}

std::vector<std::string> stems(const TalkingClips& clips) {
  std::vector<std::string> out;
  for (const TalkingClip* clip : clips) out.push_back(clip->clip.video.stem().string());
  return out;
}

TEST(MouthProtocol, GridHoldsOutEveryFifthClipOfEachFolder) {
  const TalkingCorpus corpus = corpusOf();
  const GridSplit split = splitGrid(corpus);
  EXPECT_EQ(stems(split.heldOut), (std::vector<std::string>{"c4", "d4"}));
  EXPECT_EQ(split.train.size(), 10U);
  EXPECT_EQ(split.otherSpeakers.size(), 4U);  // bbaf2n, s2, Obama, andrew
  EXPECT_EQ(mouthModelTrainingClips(split).size(), 10U + 5U);
}

TEST(MouthProtocol, TheSetsKeepGridsSamplesApartAndLeaveOutS1sOwn) {
  const TalkingCorpus corpus = corpusOf();
  const MouthEvaluationSets sets = mouthEvaluationSets(corpus);
  EXPECT_EQ(stems(sets.gridOthers), (std::vector<std::string>{"s2"}));
  EXPECT_EQ(stems(sets.styleTalk), (std::vector<std::string>{"Obama_clip1", "Obama_clip2", "andrew_clip1"}));
  ASSERT_EQ(sets.styleTalkSpeakers.size(), 2U);
  EXPECT_EQ(sets.styleTalkSpeakers.at("Obama").size(), 2U);
  EXPECT_EQ(mouthTrainingClips(sets).size(), 10U + 3U);
  const TalkingClips fold = mouthTrainingClips(sets, "Obama");
  EXPECT_EQ(fold.size(), 10U + 1U);
  EXPECT_EQ(fold.back()->speaker, "andrew");
}

TEST(MouthProtocol, OtherSpeakersWeighAsAsked) {
  const TalkingCorpus corpus = corpusOf();
  const TalkingClips clips{&corpus.clips[0], &corpus.clips[14], &corpus.clips[16]};  // s1, Obama, andrew
  EXPECT_EQ(mouthRecordingsOf(clips).size(), 3U);
  EXPECT_EQ(mouthRecordingsOf(clips, 3).size(), 1U + 3U + 3U);
}

TEST(MouthProtocol, TheRecipeIsDescribed) {
  MouthRecipe recipe;
  recipe.model.futureContextFrames = recipe.model.contextFrames + 2;
  recipe.stageTwo = true;
  recipe.otherSpeakerWeight = 4;
  const std::string text = describeMouthRecipe(recipe);
  EXPECT_NE(text.find(std::to_string(recipe.model.states) + " states x "), std::string::npos) << text;
  EXPECT_NE(text.find("..+" + std::to_string(recipe.model.contextFrames + 2)), std::string::npos) << text;
  EXPECT_NE(text.find(", stage 2 on speech-only voices"), std::string::npos) << text;
  EXPECT_NE(text.find("weighing 4x"), std::string::npos) << text;
  EXPECT_EQ(describeMouthRecipe({}).find("stage 2"), std::string::npos);
}

TEST(MouthProtocol, BaselinesAreTheTrainingMeanAndTheLevel) {
  TalkingCorpus corpus;
  corpus.faps = {3};
  corpus.clips = {clipOf("a.mp4", "A", 10, 100.0), clipOf("b.mp4", "B", 30, 200.0)};
  const TalkingClips training{&corpus.clips[0], &corpus.clips[1]};
  const MouthBaselines baselines = mouthBaselinesFor(training, corpus.faps);
  EXPECT_EQ(baselines.level.name, kLevelBaselineName);
  const std::vector<Eigen::MatrixXd> means = estimatesFor(baselines.mean, training);
  ASSERT_EQ(means.size(), 2U);
  EXPECT_EQ(means[0].cols(), 10);
  EXPECT_NEAR(means[0](0, 0), (10 * 100.0 + 30 * 200.0) / 40.0, 1e-9);  // weighted by frames
  // Shifted by one: each clip gets the next clip's speech (so its length).
  EXPECT_EQ(estimatesFor(baselines.mean, training, 1)[0].cols(), 30);
}

TEST(MouthProtocol, ChinDropPercentilesAndTheTruths) {
  std::vector<double> drops;
  for (int i = 0; i <= 100; ++i) drops.push_back(100.0 - i);  // unsorted on purpose
  const std::array<double, 3> p = chinDropPercentiles(drops);
  EXPECT_EQ(p[0], 5.0);
  EXPECT_EQ(p[1], 50.0);
  EXPECT_EQ(p[2], 95.0);
  EXPECT_EQ(chinDropPercentiles({})[1], 0.0);

  TalkingCorpus corpus;
  corpus.clips = {clipOf("a.mp4", "A", 10, -50.0), clipOf("b.mp4", "B", 30, 200.0)};
  // A quarter of the frames close the jaw past rest (taken as 0); the rest drop 200 units, 0.1 mm each.
  const std::array<double, 3> truth = truthChinDrop({&corpus.clips[0], &corpus.clips[1]}, {3}, 0.1);
  EXPECT_EQ(truth[0], 0.0);
  EXPECT_NEAR(truth[1], 20.0, 1e-12);
  EXPECT_NEAR(truth[2], 20.0, 1e-12);
}

TEST(MouthProtocol, PhoneClassTruthIsTheTrackedLipsByTheLabels) {
  TalkingClip clip = clipOf("a.mp4", "A", 9);
  clip.labels = {{0.0, 0.1, "B"}, {0.1, 0.3, "AA"}};  // frames 0-2 a bilabial, 3-8 an open vowel
  clip.clip.lipShape = Eigen::MatrixXd::Zero(2, 9);
  clip.clip.lipShape.row(0) << 0.01, 0.02, 0.03, 0.3, 0.3, 0.3, 0.3, 0.4, 0.4;
  PhoneClassShapes truth;
  addPhoneClassTruth(truth, {&clip});
  EXPECT_EQ(truth.count(PhoneClass::kBilabial), 3);
  EXPECT_NEAR(truth.mean(PhoneClass::kBilabial)[0], 0.02, 1e-12);
  EXPECT_EQ(truth.count(PhoneClass::kOpenVowel), 6);
  EXPECT_NEAR(truth.mean(PhoneClass::kOpenVowel)[0], 2.0 / 6.0, 1e-12);
}

TEST(MouthProtocol, ReadsTheMultilingualIndexAndClassedPhones) {
  th::TemporaryFolder folder;
  std::ofstream(folder.path() / "index.csv") << "file,language,text\nde_1,de,x\nen_1,en,y\nde_2,de,z\nbroken\n";
  const auto index = readMultilingualIndex(folder.path());
  ASSERT_EQ(index.size(), 2U);
  EXPECT_EQ(index.at("de"), (std::vector<std::string>{"de_1", "de_2"}));
  std::ofstream(folder.path() / "de_1.phones.csv") << "start,end,phone,class\n0,0.1,p,bilabial\n0.1,0.3,a,open_vowel\n"
                                                      "0.3,0.4,x,click\n";
  const auto phones = readClassedPhones(folder.path() / "de_1.phones.csv");
  ASSERT_EQ(phones.size(), 3U);
  EXPECT_EQ(phones[0].second, PhoneClass::kBilabial);
  EXPECT_EQ(phones[1].second, PhoneClass::kOpenVowel);
  EXPECT_DOUBLE_EQ(phones[1].first.endSeconds, 0.3);
  EXPECT_EQ(phones[2].second, PhoneClass::kConsonant);  // an unknown class claims nothing
  EXPECT_THROW(readClassedPhones(folder.path() / "missing.phones.csv"), th::Error);
  EXPECT_THROW(readMultilingualIndex(folder.path() / "nowhere"), th::Error);
}

}  // namespace
