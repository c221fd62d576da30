// `talkinghead live --headless` as a user meets it: a recording played through the live pipeline's threads,
// at real-time pace or at full speed, gives the same frames (tests/pipeline holds the decoder to `animate`);
// bad input fails in one line and leaves no dump behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "core/data_path.h"
#include "video/animation_file.h"

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
  CliResult result = runCli({"live", "--headless", "--input", speech().string(), "--duration", "8", "--speed", "4",
                             "--dump", live.string()},
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
  const th::video::Animation a = th::video::readAnimation(live);
  const th::video::Animation b = th::video::readAnimation(out() / "fast.csv");
  ASSERT_EQ(a.faps, b.faps);
  ASSERT_EQ(a.numFrames(), 240);
  ASSERT_EQ(b.numFrames(), 240);
  // Real-time pace or as fast as possible: the same frames (the decoder does not depend on timing).
  EXPECT_EQ((a.values - b.values).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GE(a.columnOf(3), 0);
  EXPECT_GT(a.values.col(a.columnOf(3)).maxCoeff(), 0.0);  // the jaw moves
}

TEST_F(LiveCliTest, BadInputFailsInOneLineAndLeavesNoDump) {
  const fs::path dump = out() / "dump.csv";
  expectOneLineFailure(runCli({"live", "--headless", "--input", (out() / "missing.wav").string(), "--dump", dump.string()}, logs()),
                       "missing.wav", "no such file");
  EXPECT_FALSE(fs::exists(dump));
  const fs::path text = out() / "text.wav";
  std::ofstream(text) << "not audio at all";
  const CliResult notAudio = runCli({"live", "--headless", "--input", text.string(), "--dump", dump.string()}, logs());
  EXPECT_NE(notAudio.exitCode, 0);
  EXPECT_FALSE(fs::exists(dump));
  expectOneLineFailure(runCli({"live", "--headless", "--input", speech().string(), "--dump", (out() / "x.txt").string()}, logs()),
                       "x.txt", "");
  EXPECT_NE(runCli({"live", "--input", speech().string()}, logs()).exitCode, 0) << "--headless is required (no window yet)";
}

}  // namespace
