// A person's head style as a user meets it: `talkinghead style` on a talking video and on the head-pose CSV
// another tracker made of the same video (they must agree), --head-style on animate, export and live (the rest
// pose moves every frame of each by the same angles; the fitted gains move the head like the person), and the
// clips it refuses in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "animation/head_model.h"
#include "animation/head_style.h"
#include "audio/audio_file.h"
#include "cli_runner.h"
#include "core/data_path.h"
#include "face/fap.h"
#include "formats/animation_format.h"
#include "support/files.h"
#include "tracking_test_support.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

constexpr double kDegreesPerUnit = th::face::kAngleUnit * 180.0 / 3.14159265358979323846;

class HeadStyleCliTest : public th::test::CliTest {
 protected:
  // StyleTalk's Obama, 20 s (the style's clip) and 30 s (another clip of him, animated).
  static fs::path styleVideo() { return th::sharedDataPath("talking/styletalk/Obama_clip1.mp4"); }
  static fs::path otherClip() { return th::sharedDataPath("talking/styletalk/Obama_clip2.wav"); }
  static fs::path prompt() { return th::sharedDataPath("speech/arctic/arctic_a0001.wav"); }

  // A style that only moves the rest pose: the model's own motion, shifted.
  fs::path restOnlyStyle(const Eigen::Vector3d& rest) const {
    th::animation::HeadStyle style;
    style.source = "made by the test";
    style.restPose = rest;
    const fs::path path = out() / "rest.json";
    th::animation::saveHeadStyle(path, style);
    return path;
  }
};

// Head rotation per frame (3 x T, degrees) of an animation file.
Eigen::MatrixXd headDegrees(const fs::path& file) {
  const th::face::FapTrack track = th::formats::readAnimation(file);
  Eigen::MatrixXd head(3, track.numFrames());
  for (int axis = 0; axis < 3; ++axis) {
    const int row = track.rowOf(48 + axis);
    EXPECT_GE(row, 0) << file;
    if (row >= 0) head.row(axis) = track.values.row(row) * kDegreesPerUnit;
  }
  return head;
}

Eigen::Vector3d spreadOf(const Eigen::MatrixXd& head) {
  const Eigen::MatrixXd centred = head.colwise() - head.rowwise().mean();
  return (centred.array().square().rowwise().mean()).sqrt();
}

// The shift between two animations of the same speech, frame by frame, at its largest off `rest`.
double offRest(const Eigen::MatrixXd& styled, const Eigen::MatrixXd& plain, const Eigen::Vector3d& rest) {
  EXPECT_EQ(styled.cols(), plain.cols());
  if (styled.cols() != plain.cols()) return 1e9;
  return ((styled - plain).colwise() - rest).cwiseAbs().maxCoeff();
}

