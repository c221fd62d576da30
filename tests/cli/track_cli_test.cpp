// `talkinghead track` as a user meets it: a GRID clip gives a landmark track (smoothed, or as dlib gave it) and its
// sound (its own, or a silent video's WAV beside it); a video without a face, without sound, or not a video at all
// fails in one line and leaves nothing behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "cli_runner.h"
#include "core/data_path.h"
#include "core/numeric_csv.h"
#include "tracking_test_support.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

class TrackCliTest : public th::test::CliTest {
 protected:
  static fs::path clip() { return th::sharedDataPath("grid/s1/bbal7s.mpg"); }
};

TEST_F(TrackCliTest, AGridClipGivesItsLandmarksAndItsSound) {
  const fs::path track = out() / "bbal7s.csv";
  const CliResult result = runCli({"track", clip().string(), "-o", track.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("75 frames at 25 fps, the face found in 75"), std::string::npos) << result.out;
  const th::NumericTable table = th::readNumericCsv(track);
  ASSERT_EQ(table.rows.size(), 75u);
  // time, face; the head's three angles, the jaw and 20 lip FAPs, the residual; the 68 landmarks.
  EXPECT_EQ(table.columns.size(), 2u + 3u + 21u + 1u + 2u * 68u);
  EXPECT_NEAR(table.rows[74][static_cast<std::size_t>(table.column("time_s"))], 74 / 25.0, 1e-6);
  double residual = 0.0, widest = 0.0;
  for (const std::vector<double>& row : table.rows) {
    residual += row[static_cast<std::size_t>(table.column("residual_px"))] / 75.0;
    widest = std::max(widest, row[static_cast<std::size_t>(table.column("fap3"))]);
  }
  EXPECT_LT(residual, 3.0);
  EXPECT_GT(widest, 50.0);  // the jaw opens (MNS) as he speaks
  // The sound beside it: the clip's 3 s.
  const th::audio::AudioClip sound = th::audio::readAudioFile(out() / "bbal7s.wav");
  EXPECT_NEAR(static_cast<double>(sound.samples.size()) / sound.sampleRateHz, 3.0, 0.05);
  // --audio puts it elsewhere; --no-smooth writes dlib's landmarks as each frame gave them, which jitter more
  // from frame to frame than the smoothed ones (the sum of the second differences of every landmark's path).
  ASSERT_EQ(runCli({"track", clip().string(), "-o", (out() / "b.csv").string(), "--audio",
                    (out() / "sound.wav").string(), "--no-smooth"},
                   logs())
                .exitCode,
            0);
  EXPECT_TRUE(fs::exists(out() / "sound.wav"));
  EXPECT_FALSE(fs::exists(out() / "b.wav"));
  const auto jitter = [](const th::NumericTable& landmarks) {
    double sum = 0.0;
    for (int point = 0; point < 68; ++point)
      for (const char* axis : {"x", "y"}) {
        const auto column = static_cast<std::size_t>(landmarks.column(axis + std::to_string(point)));
        for (std::size_t f = 1; f + 1 < landmarks.rows.size(); ++f)
          sum +=
              std::abs(landmarks.rows[f + 1][column] - 2 * landmarks.rows[f][column] + landmarks.rows[f - 1][column]);
      }
    return sum;
  };
  const th::NumericTable raw = th::readNumericCsv(out() / "b.csv");
  ASSERT_EQ(raw.rows.size(), 75u);
  EXPECT_GT(jitter(raw), 1.5 * jitter(table));
}

TEST_F(TrackCliTest, ASilentVideoTakesTheWavOfItsNameBesideIt) {
  // A corpus that ships its sound apart from the picture (StyleTalk's clips): NAME.mp4 without a sound track and
  // NAME.wav beside it.
  const fs::path folder = folder_.path() / "clips";
  fs::create_directories(folder);
  const fs::path silent = folder / "speaker.avi";
  th::test::writeSoundlessCopy(clip(), silent);
  const th::audio::AudioClip original = th::audio::readMediaAudio(clip());
  th::audio::writeWav16(folder / "speaker.wav", original.samples, original.sampleRateHz);
  const CliResult result = runCli({"track", silent.string(), "-o", (out() / "speaker.csv").string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const th::audio::AudioClip sound = th::audio::readAudioFile(out() / "speaker.wav");
  ASSERT_EQ(sound.samples.size(), original.samples.size());
  EXPECT_TRUE(std::equal(sound.samples.begin(), sound.samples.end(), original.samples.begin(),
                         [](float a, float b) { return std::abs(a - b) < 1e-3F; }));
  // The track's sound is never written over that WAV, its input.
  expectOneLineFailure(runCli({"track", silent.string(), "-o", (folder / "speaker.csv").string()}, logs()),
                       "speaker.wav", "the video's own sound");
  EXPECT_FALSE(fs::exists(folder / "speaker.csv"));
}

TEST_F(TrackCliTest, BadVideosFailInOneLineAndLeaveNothing) {
  const std::string csv = (out() / "t.csv").string();
  expectOneLineFailure(runCli({"track", (folder_.path() / "missing.mpg").string(), "-o", csv}, logs()), "missing.mpg",
                       "no such file");
  const fs::path text = folder_.path() / "text.mp4";
  std::ofstream(text) << "not a video at all";
  expectOneLineFailure(runCli({"track", text.string(), "-o", csv}, logs()), "text.mp4", "");
  const fs::path faceless = folder_.path() / "gradient.mp4";
  th::test::writeFacelessVideo(faceless);
  expectOneLineFailure(runCli({"track", faceless.string(), "-o", csv}, logs()), "gradient.mp4", "no face found");
  const fs::path soundless = folder_.path() / "silent.avi";
  th::test::writeSoundlessCopy(clip(), soundless);
  expectOneLineFailure(runCli({"track", soundless.string(), "-o", csv}, logs()), "silent.avi", "audio");
  expectOneLineFailure(runCli({"track", clip().string(), "-o", (out() / "t.txt").string()}, logs()), "t.txt", ".csv");
  expectOneLineFailure(runCli({"track", clip().string(), "-o", (out() / "no" / "t.csv").string()}, logs()), "t.csv",
                       "folder does not exist");
  EXPECT_TRUE(fs::is_empty(out())) << "a partial output was left behind";
}

}  // namespace
