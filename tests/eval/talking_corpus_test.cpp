// Talking corpora for the mouth: the labels the shared corpora ship (GRID's words, StyleTalk's per-frame phones,
// BEAT2's TextGrid) read and classed, broken label files refused naming them, a sound put in late found again,
// speakers named, and the scores and baselines the evaluation prints.
#include "eval/talking_corpus.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>

#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "eval/mouth_scores.h"
#include "face/face_model.h"
#include "features/speech_normaliser.h"

namespace {

namespace fs = std::filesystem;
using th::eval::LabelInterval;
using th::eval::PhoneClass;

TEST(TalkingCorpus, ReadsGridWordsStyleTalkPhonesAndBeat2PhonesFromTheSharedData) {
  const std::vector<LabelInterval> words = th::eval::readGridAlignment(th::sharedDataPath("grid/s1/bbal7s.align"));
  ASSERT_EQ(words.size(), 8u);  // sil, six words, sil
  EXPECT_EQ(words[0].label, "sil");
  EXPECT_EQ(words[1].label, "bin");
  EXPECT_EQ(words[2].label, "blue");
  EXPECT_DOUBLE_EQ(words[0].startSeconds, 0.0);
  EXPECT_NEAR(words.back().endSeconds, 3.0, 0.05);
  for (std::size_t i = 1; i < words.size(); ++i) EXPECT_DOUBLE_EQ(words[i].startSeconds, words[i - 1].endSeconds);

  const fs::path styletalk = th::sharedDataPath("talking/styletalk");
  const std::vector<LabelInterval> phones =
      th::eval::readFramePhones(styletalk / "Obama_clip1_phonemes.json", styletalk / "phindex.json");
  EXPECT_EQ(phones.front().label, "SIL");
  EXPECT_NEAR(phones.back().endSeconds, 599.5 / 30.0, 1e-9) << "600 frames, the last centred at 599 / 30 s";
  int bilabials = 0;
  for (const LabelInterval& phone : phones) bilabials += th::eval::phoneClassOf(phone.label) == PhoneClass::kBilabial;
  EXPECT_GE(bilabials, 8);

  const std::vector<LabelInterval> beat2 =
      th::eval::readTextGridPhones(th::sharedDataPath("beat2/2_scott_0_1_1.TextGrid"));
  EXPECT_GT(beat2.size(), 300u);
  for (const LabelInterval& phone : beat2) {
    EXPECT_LE(phone.startSeconds, phone.endSeconds);
    EXPECT_TRUE(phone.label.empty() || !std::isdigit(static_cast<unsigned char>(phone.label.back()))) << "stress kept";
  }
}

TEST(TalkingCorpus, ClassesFramesByPhoneAndGridWordsByTheirBilabialStartAndOpenVowel) {
  EXPECT_EQ(th::eval::phoneClassOf("M"), PhoneClass::kBilabial);
  EXPECT_EQ(th::eval::phoneClassOf("AA"), PhoneClass::kOpenVowel);
  EXPECT_EQ(th::eval::phoneClassOf("UW"), PhoneClass::kRoundedVowel);
  EXPECT_EQ(th::eval::phoneClassOf("IY"), PhoneClass::kSpreadVowel);
  EXPECT_EQ(th::eval::phoneClassOf("SIL"), PhoneClass::kSilence);
  EXPECT_EQ(th::eval::phoneClassOf("K"), PhoneClass::kConsonant);
  // "sil" 0-0.5 s, "bin" 0.5-0.8 s, "at" 0.8-1.1 s, at 100 frames a second.
  const std::vector<LabelInterval> words{{0.0, 0.5, "sil"}, {0.5, 0.8, "bin"}, {0.8, 1.1, "at"}};
  const std::vector<PhoneClass> classes = th::eval::labelClassesAt(words, true, 100.0, 120);
  EXPECT_EQ(classes[10], PhoneClass::kSilence);
  EXPECT_EQ(classes[50], PhoneClass::kBilabial);
  EXPECT_EQ(classes[57], PhoneClass::kBilabial);
  EXPECT_EQ(classes[59], PhoneClass::kConsonant) << "past the closure's 80 ms; 'bin' has no open vowel";
  EXPECT_EQ(classes[85], PhoneClass::kConsonant) << "the first third of 'at'";
  EXPECT_EQ(classes[95], PhoneClass::kOpenVowel);
  EXPECT_EQ(classes[115], PhoneClass::kSilence) << "after the last word";
  const std::vector<PhoneClass> phoneClasses =
      th::eval::labelClassesAt({{0.0, 0.1, "SIL"}, {0.1, 0.2, "B"}, {0.2, 0.4, "AA"}}, false, 100.0, 40);
  EXPECT_EQ(phoneClasses[5], PhoneClass::kSilence);
  EXPECT_EQ(phoneClasses[15], PhoneClass::kBilabial);
  EXPECT_EQ(phoneClasses[35], PhoneClass::kOpenVowel);
}

TEST(TalkingCorpus, BrokenLabelFilesAreRefusedNamingThem) {
  th::TemporaryFolder folder;
  const fs::path align = folder.path() / "x.align";
  std::ofstream(align) << "0 1000 sil\nnot a line\n";
  const fs::path index = folder.path() / "phindex.json";
  std::ofstream(index) << "{\"AA\": 0, \"SIL\": 1}";
  const fs::path phones = folder.path() / "x_phonemes.json";
  std::ofstream(phones) << "[0, 1, 7]";
  const fs::path grid = folder.path() / "x.TextGrid";
  std::ofstream(grid) << "File type = \"ooTextFile\"\nitem [1]:\n name = \"words\"\n";
  for (const auto& [file, read] : std::vector<std::pair<fs::path, std::function<void()>>>{
           {align, [&] { th::eval::readGridAlignment(align); }},
           {phones, [&] { th::eval::readFramePhones(phones, index); }},
           {grid, [&] { th::eval::readTextGridPhones(grid); }}}) {
    try {
      read();
      FAIL() << file << " was accepted";
    } catch (const th::Error& error) {
      EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos) << error.what();
    }
  }
}