TEST_F(HeadStyleCliTest, AVideoAndItsPoseCsvByAnotherTrackerGiveTheSameStyle) {
  const fs::path fromVideo = out() / "video.json";
  CliResult result = runCli({"style", styleVideo().string(), "-o", fromVideo.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("wrote " + fromVideo.string()), std::string::npos) << result.out;
  const th::animation::HeadStyle video = th::animation::loadHeadStyle(fromVideo);
  EXPECT_EQ(video.source, "Obama_clip1.mp4");
  EXPECT_NEAR(video.person.seconds, 20.0, 0.5);

  // StyleTalk's pose of the same video (a 3DMM fitted to each frame), beside its sound.
  const fs::path csv = out() / "obama.csv";
  fs::copy_file(th::sharedDataPath("talking/styletalk/Obama_clip1_headpose_30fps.csv"), csv);
  fs::copy_file(th::sharedDataPath("talking/styletalk/Obama_clip1.wav"), out() / "obama.wav");
  const fs::path fromCsv = out() / "csv.json";
  result = runCli({"style", csv.string(), "-o", fromCsv.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const th::animation::HeadStyle other = th::animation::loadHeadStyle(fromCsv);
  std::printf(
      "[ INFO     ] spread from the video %.2f / %.2f / %.2f deg, from the 3DMM pose %.2f / %.2f / %.2f; p95 speed "
      "%.0f and %.0f deg/s\n",
      video.person.spread[0], video.person.spread[1], video.person.spread[2], other.person.spread[0],
      other.person.spread[1], other.person.spread[2], video.person.speedP95, other.person.speedP95);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(std::log(video.person.spread[axis] / other.person.spread[axis]), 0.0, std::log(1.4)) << axis;
  EXPECT_NEAR(std::log(video.person.speedP95 / other.person.speedP95), 0.0, std::log(1.3));

  // Animating his other clip, the styled head spreads like him on every axis, nearer than the model's own.
  const fs::path plain = out() / "plain.csv";
  const fs::path styled = out() / "styled.csv";
  ASSERT_EQ(runCli({"animate", otherClip().string(), "-o", plain.string()}, logs()).exitCode, 0);
  result = runCli({"animate", otherClip().string(), "-o", styled.string(), "--head-style", fromVideo.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.err.find("head style Obama_clip1.mp4"), std::string::npos) << result.err;
  const Eigen::Vector3d plainSpread = spreadOf(headDegrees(plain));
  const Eigen::Vector3d styledSpread = spreadOf(headDegrees(styled));
  for (int axis = 0; axis < 3; ++axis) {
    const double person = video.person.spread[axis];
    EXPECT_LT(std::abs(std::log(styledSpread[axis] / person)), std::abs(std::log(plainSpread[axis] / person)))
        << "axis " << axis << ": styled " << styledSpread[axis] << ", plain " << plainSpread[axis] << ", person "
        << person;
    EXPECT_NEAR(std::log(styledSpread[axis] / person), 0.0, std::log(1.5)) << axis;
  }
}

TEST_F(HeadStyleCliTest, TheRestPoseMovesEveryFrameOfAnimateExportAndLive) {
  const Eigen::Vector3d rest(6.0, -9.0, 3.0);
  const fs::path style = restOnlyStyle(rest);
  const std::string speech = prompt().string();
  const auto both = [&](std::vector<std::string> arguments, const fs::path& plain, const fs::path& styled) {
    CliResult result = runCli(arguments, logs());
    ASSERT_EQ(result.exitCode, 0) << result.err;
    arguments.push_back("--head-style");
    arguments.push_back(style.string());
    for (std::string& argument : arguments)
      if (argument == plain.string()) argument = styled.string();
    result = runCli(arguments, logs());
    ASSERT_EQ(result.exitCode, 0) << result.err;
  };
  // FAPs are written in whole angle units (1e-5 rad): 0.001 degrees.
  constexpr double kWritten = 1e-3;
  both({"animate", speech, "-o", (out() / "a.csv").string()}, out() / "a.csv", out() / "a_styled.csv");
  EXPECT_LT(offRest(headDegrees(out() / "a_styled.csv"), headDegrees(out() / "a.csv"), rest), kWritten);
  both({"animate", speech, "-o", (out() / "o.csv").string(), "--online", "--preset", "default"}, out() / "o.csv",
       out() / "o_styled.csv");
  EXPECT_LT(offRest(headDegrees(out() / "o_styled.csv"), headDegrees(out() / "o.csv"), rest), kWritten);
  both({"export", speech, "-o", (out() / "e.mp4").string(), "--size", "32x24", "--save-anim",
        (out() / "e.csv").string()},
       out() / "e.csv", out() / "e_styled.csv");
  EXPECT_LT(offRest(headDegrees(out() / "e_styled.csv"), headDegrees(out() / "e.csv"), rest), kWritten);
  both({"live", "--headless", "--no-settings", "--input", speech, "--speed", "0", "--dump", (out() / "l.csv").string()},
       out() / "l.csv", out() / "l_styled.csv");
  EXPECT_LT(offRest(headDegrees(out() / "l_styled.csv"), headDegrees(out() / "l.csv"), rest), kWritten);
}

TEST_F(HeadStyleCliTest, StylesGoToTheFolderTheLivePanelListsWithoutAnOutputName) {
  const fs::path config = out() / "config";
  ASSERT_EQ(setenv("XDG_CONFIG_HOME", config.c_str(), 1), 0);
  const fs::path csv = out() / "obama.csv";
  fs::copy_file(th::sharedDataPath("talking/styletalk/Obama_clip1_headpose_30fps.csv"), csv);
  fs::copy_file(th::sharedDataPath("talking/styletalk/Obama_clip1.wav"), out() / "obama.wav");
  const CliResult result = runCli({"style", csv.string()}, logs());
  unsetenv("XDG_CONFIG_HOME");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_TRUE(th::animation::isHeadStyleFile(config / "talkinghead" / "head-styles" / "obama.json"));
}

// train head --video: the user's clip tracked and trained on beside the corpora (a small model, quickly), its
// last quarter held out and judged beside the shipped model.
TEST_F(HeadStyleCliTest, TrainHeadOnOnesOwnVideoHoldsOutAndJudgesPartOfIt) {
  const fs::path folder = out() / "me";
  fs::create_directories(folder);
  fs::copy_file(styleVideo(), folder / "take.mp4");
  fs::copy_file(th::sharedDataPath("talking/styletalk/Obama_clip1.wav"), folder / "take.wav");
  const fs::path model = out() / "head.json";
  expectOneLineFailure(runCli({"train", "head", "--video", folder.string()}, logs()), "", "give -o");
  const CliResult result = runCli({"train", "head", "--video", folder.string(), "-o", model.string(), "--start-states",
                                   "6", "--iterations", "5", "--residual-from-training"},
                                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("me: 1 clips tracked, 1 trained on"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("take.mp4 (last quarter)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("trained with these clips (5 seeds)"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("the shipped model (5 seeds)"), std::string::npos) << result.out;
  const th::animation::HeadModel trained = th::animation::loadHeadModel(model);
  EXPECT_NE(std::find(trained.speakers.begin(), trained.speakers.end(), "me"), trained.speakers.end());
  EXPECT_TRUE(fs::exists(out() / "head_tracks" / "take.mp4.csv"));
}

TEST_F(HeadStyleCliTest, BadClipsFailInOneLineAndLeaveNoFile) {
  const fs::path output = out() / "style.json";
  expectOneLineFailure(runCli({"style", (out() / "missing.mp4").string(), "-o", output.string()}, logs()),
                       (out() / "missing.mp4").string(), "no such file");
  // Too short: the tracking tests' faceless video is 2 s.
  const fs::path faceless = out() / "faceless.mp4";
  th::test::writeFacelessVideo(faceless);
  expectOneLineFailure(runCli({"style", faceless.string(), "-o", output.string()}, logs()), faceless.string(),
                       "a head style needs 10 s");
  // A pose without its sound.
  const fs::path lonely = out() / "lonely.csv";
  fs::copy_file(th::sharedDataPath("talking/styletalk/Obama_clip1_headpose_30fps.csv"), lonely);
  expectOneLineFailure(runCli({"style", lonely.string(), "-o", output.string()}, logs()), lonely.string(),
                       "lonely.wav");
  // A pose whose take is silent: no speech to fit to.
  const fs::path quiet = out() / "quiet.csv";
  fs::copy_file(lonely, quiet);
  th::audio::writeWav16(out() / "quiet.wav", std::vector<float>(16000 * 21, 0.0f), 16000);
  expectOneLineFailure(runCli({"style", quiet.string(), "-o", output.string()}, logs()), quiet.string(), "no speech");
  EXPECT_FALSE(fs::exists(output));
  // On animate: a style that is not there fails before any work, and nothing is written.
  const fs::path animation = out() / "a.csv";
  expectOneLineFailure(
      runCli({"animate", prompt().string(), "-o", animation.string(), "--head-style", (out() / "gone.json").string()},
             logs()),
      (out() / "gone.json").string(), "no such file");
  EXPECT_FALSE(fs::exists(animation));
  expectOneLineFailure(runCli({"style", prompt().string(), "-o", (out() / "x.txt").string()}, logs()),
                       (out() / "x.txt").string(), ".json");
}

}  // namespace
