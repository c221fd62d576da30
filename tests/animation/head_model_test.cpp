// The head-motion path: prosody from feature rows, the paper's error and the other metrics, training a head
// model on data with a known voice-motion link, its file, and the batch and online synthesis variants.
#include "animation/head_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "animation/head_data.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "eval/head_corpus.h"
#include "eval/head_evaluation.h"
#include "hmm/model_file.h"
#include "hmm/sampling.h"

namespace th::animation {
namespace {

std::vector<float> featureRow(float f0, float energy, float deltaF0, float deltaEnergy) {
  std::vector<float> row(static_cast<size_t>(features::FeatureLayout{}.size()), 0.0f);
  row[features::FeatureLayout::kF0Hz] = f0;
  row[features::FeatureLayout::kEnergy] = energy;
  row[features::FeatureLayout::kDeltaF0] = deltaF0;
  row[features::FeatureLayout::kDeltaEnergy] = deltaEnergy;
  return row;
}

TEST(Prosody, SemitonesAroundTheRunningMeanAndAHeldPitchThatRelaxesWhenUnvoiced) {
  ProsodyTracker tracker(30.0, {.unvoicedDecaySeconds = 0.1, .meanPitchSeconds = 1e9});
  // The first voiced frame sets the mean: 0 semitones; an octave up is +12.
  EXPECT_NEAR(tracker.accept(featureRow(100.0f, 0.5f, 0.0f, 0.1f))[0], 0.0, 1e-9);
  const Eigen::Vector4d octave = tracker.accept(featureRow(200.0f, 0.7f, 10.0f, -0.2f));
  EXPECT_NEAR(octave[0], 12.0, 1e-6);
  EXPECT_NEAR(octave[1], 0.7, 1e-6);
  EXPECT_NEAR(octave[2], 12.0 / std::log(2.0) * 10.0 / 200.0, 1e-6) << "dF0/F0 in semitones per frame";
  EXPECT_NEAR(octave[3], -0.2, 1e-6);
  // Unvoiced: the pitch holds and relaxes by exp(-1 / (30 x 0.1)) per frame; its delta is 0.
  const Eigen::Vector4d unvoiced = tracker.accept(featureRow(0.0f, -1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(unvoiced[0], 12.0 * std::exp(-1.0 / 3.0), 1e-6);
  EXPECT_EQ(unvoiced[2], 0.0);
  Eigen::Vector4d later;
  for (int t = 0; t < 60; ++t) later = tracker.accept(featureRow(0.0f, -1.0f, 0.0f, 0.0f));
  EXPECT_LT(std::abs(later[0]), 1e-6) << "two seconds of silence bring it back to the speaker's mean";
}

TEST(HeadEvaluation, ThePapersErrorAndItsReferencePoints) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal(0.0, 5.0);
  const Eigen::MatrixXd truth = Eigen::MatrixXd::NullaryExpr(3, 4000, [&] { return normal(random); });
  const Eigen::MatrixXd unrelated = Eigen::MatrixXd::NullaryExpr(3, 4000, [&] { return normal(random); });
  EXPECT_EQ(th::eval::headError(truth, truth), 0.0);
  EXPECT_DOUBLE_EQ(th::eval::headError(Eigen::MatrixXd::Zero(3, 4000), truth), 1.0) << "the rest pose scores exactly 1";
  EXPECT_NEAR(th::eval::headError(unrelated, truth), 1.0, 0.03)
      << "an unrelated motion of the same size scores about 1";
  EXPECT_NEAR(th::eval::headError(-truth, truth), 2.0, 1e-12) << "the mirror image scores 2";
  // One frame by hand: x^ = (1, 0, 0), x = (0, 1, 0): |x^ - x|^2 = 2, |x^|^2 + |x|^2 = 2.
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3, 2);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3, 2);
  a(0, 0) = 1.0;
  b(1, 0) = 1.0;
  EXPECT_DOUBLE_EQ(th::eval::headError(a, b), 0.5) << "(2/2 + 0 for the frame where both rest) / 2";