TEST(TalkingCorpus, NamesSpeakersByTheClipNameUpToClip) {
  EXPECT_EQ(th::eval::speakerOfClip("a/Obama_clip2.mp4"), "Obama");
  EXPECT_EQ(th::eval::speakerOfClip("a/andrew_clip_1.mp4"), "andrew");
  EXPECT_EQ(th::eval::speakerOfClip("a/KristiNoem.mp4"), "KristiNoem");
}

// A mouth that moves at random (smoothed) and a sound level that follows it `lagFrames` later, with noise.
struct SyntheticClip {
  Eigen::RowVectorXd level, jaw, lips;
};

SyntheticClip syntheticClip(int frames, double soundLagFrames, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> gaussian;
  Eigen::RowVectorXd mouth(frames + 40);
  double value = 0.0;
  for (Eigen::Index t = 0; t < mouth.size(); ++t) mouth[t] = value = 0.7 * value + gaussian(random);
  SyntheticClip clip{Eigen::RowVectorXd(frames), mouth.segment(20, frames), Eigen::RowVectorXd(frames)};
  for (int t = 0; t < frames; ++t) {
    // Linear interpolation for a lag between frames.
    const double at = 20.0 + t - soundLagFrames;
    const auto lo = static_cast<Eigen::Index>(std::floor(at));
    const double w = at - static_cast<double>(lo);
    clip.level[t] = 10.0 * ((1.0 - w) * mouth[lo] + w * mouth[lo + 1]) + 2.0 * gaussian(random);
    clip.lips[t] = 0.5 * clip.jaw[t] + 0.3 * gaussian(random);
  }
  return clip;
}

