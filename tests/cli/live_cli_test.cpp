// `talkinghead live` as a user meets it: --headless, a recording played through the live pipeline's threads,
// at real-time pace or at full speed, gives the same frames (tests/pipeline holds the decoder to `animate`);
// bad input fails in one line and leaves no dump behind; the window draws the face and its panel under Xvfb
// and keeps its settings, or draws the user's character instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli_runner.h"
#include "core/data_path.h"
#include "formats/animation_format.h"
#include "render/image.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

class LiveCliTest : public th::test::CliTest {
 protected:
  static fs::path speech() { return th::sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"); }
};

TEST_F(LiveCliTest, HeadlessGivesTheOnlineAnimationThroughTheThreads) {
  const fs::path live = out() / "live.csv";
  // 8 s at 4x real time: the display loop runs at its own pace while the file plays.
  CliResult result = runCli(
      {"live", "--headless", "--input", speech().string(), "--duration", "8", "--speed", "4", "--dump", live.string()},
      logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("240 decoded, 240 shown, 0 dropped"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("0 overrun"), std::string::npos) << result.out;
  // The same 8 s as fast as the worker decodes.
  ASSERT_EQ(runCli({"live", "--headless", "--input", speech().string(), "--duration", "8", "--speed", "0", "--dump",
                    (out() / "fast.csv").string()},
                   logs())
                .exitCode,
            0);
  const th::face::FapTrack a = th::formats::readAnimation(live);
  const th::face::FapTrack b = th::formats::readAnimation(out() / "fast.csv");
  ASSERT_EQ(a.faps, b.faps);
  ASSERT_EQ(a.numFrames(), 240);
  ASSERT_EQ(b.numFrames(), 240);
  // Real-time pace or as fast as possible: the same frames (the decoder does not depend on timing).
  EXPECT_EQ((a.values - b.values).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GE(a.rowOf(3), 0);
  EXPECT_GT(a.values.row(a.rowOf(3)).maxCoeff(), 0.0);  // the jaw moves
}

// What a file of the speech has, live shows: `animate --online` and `live --headless` on the same recording
// give the same blinks and gaze shifts, and the same head, shown as many frames late as live reports (the
// mouth does not wait for it); without the idle behaviour's rests in pauses, exactly.
TEST_F(LiveCliTest, TheHeadBlinksAndGazeAreTheFilesShownTheHeadsLookAheadLate) {
  const auto run = [&](const std::vector<std::string>& idle, const std::string& tag) {
    const fs::path file = out() / (tag + "_file.csv"), live = out() / (tag + "_live.csv");
    std::vector<std::string> animate = {"animate", speech().string(), "-o", file.string(), "--online"};
    std::vector<std::string> headless = {"live", "--headless", "--input", speech().string(), "--duration",
                                         "12",   "--speed",    "0",       "--dump",          live.string()};
    animate.insert(animate.end(), idle.begin(), idle.end());
    headless.insert(headless.end(), idle.begin(), idle.end());
    EXPECT_EQ(runCli(animate, logs()).exitCode, 0);
    const CliResult result = runCli(headless, logs());
    EXPECT_EQ(result.exitCode, 0) << result.err;
    const std::string marker = "the head shown ";
    const std::size_t at = result.out.find(marker);
    EXPECT_NE(at, std::string::npos) << result.out;
    const int late = at == std::string::npos ? 0 : std::stoi(result.out.substr(at + marker.size()));
    return std::make_tuple(th::formats::readAnimation(file), th::formats::readAnimation(live), late);
  };
  {
    const auto [file, live, late] = run({"--no-idle"}, "still");
    ASSERT_GT(late, 0);
    ASSERT_EQ(live.numFrames(), 360);
    double largest = 0.0, moved = 0.0;
    for (const int fap : {48, 49, 50}) {
      ASSERT_GE(file.rowOf(fap), 0);
      ASSERT_GE(live.rowOf(fap), 0);
      for (Eigen::Index t = late; t < live.numFrames(); ++t) {
        largest = std::max(largest, std::abs(live.values(live.rowOf(fap), t) - file.values(file.rowOf(fap), t - late)));
        moved = std::max(moved, std::abs(file.values(file.rowOf(fap), t - late)));
      }
    }
    EXPECT_LT(largest, 1e-3) << "FAP units";
    EXPECT_GT(moved, 1000.0) << "the head moves";
  }
  const auto [file, live, late] = run({}, "idle");
  for (const int fap : {19, 20, 23, 24, 25, 26}) {
    ASSERT_GE(file.rowOf(fap), 0) << fap;
    ASSERT_GE(live.rowOf(fap), 0) << fap << ": the dump has what the display showed";
    EXPECT_EQ(live.values.row(live.rowOf(fap)), file.values.row(file.rowOf(fap)).head(live.numFrames())) << fap;
  }
  EXPECT_GT(file.values.row(file.rowOf(19)).maxCoeff(), 0.0) << "it blinks";
  for (const int fap : {48, 49, 50}) {
    const Eigen::RowVectorXd a = live.values.row(live.rowOf(fap)).segment(late, live.numFrames() - late);
    const Eigen::RowVectorXd b = file.values.row(file.rowOf(fap)).head(live.numFrames() - late);
    const Eigen::RowVectorXd ca = a.array() - a.mean(), cb = b.array() - b.mean();
    EXPECT_GT(ca.dot(cb) / std::sqrt(ca.squaredNorm() * cb.squaredNorm()), 0.95) << fap;
  }
}

// CPU overload: three busy loops on the two cores while 6 s of speech plays at real-time pace. No sample is
// lost (the counters say 0 overrun, every sample in) and every frame is decoded; frames the display could not
// take would be dropped and counted, never samples.
TEST_F(LiveCliTest, UnderCpuOverloadNoSampleIsLost) {
  for (int i = 0; i < 3; ++i) ASSERT_EQ(std::system("timeout 9 sh -c 'while :; do :; done' > /dev/null 2>&1 &"), 0);
  const CliResult result =
      runCli({"live", "--headless", "--input", speech().string(), "--duration", "6", "--speed", "1"}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  std::printf("%s", result.out.c_str());
  EXPECT_NE(result.out.find("180 decoded"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("samples: 96000 in, 0 overrun"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("dropped"), std::string::npos) << "the counter is shown";
}

TEST_F(LiveCliTest, BadInputFailsInOneLineAndLeavesNoDump) {
  const fs::path dump = out() / "dump.csv";
  expectOneLineFailure(
      runCli({"live", "--headless", "--input", (out() / "missing.wav").string(), "--dump", dump.string()}, logs()),
      "missing.wav", "no such file");
  EXPECT_FALSE(fs::exists(dump));
  const fs::path text = out() / "text.wav";
  std::ofstream(text) << "not audio at all";
  const CliResult notAudio = runCli({"live", "--headless", "--input", text.string(), "--dump", dump.string()}, logs());
  EXPECT_NE(notAudio.exitCode, 0);
  EXPECT_FALSE(fs::exists(dump));
  expectOneLineFailure(
      runCli({"live", "--headless", "--input", speech().string(), "--dump", (out() / "x.txt").string()}, logs()),
      "x.txt", "");
  expectOneLineFailure(runCli({"live", "--headless"}, logs()), "--input", "");
  expectOneLineFailure(runCli({"live", "--headless", "--input", speech().string(), "--device", "default"}, logs()),
                       "not both", "");
  expectOneLineFailure(runCli({"live", "--input", speech().string(), "--max-fps", "-5"}, logs()), "--max-fps", "");
  const fs::path settings = out() / "settings.json";
  std::ofstream(settings) << "{ not json";
  expectOneLineFailure(runCli({"live", "--input", speech().string(), "--settings", settings.string()}, logs()),
                       "settings.json", "not valid JSON");
  std::ofstream(settings) << R"({"window": 0})";
  expectOneLineFailure(runCli({"live", "--input", speech().string(), "--settings", settings.string()}, logs()),
                       "settings.json", "window");
  std::ofstream(settings) << R"({"head_variation": 9})";
  expectOneLineFailure(runCli({"live", "--input", speech().string(), "--settings", settings.string()}, logs()),
                       "settings.json", "head_variation");
}

// The window under a virtual X server (xvfb-run): the face and the panel are drawn while a recording plays
// through the pipeline, the window quits cleanly after the screenshot, and the settings it was given are saved
// and come back the next time.
TEST_F(LiveCliTest, TheWindowDrawsTheFaceAndThePanelAndKeepsItsSettings) {
  const fs::path shot = out() / "live.png";
  const fs::path settings = out() / "live.json";
  // Leak checking off for this process in sanitizer builds, as for `show` (Mesa's GLX driver, unloaded at exit).
  const std::string prefix =
      "ASAN_OPTIONS=detect_leaks=0 timeout 120 xvfb-run -a -s '-screen 0 1280x800x24' " + std::string(TALKINGHEAD_CLI);
  const std::string first = prefix + " live --input " + speech().string() + " --settings " + settings.string() +
                            " --screenshot " + shot.string() + " --frames 300 --window 3 --head paper" +
                            " --head-amplitude 1.5 --head-smoothing 2 --no-idle --seed 4 > " +
                            (logs() / "window.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(first.c_str()), 0) << th::test::readText(logs() / "window.txt");
  const std::string log = th::test::readText(logs() / "window.txt");
  EXPECT_NE(log.find("head paper"), std::string::npos) << log;
  EXPECT_NE(log.find("window 3"), std::string::npos) << log;
  // Whether the back buffer keeps the panel's column between frames was checked (Mesa's software path under X
  // keeps it: the column is then drawn only when it changes, and the screenshot still shows it, below).
  EXPECT_NE(log.find("the window's back buffer keeps its pixels between frames"), std::string::npos) << log;
  const th::render::Image image = th::render::readPng(shot);
  ASSERT_EQ(image.width, 1280);
  ASSERT_EQ(image.height, 720);
  // The panel (left) is ImGui's dark grey-blue; the face (centre right) is skin: red above green above blue.
  int panel = 0, skin = 0, plotted = 0;
  for (int y = 100; y < 700; y += 4) {
    const std::uint8_t* p = image.pixel(200, y);
    panel += (p[0] < 60 && p[2] > p[0] && p[2] < 120) ? 1 : 0;
    const std::uint8_t* q = image.pixel(760, y);
    skin += (q[0] > 150 && q[0] > q[1] && q[1] > q[2]) ? 1 : 0;
  }
  // The waveform plot's bars are ImGui's yellow-orange: sound reached the panel.
  for (int y = 0; y < 720; ++y)
    for (int x = 20; x < 420; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      plotted += (p[0] > 200 && p[1] > 120 && p[2] < 60) ? 1 : 0;
    }
  EXPECT_GT(panel, 25);
  EXPECT_GT(skin, 60);
  EXPECT_GT(plotted, 200);
  ASSERT_TRUE(fs::exists(settings));
  const std::string saved = th::test::readText(settings);
  // Typed under its former name (--window), saved under its name now.
  for (const std::string expected :
       {"\"window_frames\": 3", "\"head_amplitude\": 1.5", "\"head_smoothing\": 2.0", "\"idle\": false", "\"seed\": 4"})
    EXPECT_NE(saved.find(expected), std::string::npos) << expected << " in " << saved;
  // The next time, without the options: the saved settings. (And without the loop's cap: frames as fast as
  // they can be drawn.)
  const std::string second = prefix + " live --input " + speech().string() + " --settings " + settings.string() +
                             " --screenshot " + (out() / "again.png").string() + " --frames 3 --max-fps 0 > " +
                             (logs() / "again.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(second.c_str()), 0) << th::test::readText(logs() / "again.txt");
  const std::string again = th::test::readText(logs() / "again.txt");
  EXPECT_NE(again.find("head paper"), std::string::npos) << again;
  EXPECT_NE(again.find("window 3"), std::string::npos) << again;
}

// --avatar: the user's character in the window instead of our face, beside the same panel; --headless, which
// draws nothing, refuses it in one line.
TEST_F(LiveCliTest, TheWindowDrawsTheUsersCharacter) {
  const fs::path character = th::sharedDataPath("face/avatars/brunette-t.glb");
  const fs::path shot = out() / "character.png";
  const std::string command = "ASAN_OPTIONS=detect_leaks=0 timeout 120 xvfb-run -a -s '-screen 0 1280x800x24' " +
                              std::string(TALKINGHEAD_CLI) + " live --input " + speech().string() +
                              " --no-settings --avatar " + character.string() + " --screenshot " + shot.string() +
                              " --frames 20 > " + (logs() / "character.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << th::test::readText(logs() / "character.txt");
  const std::string log = th::test::readText(logs() / "character.txt");
  EXPECT_NE(log.find("brunette-t: ARKit blendshapes"), std::string::npos) << log;
  const th::render::Image image = th::render::readPng(shot);
  ASSERT_EQ(image.width, 1280);
  ASSERT_EQ(image.height, 720);
  // The panel on the left; the character's face in the middle of the rest: skin, red above green above blue
  // (the backdrop is blue-grey), below its dark hair.
  int panel = 0, skin = 0, dark = 0;
  for (int y = 100; y < 700; y += 4) {
    const std::uint8_t* p = image.pixel(200, y);
    panel += (p[0] < 60 && p[2] > p[0] && p[2] < 120) ? 1 : 0;
  }
  for (int y = 0; y < 720; y += 4)
    for (int x = 700; x < 1060; x += 4) {
      const std::uint8_t* q = image.pixel(x, y);
      skin += (q[0] > 150 && q[0] > q[1] + 20 && q[1] > q[2]) ? 1 : 0;
      dark += (q[0] < 50 && q[1] < 50 && q[2] < 50) ? 1 : 0;
    }
  EXPECT_GT(panel, 25);
  EXPECT_GT(skin, 800) << "the face fills the middle of the frame";
  EXPECT_GT(dark, 400) << "its hair";
  expectOneLineFailure(
      runCli({"live", "--headless", "--input", speech().string(), "--avatar", character.string()}, logs()), "--avatar",
      "--headless");
}

}  // namespace