  const th::eval::HeadMetrics self = th::eval::evaluateHead(truth, truth, th::eval::stepQuantile(truth, 0.99));
  EXPECT_NEAR(self.correlation.minCoeff(), 1.0, 1e-12);
  EXPECT_NEAR(self.jumpRate, 0.01, 0.002) << "1 % of the truth's own steps exceed its 99th percentile";
  EXPECT_EQ(self.poseStd, self.truthPoseStd);
  EXPECT_THROW(th::eval::headError(truth.leftCols(10), truth), Error);
}

// A recording where the voice determines the head: a 3-state process, each state with its own pose and its own
// prosody.
HeadRecording synthetic(int frames, unsigned seed) {
  hmm::HmmModel joint;
  joint.initial = Eigen::Vector3d::Constant(1.0 / 3.0);
  joint.transition = Eigen::Matrix3d::Constant(0.05);
  joint.transition.diagonal().setConstant(0.9);
  const double poses[3][3] = {{-6.0, 0.0, 1.0}, {0.0, 8.0, -1.0}, {5.0, -6.0, 0.0}};
  for (int j = 0; j < 3; ++j) {
    Eigen::VectorXd mean(7);
    mean << poses[j][0], poses[j][1], poses[j][2], 3.0 * (j - 1), 0.8 * (j - 1), 0.0, 0.0;
    Eigen::VectorXd variances(7);
    variances << 1.0, 1.0, 1.0, 1.0, 0.1, 0.05, 0.05;
    joint.states.emplace_back(Eigen::VectorXd::Ones(1), std::vector<hmm::Gaussian>{hmm::Gaussian(
                                                            mean, variances.asDiagonal(), hmm::CovarianceType::kFull)});
  }
  std::mt19937 random(seed);
  const hmm::Sample sample = hmm::sampleHmm(joint, frames, random);
  HeadRecording recording;
  recording.rotations = sample.frames.topRows(3);
  recording.prosody = sample.frames.bottomRows(4);
  return recording;
}

TEST(HeadModel, LearnsAVoiceThatDrivesTheHeadAndBeatsItsBaselines) {
  const HeadRecording train = synthetic(3000, 1);
  const HeadRecording test = synthetic(1000, 2);
  const HeadModel model =
      trainHeadModel({train}, {.startStates = 8, .entropicWeightPerFrame = 0.05, .maxIterations = 60});
  EXPECT_LE(model.hmm.numStates(), 8);
  EXPECT_GE(model.hmm.numStates(), 3);
  const Eigen::MatrixXd truth = test.rotations.colwise() - model.meanPose;
  const double paper = th::eval::headError(
      synthesiseHead(model, test.prosody, test.voiced, {.variant = HeadVariant::kStateMeans}), truth);
  const double trajectory = th::eval::headError(
      synthesiseHead(model, test.prosody, test.voiced, {.variant = HeadVariant::kTrajectory}), truth);
  const double posterior = th::eval::headError(
      synthesiseHead(model, test.prosody, test.voiced, {.variant = HeadVariant::kPosteriorMeans}), truth);
  const double walk = th::eval::headError(randomWalkHead(model, test.numFrames(), 4), truth);
  std::printf(
      "[ INFO     ] synthetic held-out E: paper %.3f, trajectory %.3f, posterior means %.3f, random walk %.3f\n", paper,
      trajectory, posterior, walk);
  EXPECT_LT(paper, 0.2);
  EXPECT_LT(trajectory, 0.2);
  EXPECT_LT(posterior, 0.2);
  EXPECT_GT(walk, 0.6) << "the voice is what makes the difference";
}

TEST(HeadModel, OnlineVariantsMatchBatchWithALongLagAndRespectTheirLag) {
  const HeadRecording train = synthetic(2000, 5);
  const HeadModel model = trainHeadModel({train}, {.startStates = 6, .maxIterations = 40});
  const HeadRecording test = synthetic(600, 6);
  for (HeadVariant variant : {HeadVariant::kStateMeans, HeadVariant::kPosteriorMeans}) {
    const Eigen::MatrixXd batch = synthesiseHead(model, test.prosody, test.voiced, {.variant = variant});
    const Eigen::MatrixXd online =
        synthesiseHead(model, test.prosody, test.voiced, {.variant = variant, .maxLagFrames = 600});
    EXPECT_LT((batch - online).cwiseAbs().maxCoeff(), 1e-9) << static_cast<int>(variant);
  }
  for (HeadVariant variant : {HeadVariant::kStateMeans, HeadVariant::kTrajectory, HeadVariant::kPosteriorMeans}) {
    HeadSynthesiser live(model, {.variant = variant, .maxLagFrames = 4});
    for (Eigen::Index t = 0; t < test.prosody.cols(); ++t) {
      live.acceptProsody(test.prosody.col(t), true);
      ASSERT_GE(live.numReady(), static_cast<int>(t) + 1 - live.lookaheadFrames())
          << "variant " << static_cast<int>(variant);
    }
    live.finish();
    EXPECT_EQ(live.numReady(), test.prosody.cols());
  }
  // The online trajectory, solved over windows, stays close to the batch trajectory.
  const Eigen::MatrixXd batch = synthesiseHead(model, test.prosody, test.voiced, {.variant = HeadVariant::kTrajectory});
  const Eigen::MatrixXd online =
      synthesiseHead(model, test.prosody, test.voiced, {.variant = HeadVariant::kTrajectory, .maxLagFrames = 600});
  EXPECT_LT(std::sqrt((batch - online).squaredNorm() / static_cast<double>(batch.size())), 0.2);
}

// Two speakers who move the same way at different sizes: the model learns the shapes in units of each one's
// spread and gives the geometric mean size; the voice still drives the head.
TEST(HeadModel, NormalisesEachSpeakersAmplitude) {
  HeadRecording calm = synthetic(2000, 11);
  calm.speaker = "calm";
  HeadRecording lively = synthetic(2000, 12);
  lively.speaker = "lively";
  lively.rotations = (4.0 * lively.rotations).colwise() + Eigen::Vector3d(10.0, -5.0, 2.0);
  const HeadModel model = trainHeadModel({calm, lively}, {.startStates = 8, .maxIterations = 40});
  EXPECT_EQ(model.speakers, (std::vector<std::string>{"calm", "lively"}));
  const auto spread = [](const Eigen::MatrixXd& x) {
    return Eigen::Vector3d(((x.colwise() - x.rowwise().mean()).cwiseAbs2().rowwise().mean()).cwiseSqrt());
  };
  const Eigen::Vector3d calmSpread = spread(calm.rotations);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(model.amplitude[axis], 2.0 * calmSpread[axis], 0.15 * calmSpread[axis]);
  const HeadRecording test = synthetic(1000, 13);
  const Eigen::MatrixXd out = synthesiseHead(model, test.prosody, test.voiced, {.variation = 0.0});
  const Eigen::MatrixXd truth = test.rotations.colwise() - test.rotations.rowwise().mean();
  EXPECT_LT(th::eval::headError(out / 2.0, truth), 0.25) << "the shapes at the calm speaker's size";
  // Without normalisation the lively speaker's offset mean pose and size dominate.
  const HeadModel raw =
      trainHeadModel({calm, lively}, {.startStates = 8, .maxIterations = 40, .normaliseSpeakers = false});
  EXPECT_EQ(raw.amplitude, Eigen::Vector3d::Ones());
}

// Frames without a voice do not move the decoder: over a long unvoiced stretch the smooth trajectory holds still,
// while decoding those frames' prosody too lets it wander.
TEST(HeadModel, UnvoicedFramesDoNotDriveTheStates) {
  const HeadModel model = trainHeadModel({synthetic(2000, 21)}, {.startStates = 6, .maxIterations = 40});
  HeadRecording test = synthetic(600, 22);
  test.voiced = Eigen::RowVectorXd::Ones(600);
  test.voiced.segment(200, 300).setZero();
  const Eigen::MatrixXd gated = synthesiseHead(model, test.prosody, test.voiced, {.variation = 0.0});
  const Eigen::MatrixXd free =
      synthesiseHead(model, test.prosody, test.voiced, {.voicedOnly = false, .variation = 0.0});
  const auto travel = [](const Eigen::MatrixXd& x) {
    return (x.middleCols(231, 239) - x.middleCols(230, 239)).colwise().norm().sum();
  };
  EXPECT_LT(travel(gated), 1e-6) << "one state throughout the silence";
  EXPECT_GT(travel(free), 1.0);
  // The online decoder agrees.
  const Eigen::MatrixXd online =
      synthesiseHead(model, test.prosody, test.voiced, {.maxLagFrames = 600, .variation = 0.0});
  EXPECT_LT(travel(online), 1e-3);
}

// The residual motion: real motion's spread and step, the same for a seed, quieter in pauses, and the same in
// batch and online synthesis.
TEST(HeadModel, ResidualMotionIsSeededAndQuieterInPauses) {
  HeadRecording train = synthetic(3000, 31);
  std::mt19937 random(3);
  std::normal_distribution<double> wobble(0.0, 1.0);
  for (Eigen::Index t = 0; t < train.rotations.cols(); ++t)
    for (int axis = 0; axis < 3; ++axis) train.rotations(axis, t) += wobble(random);
  const HeadModel model = trainHeadModel({train}, {.startStates = 6, .maxIterations = 40});
  EXPECT_GT(model.residualStd.minCoeff(), 0.1);
  EXPECT_GT(model.residualStepStd.minCoeff(), 0.1);
  HeadRecording test = synthetic(900, 32);
  test.voiced = Eigen::RowVectorXd::Ones(900);
  test.voiced.segment(300, 300).setZero();
  const Eigen::MatrixXd smooth = synthesiseHead(model, test.prosody, test.voiced, {.variation = 0.0});
  const Eigen::MatrixXd a = synthesiseHead(model, test.prosody, test.voiced, {});
  const Eigen::MatrixXd b = synthesiseHead(model, test.prosody, test.voiced, {});
  const Eigen::MatrixXd c = synthesiseHead(model, test.prosody, test.voiced, {.seed = 2});
  EXPECT_EQ(a, b);
  EXPECT_GT((a - c).cwiseAbs().maxCoeff(), 0.1);
  const Eigen::MatrixXd residual = a - smooth;
  const auto energy = [&](Eigen::Index begin) { return residual.middleCols(begin, 200).squaredNorm(); };
  EXPECT_LT(energy(380), 0.4 * energy(80)) << "a pause: the residual eased down";
  const Eigen::MatrixXd online = synthesiseHead(model, test.prosody, test.voiced, {.maxLagFrames = 900});
  EXPECT_LT(std::sqrt((a - online).squaredNorm() / static_cast<double>(a.size())), 0.2);
}

TEST(HeadModel, FileRoundTripAndRefusals) {
  const HeadModel model = trainHeadModel({synthetic(1500, 7)}, {.startStates = 5, .maxIterations = 30});
  const TemporaryFile file(".json");
  saveHeadModel(file.path(), model, {});
  const HeadModel loaded = loadHeadModel(file.path());
  EXPECT_EQ(loaded.meanPose, model.meanPose);
  EXPECT_EQ(loaded.amplitude, model.amplitude);
  EXPECT_EQ(loaded.residualStd, model.residualStd);
  EXPECT_EQ(loaded.residualStepStd, model.residualStepStd);
  EXPECT_TRUE(loaded.hasAcceleration);
  const HeadRecording test = synthetic(300, 8);
  EXPECT_EQ(synthesiseHead(loaded, test.prosody, test.voiced), synthesiseHead(model, test.prosody, test.voiced));
  // A plain HMM file is not a head model.
  const TemporaryFile plain(".json");
  hmm::saveModel(plain.path(), model.hmm);
  try {
    loadHeadModel(plain.path());
    FAIL() << "a plain HMM file was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(plain.path().string()), std::string::npos) << error.what();
  }
  // A head model whose training object lacks the mean pose, or names another kind with a number.
  for (const std::string training :
       {R"({"kind": "head"})", R"({"kind": 5})", R"({"kind": "head", "mean_pose_deg": [1, "x", 3]})"}) {
    const TemporaryFile broken(".json");
    hmm::saveModel(broken.path(), model.hmm, training);
    try {
      loadHeadModel(broken.path());
      FAIL() << training << " was accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(broken.path().string()), std::string::npos) << error.what();
    }
  }
}

// The viewer's measures: speed percentiles, pauses, the Fréchet distance and the matched random walk.
TEST(HeadEvaluation, SpeedPausesFrechetAndTheMatchedWalk) {
  const int frames = 3000;
  const Eigen::MatrixXd walk =
      th::eval::matchedRandomWalk(Eigen::Vector3d(2.0, 4.0, 1.0), Eigen::Vector3d(0.5, 0.5, 0.25), frames, 5);
  const th::eval::HeadMetrics self = th::eval::evaluateHead(walk, walk, 1e9);
  EXPECT_NEAR(self.poseStd[1], 4.0, 1.0);
  EXPECT_NEAR(self.velocityStd[0], 0.5, 0.05);
  EXPECT_NEAR(self.velocityStd[2], 0.25, 0.03);
  EXPECT_LT(th::eval::frechetDistance(walk, walk, 30.0), 1e-6);
  const Eigen::MatrixXd other =
      th::eval::matchedRandomWalk(Eigen::Vector3d(2.0, 4.0, 1.0), Eigen::Vector3d(0.5, 0.5, 0.25), frames, 6);
  const double sameKind = th::eval::frechetDistance(walk, other, 30.0);
  EXPECT_LT(sameKind, th::eval::frechetDistance(walk, 3.0 * other, 30.0));
  EXPECT_LT(sameKind, th::eval::frechetDistance(walk, Eigen::MatrixXd::Zero(3, frames), 30.0));
  EXPECT_THROW(th::eval::frechetDistance(walk.leftCols(10), walk, 30.0), Error);
  // Pauses: the second half is 40 dB down; a head that stops there has a pause/speech speed ratio of 0.
  Eigen::RowVectorXd level = Eigen::RowVectorXd::Constant(frames, -20.0);
  level.tail(frames / 2).setConstant(-60.0);
  const Eigen::RowVectorXd pauses = th::animation::pauseFrames(level);
  EXPECT_EQ(pauses.sum(), frames / 2);
  Eigen::MatrixXd stops = walk;
  for (int t = frames / 2; t < frames; ++t) stops.col(t) = walk.col(frames / 2 - 1);
  const th::animation::HeadMotionStatistics statistics = th::animation::motionStatistics(stops, pauses, 30.0);
  EXPECT_NEAR(statistics.pauseSpeechRatio, 0.0, 1e-12);
  EXPECT_NEAR(th::animation::motionStatistics(walk, pauses, 30.0).pauseSpeechRatio, 1.0, 0.1);
  EXPECT_GT(statistics.speedP95, 0.0);
}

TEST(HeadEvaluation, BeatAlignFindsMovementsThatStartOnTheSyllables) {
  // Speech: a syllable every 12 frames (the level jumps 20 dB and decays); the head: a nod that ends and
  // starts again on each syllable, the same nods half a period late, and a head that never moves.
  const int frames = 300;
  Eigen::RowVectorXd level(frames);
  for (int t = 0; t < frames; ++t) level[t] = -50.0 + 20.0 * std::exp(-(t % 12) / 3.0);
  const std::vector<int> syllables = th::animation::speechBeats(level);
  ASSERT_GE(syllables.size(), 22U);
  for (std::size_t k = 1; k < syllables.size(); ++k) EXPECT_EQ(syllables[k] - syllables[k - 1], 12);
  const auto nods = [&](double shift) {
    Eigen::MatrixXd rotations = Eigen::MatrixXd::Zero(3, frames);
    for (int t = 0; t < frames; ++t) rotations(0, t) = 3.0 * std::sin(M_PI * (t - shift) / 12.0);
    return rotations;
  };
  // The nod's speed is least where it turns (t = 6 + 12k + shift, between frames: no two frames tie); on the
  // syllables with shift -5.7, half a period off with 0.3.
  const double onBeat = th::eval::beatAlign(syllables, th::animation::motionBeats(nods(-5.7)));
  const double late = th::eval::beatAlign(syllables, th::animation::motionBeats(nods(0.3)));
  EXPECT_GT(onBeat, 0.9);
  EXPECT_LT(late, 0.3);  // 5 frames off: exp(-25 / 18)
  EXPECT_EQ(th::eval::beatAlign(syllables, th::animation::motionBeats(Eigen::MatrixXd::Zero(3, frames))), 0.0);
  // Quiet speech has no beats; a beat needs a rise of 2 dB and 6 frames from the last.
  EXPECT_TRUE(th::animation::speechBeats(Eigen::RowVectorXd::Constant(frames, -40.0)).empty());
  // Diversity: the mean over the axes of the pose's spread.
  EXPECT_NEAR(th::eval::poseDiversity(nods(0.0)), 3.0 / std::sqrt(2.0) / 3.0, 0.02);
}

TEST(HeadEvaluation, ChanceBeatAlignTellsTimingFromTheRateOfMovements) {
  // Stressed syllables at irregular intervals (20 to 40 frames, as often as heads turn); a head whose every
  // movement turns on one (a half-cosine from one to the next), and the same movements on another take's.
  const int frames = 1800;
  std::mt19937 random(3);
  std::uniform_int_distribution<int> gap(20, 40);
  const auto syllablesOf = [&] {
    std::vector<int> at{5};
    while (at.back() + 40 < frames) at.push_back(at.back() + gap(random));
    return at;
  };
  const auto levelOf = [&](const std::vector<int>& at) {
    Eigen::RowVectorXd level = Eigen::RowVectorXd::Constant(frames, -50.0);
    for (int t = 0; t < frames; ++t)
      for (const int s : at)
        if (s <= t) level[t] = -50.0 + 20.0 * std::exp(-(t - s) / 3.0);
    return level;
  };
  const auto headTurningOn = [&](const std::vector<int>& at) {
    Eigen::MatrixXd rotations = Eigen::MatrixXd::Zero(3, frames);
    for (std::size_t k = 0; k + 1 < at.size(); ++k)
      for (int t = at[k]; t < std::min(at[k + 1], frames); ++t)
        rotations(0, t) = (k % 2 == 0 ? 3.0 : -3.0) * std::cos(M_PI * (t - at[k] + 0.5) / (at[k + 1] - at[k]));
    return rotations;
  };
  const std::vector<int> take = syllablesOf(), other = syllablesOf();
  const std::vector<int> beats = th::animation::speechBeats(levelOf(take));
  ASSERT_GE(beats.size(), 40U);
  const std::vector<int> locked = th::animation::motionBeats(headTurningOn(take));
  const std::vector<int> unlocked = th::animation::motionBeats(headTurningOn(other));
  const double onBeat = th::eval::beatAlign(beats, locked);
  const double onBeatByChance = th::eval::chanceBeatAlign(beats, locked, frames);
  const double elsewhere = th::eval::beatAlign(beats, unlocked);
  const double elsewhereByChance = th::eval::chanceBeatAlign(beats, unlocked, frames);
  EXPECT_GT(onBeat, 0.8);
  EXPECT_LT(onBeatByChance, onBeat - 0.2) << "moved off the syllables, the same movements score less";
  // Movements as frequent but timed by something else: about what chance gives them.
  EXPECT_LT(elsewhere, onBeat - 0.2);
  EXPECT_NEAR(elsewhere, elsewhereByChance, 0.12);
  EXPECT_EQ(th::eval::chanceBeatAlign(beats, locked, 0), 0.0);
}

TEST(HeadData, StyleTalkClipsHaveTheirSpeakersVoicingAndLevel) {
  const std::vector<HeadRecording> clips = th::eval::loadStyleTalkHeads();
  ASSERT_EQ(clips.size(), 6u);
  std::set<std::string> speakers;
  for (const auto& clip : clips) {
    speakers.insert(clip.speaker);
    EXPECT_EQ(clip.voiced.size(), clip.numFrames());
    EXPECT_EQ(clip.levelDb.size(), clip.numFrames());
    const double voicedShare = clip.voiced.mean();
    EXPECT_GT(voicedShare, 0.3) << clip.name;
    EXPECT_LT(voicedShare, 0.9) << clip.name;
    EXPECT_GT(clip.rotations.cwiseAbs().maxCoeff(), 1.0) << clip.name;
  }
  EXPECT_EQ(speakers, (std::set<std::string>{"KristiNoem", "Obama", "andrew"}));
}

TEST(HeadData, Beat2TakeIsAlignedAndPlausible) {
  const HeadRecording take = th::eval::loadBeat2Head();
  EXPECT_EQ(take.numFrames(), 1906);
  EXPECT_EQ(take.speaker, "scott");
  EXPECT_TRUE(take.prosody.allFinite());
  const Eigen::Vector3d spread =
      ((take.rotations.colwise() - take.rotations.rowwise().mean()).cwiseAbs2().rowwise().mean()).cwiseSqrt();
  // The data's README: neck+head std about 4.6 / 7.1 / 4.0 degrees.
  EXPECT_NEAR(spread[0], 4.6, 0.5);
  EXPECT_NEAR(spread[1], 7.1, 0.5);
  EXPECT_NEAR(spread[2], 4.0, 0.5);
  const auto [train, test] = splitByTime(take, 0.75);
  EXPECT_EQ(train.numFrames() + test.numFrames(), 1906);
  EXPECT_NEAR(test.startSeconds, train.numFrames() / 30.0, 1e-12);
}

}  // namespace
}  // namespace th::animation
