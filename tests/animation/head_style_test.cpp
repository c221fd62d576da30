// A person's head style: its measures on motion made here, the fit of the shipped head model to a real speaker
// (and to the same speaker made twice and half as lively), the rest pose it adds and the idle behaviour eases to,
// its file, and the clips it refuses.
#include "animation/head_style.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>

#include "animation/head_measures.h"
#include "animation/idle_motion.h"
#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "eval/head_corpus.h"
#include "support/files.h"

namespace th::animation {
namespace {

constexpr double kFps = 30.0;

const HeadModel& shippedHead() {
  static const HeadModel model = loadHeadModel(std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "models/head.json");
  return model;
}

// BEAT2's speaker: the first three quarters of the take (47.6 s), the part the shipped model trained on least
// matters here (the style is fitted to whatever clip it is given).
const HeadRecording& beat2Clip() {
  static const HeadRecording clip = [] {
    const HeadRecording take = th::eval::loadBeat2Head();
    return framesOf(take, 0, take.numFrames() * 3 / 4);
  }();
  return clip;
}

// The fit to that clip (made once: each fit plays the model some 150 times).
const HeadStyle& beat2Style() {
  static const HeadStyle style = fitHeadStyle(shippedHead(), beat2Clip());
  return style;
}

TEST(HeadStyleMeasures, TheLongestStepIsTheLargestFrameToFrameDistance) {
  Eigen::MatrixXd rotations = Eigen::MatrixXd::Zero(3, 4);
  rotations.col(1) << 3.0, 4.0, 0.0;  // a step of 5 degrees
  rotations.col(2) << 3.0, 4.0, 2.0;  // 2
  rotations.col(3) << 0.0, 0.0, 2.0;  // 5 again, back
  EXPECT_DOUBLE_EQ(longestStep(rotations), 5.0);
  EXPECT_EQ(longestStep(rotations.leftCols(1)), 0.0);
}

TEST(HeadStyleMeasures, SpreadSpeedBeatsAndPausesOfAKnownMotion) {
  // 20 s: yaw a sine of 6 degrees' amplitude and a 2 s period; pitch 2 degrees, roll still. The sound is loud for
  // the first 15 s and silent for the last 5, where the head moves at a third of the speed.
  const int frames = 600;
  Eigen::MatrixXd rotations = Eigen::MatrixXd::Zero(3, frames);
  Eigen::RowVectorXd level = Eigen::RowVectorXd::Constant(frames, -20.0);
  double phase = 0.0;
  for (int t = 0; t < frames; ++t) {
    const bool pause = t >= 450;
    if (pause) level[t] = -80.0;
    phase += 2.0 * std::numbers::pi / (2.0 * kFps) * (pause ? 1.0 / 3.0 : 1.0);
    rotations(1, t) = 6.0 * std::sin(phase);
    rotations(0, t) = 2.0 * std::sin(phase);
  }
  const HeadStyleMeasures m = measureHeadStyle(rotations, level, kFps);
  EXPECT_NEAR(m.seconds, 20.0, 1e-12);
  EXPECT_NEAR(m.spread[1], 6.0 / std::sqrt(2.0), 0.5);
  EXPECT_NEAR(m.spread[0], 2.0 / std::sqrt(2.0), 0.2);
  EXPECT_EQ(m.spread[2], 0.0);
  // The fastest: 6.3 degrees times 2π / 2 s, nearly, at the sine's zero crossings.
  const double peakSpeed = std::hypot(6.0, 2.0) * std::numbers::pi;
  EXPECT_GT(m.speedP95, 0.9 * peakSpeed);
  EXPECT_LT(m.speedP95, 1.01 * peakSpeed);
  EXPECT_TRUE(m.pauses);
  EXPECT_NEAR(m.pauseSpeechRatio, 1.0 / 3.0, 0.05);
  // The speed's minima are the sine's turns, two a period: 15 in the 7.5 periods of speech, 1 or 2 in the 0.83
  // of the pause.
  EXPECT_NEAR(m.beatsPerSecond, 16.5 / 20.0, 0.1);
  // Without a second of quiet there are no pauses to speak of.
  const HeadStyleMeasures loud = measureHeadStyle(rotations, Eigen::RowVectorXd::Constant(frames, -20.0), kFps);
  EXPECT_FALSE(loud.pauses);
  EXPECT_EQ(loud.pauseSpeechRatio, 0.0);
}

TEST(HeadStyle, TheFitMovesTheShippedModelLikeTheSpeakerOnTheirOwnSpeech) {
  const HeadStyle& style = beat2Style();
  std::printf(
      "[ INFO     ] %s, %.1f s: spread %.2f / %.2f / %.2f deg, p95 speed %.1f deg/s, %.2f beats/s, pause/speech "
      "%.2f; fitted gain %.2f / %.2f / %.2f, smoothing %.2f, variation %.2f, pause variation %.2f: p95 speed %.1f, "
      "%.2f beats/s, pause/speech %.2f\n",
      style.source.c_str(), style.person.seconds, style.person.spread[0], style.person.spread[1],
      style.person.spread[2], style.person.speedP95, style.person.beatsPerSecond, style.person.pauseSpeechRatio,
      style.axisGain[0], style.axisGain[1], style.axisGain[2], style.smoothing, style.variation, style.pauseVariation,
      style.fitted.speedP95, style.fitted.beatsPerSecond, style.fitted.pauseSpeechRatio);
  EXPECT_EQ(style.source, beat2Clip().name);
  EXPECT_GT(style.person.seconds, 40.0);
  // The spread is matched on every axis by construction, speed and beats by the grid, the pauses by their gain.
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(style.fitted.spread[axis] / style.person.spread[axis], 1.0, 0.02) << "axis " << axis;
  EXPECT_NEAR(std::log(style.fitted.speedP95 / style.person.speedP95), 0.0, std::log(1.25));
  EXPECT_NEAR(std::log(style.fitted.beatsPerSecond / style.person.beatsPerSecond), 0.0, std::log(1.3));
  ASSERT_TRUE(style.person.pauses);
  EXPECT_NEAR(style.fitted.pauseSpeechRatio, style.person.pauseSpeechRatio, 0.15);
  EXPECT_NEAR((style.restPose - beat2Clip().rotations.rowwise().mean()).norm(), 0.0, 1e-12);
  // No step the person does not make: the styled motion's longest, under each of the fit's seeds, is within the
  // person's longest.
  const double persons = longestStep(beat2Clip().rotations);
  for (unsigned seed = 1; seed <= HeadStyleFitOptions{}.seeds; ++seed) {
    HeadSynthesisOptions synthesis;
    applyHeadStyle(style, synthesis);
    synthesis.seed = seed;
    const Eigen::MatrixXd motion = synthesiseHead(shippedHead(), beat2Clip().prosody, beat2Clip().voiced, synthesis);
    EXPECT_LE(longestStep(motion), persons) << "seed " << seed;
  }
}

TEST(HeadStyle, ALivelierPersonGetsALargerGainAndAStillerOneASmaller) {
  const HeadStyle& style = beat2Style();
  for (const double size : {2.0, 0.5}) {
    HeadRecording other = beat2Clip();
    const Eigen::Vector3d mean = other.rotations.rowwise().mean();
    other.rotations = ((other.rotations.colwise() - mean) * size).colwise() + mean;
    const HeadStyle scaled = fitHeadStyle(shippedHead(), other);
    // Spread and speed scale alike, so the same smoothing fits and the gain follows the size.
    EXPECT_EQ(scaled.smoothing, style.smoothing) << "size " << size;
    EXPECT_EQ(scaled.variation, style.variation) << "size " << size;
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_NEAR(scaled.axisGain[axis] / style.axisGain[axis], size, 0.02 * size) << "axis " << axis;
  }
}

TEST(HeadStyle, TheSynthesisAddsTheRestPoseAndTheIdleHeadEasesToIt) {
  HeadStyle style = beat2Style();
  style.restPose = Eigen::Vector3d(4.0, -6.0, 2.0);
  HeadSynthesisOptions plain;
  HeadSynthesisOptions styled;
  applyHeadStyle(style, styled);
  EXPECT_EQ(styled.axisGain, style.axisGain);
  EXPECT_EQ(styled.smoothing, style.smoothing);
  EXPECT_EQ(styled.pauseVariation, style.pauseVariation);
  // A user's smoothing and variation act on top of the person's.
  HeadSynthesisOptions adjusted;
  adjusted.smoothing = 2.0;
  adjusted.variation = 0.5;
  applyHeadStyle(style, adjusted);
  EXPECT_DOUBLE_EQ(adjusted.smoothing, 2.0 * style.smoothing);
  EXPECT_DOUBLE_EQ(adjusted.variation, 0.5 * style.variation);
  const HeadRecording& clip = beat2Clip();
  const Eigen::MatrixXd rest = synthesiseHead(shippedHead(), clip.prosody, clip.voiced, plain);
  styled.axisGain = Eigen::Vector3d::Ones();
  styled.smoothing = plain.smoothing;
  styled.variation = plain.variation;
  styled.pauseVariation = plain.pauseVariation;
  const Eigen::MatrixXd moved = synthesiseHead(shippedHead(), clip.prosody, clip.voiced, styled);
  EXPECT_LT(((moved - rest).colwise() - style.restPose).cwiseAbs().maxCoeff(), 1e-9);

  // In silence the idle behaviour brings the head to the rest pose, not to zero.
  IdleMotionOptions options;
  options.headRestDegrees = style.restPose;
  IdleMotion idle(options);
  face::FapFrame faps{};
  const double unitsPerDegree = std::numbers::pi / 180.0 / face::kAngleUnit;
  for (int frame = 0; frame < 150; ++frame) {
    faps[48] = faps[49] = faps[50] = 20.0 * unitsPerDegree;  // the synthesis's head, far from the rest
    idle.apply(frame / kFps, frame < 30 ? -20.0 : -90.0, {}, faps);
  }
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(faps[static_cast<std::size_t>(48 + axis)] / unitsPerDegree, style.restPose[axis], 0.05);
}

TEST(HeadStyle, AStepLongerThanTheLimitIsShortenedAndTheRestFollows) {
  Eigen::MatrixXd motion = Eigen::MatrixXd::Zero(3, 8);
  motion.rightCols(6).row(1).setConstant(10.0);  // a 10 degree jump in yaw at frame 2
  Eigen::MatrixXd limited = motion;
  limitHeadSteps(limited, 3.0);
  const Eigen::RowVectorXd expected = (Eigen::RowVectorXd(8) << 0, 0, 3, 6, 9, 10, 10, 10).finished();
  EXPECT_LT((limited.row(1) - expected).cwiseAbs().maxCoeff(), 1e-12) << limited;
  EXPECT_TRUE(limited.row(0).isZero(0.0));
  Eigen::MatrixXd unlimited = motion;
  limitHeadSteps(unlimited, 0.0);
  EXPECT_EQ(unlimited, motion);
}

TEST(HeadStyle, TheStyledHeadStepsNoFasterThanThePersonsFastSteps) {
  const HeadStyle& style = beat2Style();
  ASSERT_GT(style.person.speedP99, style.person.speedP95);
  HeadSynthesisOptions synthesis;
  applyHeadStyle(style, synthesis);
  const double limit = style.person.speedP99 / kFps;
  EXPECT_DOUBLE_EQ(synthesis.maxStepDegrees, limit);
  const HeadRecording& clip = beat2Clip();
  HeadSynthesisOptions free = synthesis;
  free.maxStepDegrees = 0.0;
  const Eigen::MatrixXd unlimited = synthesiseHead(shippedHead(), clip.prosody, clip.voiced, free);
  const Eigen::MatrixXd batch = synthesiseHead(shippedHead(), clip.prosody, clip.voiced, synthesis);
  // Without the limit some steps are faster (so the limit does something), with it none, and the motion is the
  // same but for those: its spread within 2 %.
  EXPECT_GT(longestStep(unlimited), limit);
  EXPECT_LE(longestStep(batch), limit + 1e-9);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(axisStd(batch)[axis] / axisStd(unlimited)[axis], 1.0, 0.02) << "axis " << axis;
  // Live (decoded with a lag) alike, and twice the amplitude allows twice the step.
  synthesis.maxLagFrames = 2;
  EXPECT_LE(longestStep(synthesiseHead(shippedHead(), clip.prosody, clip.voiced, synthesis)), limit + 1e-9);
  synthesis.amplitude = 2.0;
  const Eigen::MatrixXd larger = synthesiseHead(shippedHead(), clip.prosody, clip.voiced, synthesis);
  EXPECT_LE(longestStep(larger), 2.0 * limit + 1e-9);
  EXPECT_GT(longestStep(larger), limit);
}

TEST(HeadStyle, TheFileKeepsEverythingAndBadFilesFailNamingTheField) {
  const HeadStyle& style = beat2Style();
  const TemporaryFolder folder;
  const auto path = folder.path() / "scott.head-style.json";
  saveHeadStyle(path, style);
  EXPECT_TRUE(isHeadStyleFile(path));
  const HeadStyle back = loadHeadStyle(path);
  EXPECT_EQ(back.source, style.source);
  EXPECT_LT((back.axisGain - style.axisGain).norm(), 1e-12);
  EXPECT_LT((back.restPose - style.restPose).norm(), 1e-12);
  EXPECT_EQ(back.smoothing, style.smoothing);
  EXPECT_EQ(back.variation, style.variation);
  EXPECT_EQ(back.pauseVariation, style.pauseVariation);
  EXPECT_LT((back.person.spread - style.person.spread).norm(), 1e-12);
  EXPECT_EQ(back.person.pauses, style.person.pauses);
  EXPECT_EQ(back.person.speedP99, style.person.speedP99);
  EXPECT_EQ(back.fitted.beatsPerSecond, style.fitted.beatsPerSecond);

  const auto failsWith = [&](const std::string& text, const std::string& expected) {
    const auto bad = folder.path() / "bad.json";
    std::ofstream(bad) << text;
    try {
      loadHeadStyle(bad);
      ADD_FAILURE() << "no error for " << text;
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(bad.string()), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  failsWith(R"({"format": "talkinghead-animation", "version": 1})", "format");
  failsWith("not json", "JSON");
  const std::string text = th::test::readText(path);
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string copy = text;
    copy.replace(copy.find(from), from.size(), to);
    return copy;
  };
  failsWith(replaced("\"smoothing\": ", "\"smoothing\": -"), "synthesis.smoothing");
  failsWith(replaced("\"axis_gain\": [", "\"axis_gain\": [1, "), "synthesis.axis_gain");
  // A negative speed limit would read as none.
  failsWith(replaced("\"speed_p99_deg_s\": ", "\"speed_p99_deg_s\": -"), "speed_p99_deg_s is negative");
  std::string negativeSpread = text;
  negativeSpread.insert(negativeSpread.find_first_of("0123456789", negativeSpread.find("\"spread_deg\"")), "-");
  failsWith(negativeSpread, "spread_deg has a negative spread");
  // A style saved before the step limit (no 99th-percentile speed) is read, and limits nothing.
  std::string older = text;
  const auto field = older.find("\"speed_p99_deg_s\"");
  ASSERT_NE(field, std::string::npos);
  older.erase(field, older.find('\n', field) + 1 - field);
  const auto olderPath = folder.path() / "older.json";
  std::ofstream(olderPath) << older;
  HeadSynthesisOptions synthesis;
  applyHeadStyle(loadHeadStyle(olderPath), synthesis);
  EXPECT_EQ(synthesis.maxStepDegrees, 0.0);
}

// A track's pose CSV at a 25 fps video's rate, some frames without a face, beside the take's sound.
TEST(HeadStyle, APoseCsvAtAVideosRateIsReadAtThirtyFramesASecond) {
  const TemporaryFolder folder;
  const auto csv = folder.path() / "take.csv";
  const double seconds = 12.0;
  {
    std::ofstream out(csv);
    out << "time_s,face,pitch_deg,yaw_deg,roll_deg,residual_px\n";
    for (int f = 0; f <= static_cast<int>(seconds * 25); ++f) {
      const double t = f / 25.0;
      out << t << ',' << (f % 10 == 3 ? 0 : 1) << ',' << 10.0 * t << ',' << -2.0 * t << ',' << 1.5 << ",0.5\n";
    }
  }
  std::vector<float> sound = audio::readAudioFile(th::sharedDataPath("beat2/2_scott_0_1_1.wav")).samples;
  sound.resize(static_cast<std::size_t>((seconds + 1.0) * 16000));
  audio::writeWav16(folder.path() / "take.wav", sound, 16000);
  const HeadRecording read = readHeadRecording(folder.path() / "take.wav", csv);
  EXPECT_EQ(read.name, "take");
  EXPECT_EQ(read.numFrames(), static_cast<int>(seconds * 30) + 1);
  for (int i = 0; i < read.numFrames(); ++i) {
    EXPECT_NEAR(read.rotations(0, i), 10.0 * i / 30.0, 1e-9) << i;
    EXPECT_NEAR(read.rotations(1, i), -2.0 * i / 30.0, 1e-9) << i;
    EXPECT_NEAR(read.rotations(2, i), 1.5, 1e-12) << i;
  }
  EXPECT_EQ(read.prosody.cols(), read.numFrames());
  EXPECT_GT(read.voiced.mean(), 0.2);

  // A style file is read as it is, whatever its name.
  const auto styleFile = folder.path() / "scott.style";
  saveHeadStyle(styleFile, beat2Style());
  EXPECT_EQ(headStyleFromFile(shippedHead(), styleFile).smoothing, beat2Style().smoothing);

  const auto failsWith = [&](const std::filesystem::path& file, const std::string& expected) {
    try {
      headStyleFromFile(shippedHead(), file);
      ADD_FAILURE() << "no error for " << file;
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  const auto lonely = folder.path() / "lonely.csv";
  std::filesystem::copy_file(csv, lonely);
  failsWith(lonely, "lonely.wav");
  const auto faceless = folder.path() / "faceless.csv";
  {
    std::ofstream out(faceless);
    out << "time_s,face,pitch_deg,yaw_deg,roll_deg\n";
    for (int f = 0; f < 300; ++f) out << f / 25.0 << ',' << (f < 100 ? 1 : 0) << ",1,2,3\n";
  }
  std::filesystem::copy_file(folder.path() / "take.wav", folder.path() / "faceless.wav");
  failsWith(faceless, "the face was found in 100 of its 300 frames");
  const auto text = folder.path() / "notes.txt";
  std::ofstream(text) << "hello";
  failsWith(text, "not a head style");
  failsWith(folder.path() / "missing.csv", "no such file");
}

TEST(HeadStyle, ClipsTooShortSilentOrStillAreRefusedNamingTheClip) {
  const HeadRecording& clip = beat2Clip();
  const auto refuses = [&](const HeadRecording& bad, const std::string& expected) {
    try {
      fitHeadStyle(shippedHead(), bad);
      ADD_FAILURE() << "no error for " << expected;
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(bad.name), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  };
  refuses(framesOf(clip, 0, 150), "a style needs 10 s");
  HeadRecording silent = clip;
  silent.voiced.setZero();
  refuses(silent, "no speech");
  HeadRecording still = clip;
  still.rotations.colwise() = clip.rotations.col(0);
  refuses(still, "does not move");
}

}  // namespace
}  // namespace th::animation