TEST(SoundOffset, FindsASoundPutInLateOrEarlyToAFractionOfAFrame) {
  for (const double lag : {0.0, 3.4, -2.0, 5.0}) {
    const SyntheticClip clip = syntheticClip(900, lag, 7);
    const th::tracking::SoundOffset offset =
        th::tracking::estimateSoundOffset(clip.level, clip.jaw, clip.lips, 30.0, {.naturalLeadSeconds = 0.0});
    ASSERT_TRUE(offset.measured);
    EXPECT_NEAR(offset.lateSeconds * 30.0, lag, 0.25) << "lag " << lag;
    EXPECT_GT(offset.correlation, 0.3);
  }
  // The lips' natural lead is not taken for a late sound.
  const SyntheticClip inSync = syntheticClip(900, 0.3, 8);
  EXPECT_NEAR(
      th::tracking::estimateSoundOffset(inSync.level, inSync.jaw, inSync.lips, 30.0, {.naturalLeadSeconds = 0.3 / 30.0})
          .lateSeconds,
      0.0, 0.25 / 30.0);
  // A 3 s clip is too short to say.
  const SyntheticClip shortClip = syntheticClip(90, 4.0, 9);
  const th::tracking::SoundOffset none =
      th::tracking::estimateSoundOffset(shortClip.level, shortClip.jaw, shortClip.lips, 30.0);
  EXPECT_FALSE(none.measured);
  EXPECT_EQ(none.lateSeconds, 0.0);
}

TEST(MouthScores, CorrelationSpreadAndErrorHaveTheirKnownValues) {
  const Eigen::RowVectorXd truth = (Eigen::RowVectorXd(4) << 1.0, -1.0, 2.0, -2.0).finished();
  const th::eval::CurveScore doubled = th::eval::scoreCurve(2.0 * truth, truth);
  EXPECT_NEAR(doubled.rho, 1.0, 1e-12);
  EXPECT_NEAR(doubled.spread, 2.0, 1e-12);
  EXPECT_NEAR(doubled.epsilon, 1.0, 1e-12);
  const th::eval::CurveScore flat = th::eval::scoreCurve(Eigen::RowVectorXd::Zero(4), truth);
  EXPECT_EQ(flat.rho, 0.0);
  EXPECT_EQ(flat.spread, 0.0);
  EXPECT_NEAR(flat.epsilon, 1.0, 1e-12) << "the mean scores 1";
  EXPECT_NEAR(th::eval::scoreCurve(-truth, truth).rho, -1.0, 1e-12);
}

TEST(MouthShapes, TheJawOpensTheLipsAndTheCornersWidenTheMouth) {
  const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  const th::eval::MouthShapes shapes(face);
  // FAP 3 (open_jaw) and FAPs 6/7 (stretch_l/r_cornerlip), in three frames: at rest, the jaw open, the corners out.
  Eigen::MatrixXd faps = Eigen::MatrixXd::Zero(3, 3);
  faps(0, 1) = 400.0;
  faps(1, 2) = faps(2, 2) = 200.0;
  const Eigen::MatrixXd shape = shapes.of(faps, {3, 6, 7});
  EXPECT_LT(shape(0, 0), 0.03) << "the lips nearly meet at rest";
  EXPECT_GT(shape(0, 1), shape(0, 0) + 0.05) << "the lips part as the jaw opens";
  EXPECT_GT(shape(1, 2), shape(1, 0) + 0.02) << "the corners stretched widen the mouth";
  EXPECT_NEAR(shape(0, 2), shape(0, 0), 0.02);
}

TEST(LevelBaseline, LearnsALinearMapFromTheLevel) {
  // Speech whose "jaw" is twice the level relative to its peak, plus 100: the baseline finds the map.
  th::animation::MouthRecording recording;
  const int frames = 600;
  recording.speech.mfcc = Eigen::MatrixXd::Zero(11, frames);
  recording.speech.levelDb.resize(frames);
  for (int t = 0; t < frames; ++t) recording.speech.levelDb[t] = -30.0 + 15.0 * std::sin(0.2 * t);
  const Eigen::MatrixXd normalised = th::features::normaliseSpeech({}, 30.0, Eigen::VectorXd::Zero(11),
                                                                   recording.speech.levelDb, recording.speech.mfcc);
  recording.visual = (2.0 * normalised.bottomRows(1)).array() + 100.0;
  const th::eval::LevelBaseline baseline({&recording}, 2);
  const Eigen::MatrixXd predicted = baseline.predict(recording.speech);
  EXPECT_LT((predicted - recording.visual).cwiseAbs().maxCoeff(), 0.01);
}

}  // namespace
