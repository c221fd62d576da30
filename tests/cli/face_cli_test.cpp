// The face commands as a user meets them: `render` writes one PNG per frame, `poses` a contact sheet, `export`
// an MP4 whose video lasts as long as its sound, with the animation files on request; bad input, bad sizes and
// interruptions fail in one line and leave no file.
#include <gtest/gtest.h>

extern "C" {
#include <libavformat/avformat.h>
}

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "audio_test_files.h"
#include "cli_runner.h"
#include "core/data_path.h"
#include "formats/animation_format.h"
#include "render/image.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

using FaceCliTest = th::test::CliTest;

struct Probe {
  int videoStreams = 0, audioStreams = 0;
  AVCodecID videoCodec = AV_CODEC_ID_NONE, audioCodec = AV_CODEC_ID_NONE;
  int width = 0, height = 0;
  double videoSeconds = 0.0, audioSeconds = 0.0;
};

Probe probe(const fs::path& path) {
  Probe result;
  AVFormatContext* format = nullptr;
  if (avformat_open_input(&format, path.c_str(), nullptr, nullptr) < 0) return result;
  avformat_find_stream_info(format, nullptr);
  for (unsigned i = 0; i < format->nb_streams; ++i) {
    const AVStream* stream = format->streams[i];
    const double seconds = static_cast<double>(stream->duration) * av_q2d(stream->time_base);
    if (stream->codecpar->codec_type == AVMEDIA_TYPE_VIDEO) {
      ++result.videoStreams;
      result.videoCodec = stream->codecpar->codec_id;
      result.width = stream->codecpar->width;
      result.height = stream->codecpar->height;
      result.videoSeconds = seconds;
    } else if (stream->codecpar->codec_type == AVMEDIA_TYPE_AUDIO) {
      ++result.audioStreams;
      result.audioCodec = stream->codecpar->codec_id;
      result.audioSeconds = seconds;
    }
  }
  avformat_close_input(&format);
  return result;
}

