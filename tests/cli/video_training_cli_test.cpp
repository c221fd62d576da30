// Training from video as a user meets it: `train --video DIR` tracks the clips (keeping the tracks), trains a
// mouth model, reports it on held-out clips, and writes a model that animate, live and sidebyside load;
// `sidebyside` writes the clip beside our face (or a film strip of both mouths); `train mouth` makes the shipped
// kind of model from a folder and `strip` draws a stretch of its animation; `record` says clearly when there is
// no camera or microphone.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "audio/media_audio.h"
#include "cli_runner.h"
#include "core/data_path.h"
#include "formats/animation_format.h"
#include "render/image.h"
#include "tracking/video_reader.h"
#include "tracking/video_training.h"
#include "tracking_test_support.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

class VideoTrainingCliTest : public th::test::CliTest {
 protected:
  // Four GRID clips and a video without a face, in a folder of their own.
  fs::path clipFolder() {
    const fs::path folder = folder_.path() / "clips";
    fs::create_directories(folder);
    const std::vector<fs::path> grid = th::tracking::listVideos(th::sharedDataPath("grid/s1"));
    for (std::size_t i = 0; i < 4; ++i) fs::create_symlink(grid[i], folder / grid[i].filename());
    th::test::writeFacelessVideo(folder / "zz_faceless.mp4");
    return folder;
  }
};