TEST_F(FaceCliTest, RenderWritesOnePngPerFrame) {
  th::face::FapTrack anim;
  anim.framesPerSecond = 25;
  anim.faps = {3, 49};
  anim.values = Eigen::MatrixXd::Zero(2, 10);
  for (int t = 0; t < 10; ++t) anim.values(0, t) = 60.0 * t, anim.values(1, t) = 1000.0 * t;
  th::formats::writeAnimation(out() / "a.csv", anim);
  const CliResult result =
      runCli({"render", (out() / "a.csv").string(), "-o", (out() / "frames").string(), "--size", "96x64"}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  int count = 0;
  for (const auto& entry : fs::directory_iterator(out() / "frames")) {
    const th::render::Image image = th::render::readPng(entry.path());
    EXPECT_EQ(image.width, 96);
    EXPECT_EQ(image.height, 64);
    ++count;
  }
  EXPECT_EQ(count, 10);
  // The face moves between the first and the last frame.
  EXPECT_FALSE(th::render::readPng(out() / "frames" / "frame_000000.png") ==
               th::render::readPng(out() / "frames" / "frame_000009.png"));
  expectOneLineFailure(runCli({"render", (out() / "missing.csv").string(), "-o", (out() / "f").string()}, logs()),
                       "missing.csv", "");
}

// A user's character instead of our face: in an export (its video as long as its sound) and in rendered frames,
// where it moves; a file that is not one fails in one line, before any output.
TEST_F(FaceCliTest, ExportAndRenderDrawTheUsersCharacter) {
  const fs::path character = th::sharedDataPath("face/avatars/brunette-t.glb");
  const fs::path input = th::test::readArcticPrompt().path;
  const fs::path video = out() / "character.mp4";
  CliResult result = runCli({"export", input.string(), "-o", video.string(), "--size", "160x120", "--fps", "25",
                             "--avatar", character.string(), "--save-anim", (out() / "c.json").string()},
                            logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.err.find("brunette-t: ARKit blendshapes"), std::string::npos) << result.err;
  const Probe p = probe(video);
  EXPECT_EQ(p.width, 160);
  EXPECT_NEAR(p.videoSeconds, p.audioSeconds, 1.0 / 25 + 1e-3);
  th::face::FapTrack anim;
  anim.framesPerSecond = 10;
  anim.faps = {3, 49};
  anim.values = Eigen::MatrixXd::Zero(2, 4);
  for (int t = 0; t < 4; ++t) anim.values(0, t) = 300.0 * t, anim.values(1, t) = 8000.0 * t;
  th::formats::writeAnimation(out() / "a.csv", anim);
  result = runCli({"render", (out() / "a.csv").string(), "-o", (out() / "frames").string(), "--size", "96x96",
                   "--avatar", character.string()},
                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_FALSE(th::render::readPng(out() / "frames" / "frame_000000.png") ==
               th::render::readPng(out() / "frames" / "frame_000003.png"))
      << "the jaw opens and the head turns";
  const fs::path text = out() / "me.glb";
  std::ofstream(text) << "not a character\n";
  expectOneLineFailure(
      runCli({"render", (out() / "a.csv").string(), "-o", (out() / "never").string(), "--avatar", text.string()},
             logs()),
      "me.glb", "not a glTF file");
  EXPECT_FALSE(fs::exists(out() / "never"));
  expectOneLineFailure(
      runCli({"export", input.string(), "-o", (out() / "never.mp4").string(), "--avatar", text.string()}, logs()),
      "me.glb", "not a glTF file");
  EXPECT_FALSE(fs::exists(out() / "never.mp4"));
}

TEST_F(FaceCliTest, PosesWritesAContactSheet) {
  const fs::path sheet = out() / "poses.png";
  const CliResult result = runCli({"poses", "-o", sheet.string(), "--tile", "96"}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const th::render::Image image = th::render::readPng(sheet);
  EXPECT_EQ(image.width, 3 * 96);
  EXPECT_EQ(image.height, 3 * 96);
}

TEST_F(FaceCliTest, ExportWritesAnMp4WhoseVideoLastsAsLongAsItsSound) {
  const fs::path input = th::test::readArcticPrompt().path;  // 24 kHz speech
  const fs::path video = out() / "speech.mp4";
  const CliResult result = runCli({"export", input.string(), "-o", video.string(), "--size", "160x120", "--fps", "25",
                                   "--save-anim", (out() / "speech.fap").string(), "--save-anim",
                                   (out() / "speech.json").string(), "--arkit", (out() / "arkit.csv").string()},
                                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const Probe p = probe(video);
  EXPECT_EQ(p.videoStreams, 1);
  EXPECT_EQ(p.audioStreams, 1);
  EXPECT_EQ(p.videoCodec, AV_CODEC_ID_H264);
  EXPECT_EQ(p.audioCodec, AV_CODEC_ID_AAC);
  EXPECT_EQ(p.width, 160);
  EXPECT_EQ(p.height, 120);
  EXPECT_GT(p.audioSeconds, 1.0);
  EXPECT_NEAR(p.videoSeconds, p.audioSeconds, 1.0 / 25 + 1e-3);
  EXPECT_EQ(th::formats::readAnimation(out() / "speech.fap").faps,
            th::formats::readAnimation(out() / "speech.json").faps);
  std::ifstream arkit(out() / "arkit.csv");
  std::string header;
  std::getline(arkit, header);
  EXPECT_EQ(header.rfind("time_s,eyeBlinkLeft,", 0), 0u);
  for (const auto& entry : fs::directory_iterator(out()))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();
}

// An export of a minute of speech blinks at a human rate (the saved animation's lids), deterministically for a
// seed; an animation played with --anim that has no lids gets them, and --no-idle leaves them out.
TEST_F(FaceCliTest, ExportsBlinkAtAHumanRate) {
  const std::string speech = th::sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav").string();
  const fs::path saved = out() / "minute.csv";
  ASSERT_EQ(runCli({"export", speech, "-o", (out() / "minute.mp4").string(), "--size", "64x48", "--fps", "5",
                    "--save-anim", saved.string()},
                   logs())
                .exitCode,
            0);
  const th::face::FapTrack animation = th::formats::readAnimation(saved);
  ASSERT_GE(animation.rowOf(19), 0);
  const Eigen::RowVectorXd lid = animation.values.row(animation.rowOf(19));
  int blinks = 0;
  for (Eigen::Index t = 1; t < lid.size(); ++t) blinks += lid[t] > 512.0 && lid[t - 1] <= 512.0;
  const double perMinute = blinks / (animation.numFrames() / animation.framesPerSecond / 60.0);
  std::printf("[ INFO     ] %d blinks in %.1f s: %.1f a minute\n", blinks,
              animation.numFrames() / animation.framesPerSecond, perMinute);
  EXPECT_GE(perMinute, 8.0);
  EXPECT_LE(perMinute, 30.0);

  // The lids of a played animation: a prompt of a few seconds is enough to see whether they are there.
  const std::string prompt = th::test::readArcticPrompt().path.string();
  const fs::path lidless = out() / "lidless.csv";
  ASSERT_EQ(runCli({"animate", prompt, "-o", lidless.string(), "--no-idle"}, logs()).exitCode, 0);
  EXPECT_EQ(th::formats::readAnimation(lidless).rowOf(19), -1);
  const fs::path replayed = out() / "replayed.csv";
  ASSERT_EQ(runCli({"export", prompt, "-o", (out() / "replayed.mp4").string(), "--size", "64x48", "--fps", "5",
                    "--anim", lidless.string(), "--save-anim", replayed.string()},
                   logs())
                .exitCode,
            0);
  EXPECT_GE(th::formats::readAnimation(replayed).rowOf(19), 0) << "blinks added to a file without lids";
  const fs::path still = out() / "still.csv";
  ASSERT_EQ(runCli({"export", prompt, "-o", (out() / "still.mp4").string(), "--size", "64x48", "--fps", "5", "--anim",
                    lidless.string(), "--save-anim", still.string(), "--no-idle"},
                   logs())
                .exitCode,
            0);
  EXPECT_EQ(th::formats::readAnimation(still).rowOf(19), -1);
}

TEST_F(FaceCliTest, ExportRefusesBadInputAndBadSizesInOneLine) {
  const fs::path input = th::test::readArcticPrompt().path;
  const std::string video = (out() / "v.mp4").string();
  const fs::path text = folder_.path() / "text.wav";
  std::ofstream(text) << "not audio";
  expectOneLineFailure(runCli({"export", text.string(), "-o", video}, logs()), "text.wav", "not a readable audio file");
  expectOneLineFailure(runCli({"export", input.string(), "-o", video, "--size", "big"}, logs()), "--size big",
                       "WIDTHxHEIGHT");
  expectOneLineFailure(runCli({"export", input.string(), "-o", video, "--size", "161x120"}, logs()), "161x120", "even");
  expectOneLineFailure(runCli({"export", input.string(), "-o", (out() / "v.avi").string()}, logs()), "v.avi", ".mp4");
  expectOneLineFailure(runCli({"export", input.string(), "-o", (out() / "no" / "v.mp4").string()}, logs()), "v.mp4",
                       "folder does not exist");
  const fs::path empty = folder_.path() / "empty.csv";
  std::ofstream(empty) << "";
  expectOneLineFailure(runCli({"export", input.string(), "-o", video, "--anim", empty.string()}, logs()), "empty.csv",
                       "");
  EXPECT_TRUE(fs::is_empty(out()));
}

TEST_F(FaceCliTest, AnInterruptedExportLeavesNoFile) {
  const fs::path input = th::sharedDataPath("beat2/2_scott_0_1_1.wav");  // 64 s: far longer than the wait
  // Ctrl-C 6 s in: the models and the face are loaded by then and the encoder is running (the temporary file
  // is unnamed, so there is nothing to watch for); a minute of 640x480 video takes far longer than 6 s.
  const auto start = std::chrono::steady_clock::now();
  const auto later = [&] { return std::chrono::steady_clock::now() - start > std::chrono::seconds(6); };
  const CliResult result = th::test::runCliInterrupted(
      {"export", input.string(), "-o", (out() / "long.mp4").string(), "--size", "640x480"}, logs(), later);
  expectOneLineFailure(result, "interrupted", "no output");
  EXPECT_TRUE(fs::is_empty(out())) << "a partial export was left behind";
}

// The viewer under a virtual X server (xvfb-run, from the xvfb package): it opens, draws the face and the panel,
// and quits after the screenshot.
TEST_F(FaceCliTest, ShowDrawsTheFaceAndItsPanelInAWindow) {
  const fs::path shot = out() / "show.png";
  // In sanitizer builds leak checking is off for this one process: Mesa's GLX driver is unloaded at exit, so
  // its per-display records show up as leaks from an "<unknown module>" that no suppression can name. Memory
  // errors are still caught.
  const std::string command = "ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1280x800x24' " +
                              std::string(TALKINGHEAD_CLI) + " show --screenshot " + shot.string() + " --frames 3 > " +
                              (logs() / "show.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << th::test::readText(logs() / "show.txt");
  const th::render::Image image = th::render::readPng(shot);
  ASSERT_EQ(image.width, 1280);
  ASSERT_EQ(image.height, 720);
  // The panel (left) is ImGui's dark grey-blue; the face (centre right) is skin: red above green above blue.
  int panel = 0, skin = 0;
  for (int y = 100; y < 600; y += 4) {
    const std::uint8_t* p = image.pixel(200, y);
    panel += (p[0] < 60 && p[2] > p[0] && p[2] < 120) ? 1 : 0;
    const std::uint8_t* q = image.pixel(760, y);
    skin += (q[0] > 150 && q[0] > q[1] && q[1] > q[2]) ? 1 : 0;
  }
  EXPECT_GT(panel, 25);
  EXPECT_GT(skin, 60);
}

// The viewer with --avatar: the character, playing an animation, beside the panel that names it.
TEST_F(FaceCliTest, ShowDrawsTheUsersCharacterInAWindow) {
  const fs::path character = th::sharedDataPath("face/avatars/vroid.glb");
  th::face::FapTrack anim;
  anim.framesPerSecond = 10;
  anim.faps = {3};
  anim.values = Eigen::MatrixXd::Constant(1, 20, 400.0);
  th::formats::writeAnimation(out() / "open.csv", anim);
  const fs::path shot = out() / "show_character.png";
  const std::string command = "ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1280x800x24' " +
                              std::string(TALKINGHEAD_CLI) + " show --avatar " + character.string() + " --anim " +
                              (out() / "open.csv").string() + " --screenshot " + shot.string() + " --frames 3 > " +
                              (logs() / "show_character.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << th::test::readText(logs() / "show_character.txt");
  EXPECT_NE(th::test::readText(logs() / "show_character.txt").find("vroid: Oculus visemes"), std::string::npos);
  const th::render::Image image = th::render::readPng(shot);
  ASSERT_EQ(image.width, 1280);
  // Its pale skin and white hair right of the panel.
  int skin = 0, white = 0;
  for (int y = 0; y < 720; y += 4)
    for (int x = 560; x < 1100; x += 4) {
      const std::uint8_t* q = image.pixel(x, y);
      skin += (q[0] > 180 && q[0] > q[1] + 10 && q[1] > q[2]) ? 1 : 0;
      white += (q[0] > 225 && q[1] > 225 && q[2] > 225) ? 1 : 0;
    }
  EXPECT_GT(skin, 800);
  EXPECT_GT(white, 800);
}

// sidebyside --avatar: the film strip's lower row is the character's mouth, and it moves with the clip's sound.
TEST_F(FaceCliTest, SideBySideDrawsTheUsersCharacter) {
  const fs::path character = th::sharedDataPath("face/avatars/brunette-t.glb");
  const fs::path clip = th::sharedDataPath("grid/samples/id2_vcd_swwp2s.mpg");
  const fs::path strip = out() / "strip.png";
  const CliResult result = runCli({"sidebyside", clip.string(), "-o", strip.string(), "--from", "0.8", "--seconds",
                                   "1.2", "--every", "3", "--height", "96", "--avatar", character.string()},
                                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const th::render::Image image = th::render::readPng(strip);
  const int tile = 96;  // --height 96: square tiles, the clip's mouth above the character's
  ASSERT_EQ(image.width, 10 * tile);
  // Each tile's lower half is the character's lips: red lips (R well above G) in every one, and not the same
  // picture twice in a row throughout.
  int changed = 0;
  for (int i = 0; i < 10; ++i) {
    int red = 0;
    long difference = 0;
    for (int y = tile; y < 2 * tile; ++y)
      for (int x = 0; x < tile; ++x) {
        const std::uint8_t* p = image.pixel(i * tile + x, y);
        red += (p[0] > 140 && p[0] > p[1] + 50) ? 1 : 0;
        if (i > 0) difference += std::abs(p[0] - image.pixel((i - 1) * tile + x, y)[0]);
      }
    EXPECT_GT(red, 30) << "tile " << i;
    changed += difference > tile * tile * 2L ? 1 : 0;
  }
  EXPECT_GE(changed, 5) << "the mouth moves from tile to tile";
}

}  // namespace