TEST_F(VideoTrainingCliTest, TrainsAModelThatTheOtherCommandsPlay) {
  const fs::path clips = clipFolder();
  const fs::path model = out() / "speaker.json";
  const std::vector<std::string> train{
      "train",      "--video", clips.string(), "-o", model.string(), "--hold-out", "2", "--states", "3",
      "--mixtures", "1",       "--components", "2",  "--threads",    "2"};
  CliResult result = runCli(train, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("4 clips from"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("4 tracked now"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("left out: " + (clips / "zz_faceless.mp4").string() + ": no face"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("trained on 2 clips"), std::string::npos) << result.out;
  for (const char* row : {"this model, inversion", "this model, MMSE", "--compare mouth.json",
                          "baseline: the training mean", "baseline: this model on the next held-out clip's audio"})
    EXPECT_NE(result.out.find(row), std::string::npos) << row << '\n' << result.out;
  // The tracks are kept beside the model and read back the next time.
  std::size_t tracks = 0;
  for (const auto& entry : fs::directory_iterator(out() / "speaker_tracks"))
    tracks += entry.path().extension() == ".csv";
  EXPECT_EQ(tracks, 4u);
  EXPECT_TRUE(fs::exists(out() / "speaker_tracks" / "tracker.txt"));  // how they were made
  fs::remove(model);
  result = runCli(train, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("0 tracked now, 4 read from"), std::string::npos) << result.out;

  // animate and live play it: the jaw and the 20 lip FAPs it learnt.
  const std::string speech = th::sharedDataPath("beat2/2_scott_0_1_1.wav").string();
  const fs::path csv = out() / "a.csv";
  ASSERT_EQ(
      runCli({"animate", speech, "-o", csv.string(), "--mouth-model", model.string(), "--head", "none", "--no-idle"},
             logs())
          .exitCode,
      0);
  const th::face::FapTrack animation = th::formats::readAnimation(csv);
  EXPECT_EQ(animation.faps.size(), 21u);
  EXPECT_GT(animation.values.row(0).maxCoeff(), animation.values.row(0).minCoeff());  // FAP 3 moves
  const fs::path dump = out() / "live.csv";
  result = runCli({"live", "--headless", "--input", speech, "--duration", "3", "--speed", "0", "--mouth-model",
                   model.string(), "--dump", dump.string()},
                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_EQ(th::formats::readAnimation(dump).numFrames(), 90);

  // sidebyside: the clip's picture beside the face, its sound, as long as the clip.
  const fs::path video = out() / "side.mp4";
  const fs::path clip = th::tracking::listVideos(clips).front();
  result = runCli({"sidebyside", clip.string(), "-o", video.string(), "--mouth-model", model.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  th::tracking::VideoReader reader(video);
  EXPECT_EQ(reader.width(), 720);  // two 360x288 halves
  EXPECT_EQ(reader.height(), 288);
  EXPECT_NEAR(reader.framesPerSecond(), 25.0, 1e-6);
  EXPECT_NEAR(th::audio::readMediaAudio(video).durationSeconds(), 3.0, 0.1);
}

TEST_F(VideoTrainingCliTest, TrainMouthOnAFolderThenFilmStripsOfItsMouth) {
  // `train mouth` as the shipped models are made, on a folder of one's own (the shipped ones: the shared corpora).
  const fs::path clips = clipFolder();
  const fs::path model = out() / "mouth.json";
  CliResult result =
      runCli({"train", "mouth", "--corpus", clips.string() + "=me", "--tracks", (folder_.path() / "tracks").string(),
              "--states", "3", "--mixtures", "1", "--components", "2", "-o", model.string()},
             logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.err.find("trained on 4 clips"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("normalised speech"), std::string::npos) << result.err;
  // animate plays it; strip draws a stretch of it; sidebyside draws a clip's mouth above ours.
  const fs::path csv = out() / "a.csv";
  ASSERT_EQ(runCli({"animate", th::sharedDataPath("beat2/2_scott_0_1_1.wav").string(), "-o", csv.string(),
                    "--mouth-model", model.string(), "--head", "none"},
                   logs())
                .exitCode,
            0);
  const fs::path strip = out() / "strip.png";
  result =
      runCli({"strip", csv.string(), "-o", strip.string(), "--from", "1", "--seconds", "1", "--every", "3", "--columns",
              "5", "--tile", "96", "--phones", th::sharedDataPath("beat2/2_scott_0_1_1.TextGrid").string()},
             logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const th::render::Image sheet = th::render::readPng(strip);
  EXPECT_EQ(sheet.width, 5 * 96) << "ten frames, five a row";
  EXPECT_EQ(sheet.height, 2 * (96 + 22));
  const fs::path pairs = out() / "pairs.png";
  const fs::path clip = th::tracking::listVideos(clips).front();
  result = runCli({"sidebyside", clip.string(), "-o", pairs.string(), "--mouth-model", model.string(), "--from", "0.5",
                   "--seconds", "0.8", "--every", "2", "--height", "64"},
                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const th::render::Image side = th::render::readPng(pairs);
  EXPECT_EQ(side.width, 10 * 64) << "0.8 s of 25 fps, every second frame";
  EXPECT_EQ(side.height, 2 * 64 + 20);
  expectOneLineFailure(runCli({"strip", csv.string(), "-o", (out() / "s.png").string(), "--from", "100"}, logs()),
                       "a.csv", "ends before the strip does");
  expectOneLineFailure(runCli({"strip", csv.string(), "-o", (out() / "s.jpg").string()}, logs()), "s.jpg", ".png");
}

TEST_F(VideoTrainingCliTest, BadInputFailsInOneLineAndLeavesNothing) {
  const std::string model = (out() / "m.json").string();
  expectOneLineFailure(runCli({"train", "--video", (out() / "missing").string(), "-o", model}, logs()), "missing",
                       "is not a folder");
  expectOneLineFailure(runCli({"train", "--video", out().string(), "-o", model}, logs()), out().string(),
                       "holds no videos");
  const CliResult noOutput = runCli({"train", "--video", out().string()}, logs());
  EXPECT_NE(noOutput.exitCode, 0);
  EXPECT_NE(noOutput.err.find("-o MODEL.json"), std::string::npos) << noOutput.err;
  expectOneLineFailure(runCli({"train", "--video", out().string(), "-o", (out() / "m.txt").string()}, logs()), "m.txt",
                       "give a .json name");
  // A folder whose only video has no face.
  const fs::path faceless = folder_.path() / "faceless";
  fs::create_directories(faceless);
  th::test::writeFacelessVideo(faceless / "a.mp4");
  const CliResult noFace = runCli({"train", "--video", faceless.string(), "-o", model}, logs());
  EXPECT_NE(noFace.exitCode, 0);
  EXPECT_NE(noFace.err.find("no clip could be used"), std::string::npos) << noFace.err;
  EXPECT_NE(noFace.err.find("no face"), std::string::npos) << noFace.err;
  EXPECT_FALSE(fs::exists(model));
  expectOneLineFailure(runCli({"sidebyside", (faceless / "b.mp4").string(), "-o", (out() / "s.mp4").string()}, logs()),
                       "b.mp4", "no such file");
  expectOneLineFailure(runCli({"sidebyside", (faceless / "a.mp4").string(), "-o", (out() / "s.avi").string()}, logs()),
                       "s.avi", ".mp4");
  EXPECT_TRUE(outFolderIsEmpty());
}

TEST_F(VideoTrainingCliTest, RecordSaysWhenThereIsNoCamera) {
  // CI machines have no camera (and this test does not ask for one): one line, nothing written.
  const CliResult result = runCli({"record", out().string(), "--camera", "63", "--duration", "1"}, logs());
  EXPECT_TRUE(result.exited);
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << result.err;
  EXPECT_NE(result.err.find("record: no camera (/dev/video63 cannot be opened"), std::string::npos) << result.err;
  EXPECT_TRUE(outFolderIsEmpty());
  expectOneLineFailure(runCli({"record", (out() / "missing").string()}, logs()), "missing", "is not a folder");
}

}  // namespace
