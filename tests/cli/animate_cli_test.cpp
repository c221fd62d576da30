// `talkinghead animate` as a user meets it: a recording in, FAP curves out in the format the extension names;
// the mouth moves with the voice; bad input and bad output paths fail in one line and leave no file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "audio_test_files.h"
#include "cli_runner.h"
#include "core/data_path.h"
#include "core/numeric_csv.h"
#include "formats/animation_format.h"
#include "support/files.h"

namespace {

namespace fs = std::filesystem;
using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::runCli;

class AnimateCliTest : public th::test::CliTest {
 protected:
  static fs::path speech() { return th::sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"); }
};

// Root-mean-square level of the recording in each 1/30 s frame (centred at i/30 s, like the features).
std::vector<double> frameLevels(const fs::path& wav, int frames) {
  const th::audio::AudioClip clip = th::audio::readAudioFile(wav);
  const int hop = clip.sampleRateHz / 30;
  std::vector<double> levels;
  for (int i = 0; i < frames; ++i) {
    const int centre = i * hop;
    double sum = 0.0;
    int count = 0;
    for (int n = std::max(0, centre - hop / 2);
         n < std::min<int>(static_cast<int>(clip.samples.size()), centre + hop / 2); ++n, ++count)
      sum += clip.samples[static_cast<std::size_t>(n)] * clip.samples[static_cast<std::size_t>(n)];
    levels.push_back(count > 0 ? std::sqrt(sum / count) : 0.0);
  }
  return levels;
}

TEST_F(AnimateCliTest, TheJawOpensWhenTheSpeakerIsLoudAndTheThreeFormatsAgree) {
  const fs::path csv = out() / "speech.csv";
  CliResult result = runCli({"animate", speech().string(), "-o", csv.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("FAPs 3 4"), std::string::npos) << result.out;

  const th::face::FapTrack anim = th::formats::readAnimation(csv);
  EXPECT_DOUBLE_EQ(anim.framesPerSecond, 30.0);
  EXPECT_NEAR(anim.numFrames(), 62.0 * 30, 30);  // a 62 s recording
  for (int fap : {3, 4, 5, 48, 49, 50, 51, 52}) EXPECT_GE(anim.rowOf(fap), 0) << fap;
  EXPECT_EQ(anim.faps.front(), 3);

  // The mouth follows the voice: frames in the loudest quarter open the jaw more than the quietest quarter.
  // (Only somewhat: in BEAT2's fits the true jaw correlates with the log level by 0.30; the test below
  // compares with that truth.)
  const std::vector<double> level = frameLevels(speech(), anim.numFrames());
  std::vector<double> sorted = level;
  std::sort(sorted.begin(), sorted.end());
  const double quiet = sorted[sorted.size() / 4];
  const double loud = sorted[3 * sorted.size() / 4];
  double jawLoud = 0.0, jawQuiet = 0.0;
  int numLoud = 0, numQuiet = 0;
  const int jaw = anim.rowOf(3);
  for (int t = 0; t < anim.numFrames(); ++t) {
    if (level[static_cast<std::size_t>(t)] >= loud) jawLoud += anim.values(jaw, t), ++numLoud;
    if (level[static_cast<std::size_t>(t)] <= quiet) jawQuiet += anim.values(jaw, t), ++numQuiet;
  }
  EXPECT_GT(jawLoud / numLoud, jawQuiet / numQuiet);
  // The head moves, by a plausible few degrees (1° = 1745 AU).
  for (int fap : {48, 49, 50}) {
    const auto column = anim.values.row(anim.rowOf(fap));
    const double std = std::sqrt((column.array() - column.mean()).square().mean());
    EXPECT_GT(std, 0.2 * 1745) << fap;
    EXPECT_LT(std, 15 * 1745) << fap;
  }

  for (const char* name : {"speech.json", "speech.fap"}) {
    const fs::path other = out() / name;
    result = runCli({"animate", speech().string(), "-o", other.string()}, logs());
    ASSERT_EQ(result.exitCode, 0) << result.err;
    const th::face::FapTrack back = th::formats::readAnimation(other);
    ASSERT_EQ(back.faps, anim.faps) << name;
    ASSERT_EQ(back.numFrames(), anim.numFrames()) << name;
    // CSV prints 6 significant digits; the FAP stream rounds to whole units.
    EXPECT_LT((back.values - anim.values).cwiseAbs().maxCoeff(),
              std::string(name).ends_with(".fap") ? 0.5 + 1e-3 : 0.05)
        << name;
  }
  const std::string fap = th::test::readText(out() / "speech.fap");
  EXPECT_EQ(fap.rfind("2.1 2_scott_0_2_2 30 " + std::to_string(anim.numFrames()) + "\n", 0), 0u) << fap.substr(0, 40);
}

// On BEAT2's held-out part (the last quarter, which no model trained on), FAP 3 follows the true jaw.
TEST_F(AnimateCliTest, OnHeldOutSpeechTheJawFollowsTheTruth) {
  const fs::path csv = out() / "beat2.csv";
  ASSERT_EQ(
      runCli({"animate", th::sharedDataPath("beat2/2_scott_0_1_1.wav").string(), "-o", csv.string()}, logs()).exitCode,
      0);
  const th::face::FapTrack anim = th::formats::readAnimation(csv);
  const th::NumericTable pose = th::readNumericCsv(th::sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"));
  std::vector<double> truth;
  for (const std::vector<double>& row : pose.rows)
    truth.push_back(row[static_cast<std::size_t>(pose.column("jaw_aa_x_deg"))]);
  const int frames = std::min<int>(anim.numFrames(), static_cast<int>(truth.size()));
  const int begin = frames * 3 / 4;
  Eigen::RowVectorXd predicted = anim.values.row(anim.rowOf(3)).segment(begin, frames - begin).transpose();
  Eigen::VectorXd actual = Eigen::Map<const Eigen::VectorXd>(truth.data() + begin, frames - begin);
  predicted.array() -= predicted.mean();
  actual.array() -= actual.mean();
  const double correlation = predicted.dot(actual) / (predicted.norm() * actual.norm());
  EXPECT_GT(correlation, 0.25);  // measured 0.34
}

TEST_F(AnimateCliTest, VariantsAndPartsAreSelectable) {
  const fs::path batch = out() / "batch.csv";
  const fs::path online = out() / "online.csv";
  const fs::path unbounded = out() / "unbounded.csv";
  const std::string input = speech().string();
  ASSERT_EQ(runCli({"animate", input, "-o", batch.string(), "--head", "paper", "--mouth", "mmse"}, logs()).exitCode, 0);
  ASSERT_EQ(runCli({"animate", input, "-o", online.string(), "--head", "paper", "--mouth", "mmse", "--online"}, logs())
                .exitCode,
            0);
  ASSERT_EQ(runCli({"animate", input, "-o", unbounded.string(), "--head", "paper", "--mouth", "mmse", "--online",
                    "--lag", "300"},
                   logs())
                .exitCode,
            0);
  const th::face::FapTrack a = th::formats::readAnimation(batch);
  const th::face::FapTrack b = th::formats::readAnimation(online);
  const th::face::FapTrack c = th::formats::readAnimation(unbounded);
  ASSERT_EQ(a.numFrames(), b.numFrames());
  ASSERT_EQ(a.numFrames(), c.numFrames());
  // A short decoding lag forces early decisions that batch Viterbi revises; with a lag longer than any
  // disagreement the online decoder finds the batch path exactly. The online MMSE mouth works window by window
  // (forward-backward within each): it differs from the whole-recording estimate but follows it closely.
  const int yaw = a.rowOf(49);
  EXPECT_GT((a.values.row(yaw) - b.values.row(yaw)).cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LT((a.values.row(yaw) - c.values.row(yaw)).cwiseAbs().maxCoeff(), 1e-3);
  const Eigen::RowVectorXd jawBatch = a.values.row(a.rowOf(3));
  const Eigen::RowVectorXd jawOnline = b.values.row(b.rowOf(3));
  double largestDifference = 0.0;
  for (Eigen::Index t = 0; t < jawBatch.size(); ++t)
    largestDifference = std::max(largestDifference, std::abs(jawBatch[t] - jawOnline[t]));
  EXPECT_GT(largestDifference, 1e-3);
  const auto centred = [](const Eigen::RowVectorXd& v) { return Eigen::RowVectorXd(v.array() - v.mean()); };
  const double correlation =
      centred(jawBatch).dot(centred(jawOnline)) / (centred(jawBatch).norm() * centred(jawOnline).norm());
  std::printf("[ INFO     ] online (30-frame windows) against batch MMSE jaw: correlation %.4f\n", correlation);
  EXPECT_GT(correlation, 0.9);

  const fs::path headOnly = out() / "head.csv";
  ASSERT_EQ(runCli({"animate", speech().string(), "-o", headOnly.string(), "--mouth", "none"}, logs()).exitCode, 0);
  EXPECT_EQ(th::formats::readAnimation(headOnly).faps, (std::vector<int>{19, 20, 23, 24, 25, 26, 48, 49, 50}));
  const fs::path noIdle = out() / "head_no_idle.csv";
  ASSERT_EQ(
      runCli({"animate", speech().string(), "-o", noIdle.string(), "--mouth", "none", "--no-idle"}, logs()).exitCode,
      0);
  EXPECT_EQ(th::formats::readAnimation(noIdle).faps, (std::vector<int>{48, 49, 50}));
  // The head's controls: amplitude scales it, a larger smoothing slows it.
  const fs::path twice = out() / "head_twice.csv";
  ASSERT_EQ(runCli({"animate", speech().string(), "-o", twice.string(), "--mouth", "none", "--no-idle",
                    "--head-amplitude", "2"},
                   logs())
                .exitCode,
            0);
  const th::face::FapTrack one = th::formats::readAnimation(noIdle);
  const th::face::FapTrack two = th::formats::readAnimation(twice);
  EXPECT_NEAR((two.values - 2.0 * one.values).cwiseAbs().maxCoeff(), 0.0,
              1e-3 * one.values.cwiseAbs().maxCoeff() + 1.0);
  const fs::path smooth = out() / "head_smooth.csv";
  ASSERT_EQ(runCli({"animate", speech().string(), "-o", smooth.string(), "--mouth", "none", "--no-idle",
                    "--head-smoothing", "8", "--head-variation", "0"},
                   logs())
                .exitCode,
            0);
  const fs::path plain = out() / "head_plain.csv";
  ASSERT_EQ(runCli({"animate", speech().string(), "-o", plain.string(), "--mouth", "none", "--no-idle",
                    "--head-variation", "0"},
                   logs())
                .exitCode,
            0);
  const auto roughness = [](const th::face::FapTrack& animation) {
    const Eigen::MatrixXd& v = animation.values;
    return (v.rightCols(v.cols() - 1) - v.leftCols(v.cols() - 1)).norm();
  };
  EXPECT_LT(roughness(th::formats::readAnimation(smooth)), roughness(th::formats::readAnimation(plain)));
  EXPECT_LT(roughness(th::formats::readAnimation(plain)), roughness(one)) << "the variation adds motion";
  const fs::path mouthOnly = out() / "mouth.csv";
  ASSERT_EQ(runCli({"animate", speech().string(), "-o", mouthOnly.string(), "--head", "none"}, logs()).exitCode, 0);
  EXPECT_EQ(th::formats::readAnimation(mouthOnly).rowOf(48), -1);
  expectOneLineFailure(
      runCli({"animate", speech().string(), "-o", (out() / "x.csv").string(), "--head", "none", "--mouth", "none"},
             logs()),
      "animate", "nothing to animate");
}

// The viseme model's output in every viseme and mouth-cue format: the format named, or picked by the extension.
// --online --preset P decodes as live's preset does, each frame with its own head: the frames `live --headless
// --wait-for-head` shows of the same sound (the idle motion too), to the last bit, up to where live's input was cut.
TEST_F(AnimateCliTest, APresetStreamsTheFramesLiveShowsOfTheFile) {
  const fs::path animated = out() / "preset.csv", shown = out() / "live.csv";
  ASSERT_EQ(
      runCli({"animate", speech().string(), "-o", animated.string(), "--online", "--preset", "low-latency"}, logs())
          .exitCode,
      0);
  ASSERT_EQ(runCli({"live", "--headless", "--input", speech().string(), "--duration", "8", "--speed", "0", "--preset",
                    "low-latency", "--wait-for-head", "--dump", shown.string()},
                   logs())
                .exitCode,
            0);
  const th::face::FapTrack file = th::formats::readAnimation(animated);
  const th::face::FapTrack live = th::formats::readAnimation(shown);
  ASSERT_EQ(file.faps, live.faps);
  ASSERT_GE(live.numFrames(), 200);
  // The last second of live's frames saw the input end at 8 s; the file's went on.
  const Eigen::Index compared = live.numFrames() - 30;
  EXPECT_LT((file.values.leftCols(compared) - live.values.leftCols(compared)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT(live.values.leftCols(compared).cwiseAbs().maxCoeff(), 100.0);  // it moved

  const fs::path bad = out() / "bad.csv";
  expectOneLineFailure(runCli({"animate", speech().string(), "-o", bad.string(), "--preset", "default"}, logs()),
                       bad.string(), "give --online too");
  EXPECT_FALSE(fs::exists(bad));
}

TEST_F(AnimateCliTest, VisemesAndMouthCuesInEveryFormat) {
  const fs::path prompt = th::sharedDataPath("speech/arctic/arctic_a0001.wav");
  struct Case {
    const char* file;
    const char* format;
    const char* starts;
  };
  for (const Case& c :
       {Case{"cues.tsv", "", "0.00\t"}, Case{"cues.xml", "", "<?xml version=\"1.0\" encoding=\"utf-8\"?>"},
        Case{"cues.dat", "", "MohoSwitch1\n1 "}, Case{"cues.json", "rhubarb-json", "{\n  \"metadata\""},
        Case{"oculus.csv", "oculus", "time_s,sil,PP,FF"}, Case{"oculus.json", "oculus", "{\n  \"fps\": 30"},
        Case{"vrm.csv", "vrm", "time_s,A,I,U,E,O\n"}}) {
    std::vector<std::string> arguments{"animate", prompt.string(), "-o", (out() / c.file).string()};
    if (*c.format != '\0') arguments.insert(arguments.end(), {"--format", c.format});
    const CliResult result = runCli(arguments, logs());
    ASSERT_EQ(result.exitCode, 0) << c.file << ": " << result.err;
    const std::string text = th::test::readText(out() / c.file);
    EXPECT_EQ(text.rfind(c.starts, 0), 0U) << c.file << ":\n" << text.substr(0, 200);
  }
  // The prompt is speech between silences: the cues open and close at rest and show the mouth open between.
  const std::string tsv = th::test::readText(out() / "cues.tsv");
  EXPECT_EQ(tsv.rfind("0.00\tX\n", 0), 0U) << tsv;
  EXPECT_NE(tsv.find("\tD\n"), std::string::npos) << tsv;
  EXPECT_GT(std::count(tsv.begin(), tsv.end(), '\n'), 10) << tsv;
  // Without the articulation, the viseme model's visemes: other cues from the same speech.
  const fs::path modelCues = out() / "model.tsv";
  ASSERT_EQ(
      runCli({"animate", prompt.string(), "-o", modelCues.string(), "--articulation-model", "none"}, logs()).exitCode,
      0);
  EXPECT_EQ(th::test::readText(modelCues).rfind("0.00\tX\n", 0), 0U);
  EXPECT_NE(th::test::readText(modelCues), tsv);
  expectOneLineFailure(runCli({"animate", prompt.string(), "-o", (out() / "none.tsv").string(), "--viseme-model",
                               "none", "--articulation-model", "none"},
                              logs()),
                       "none.tsv", "has no visemes");
  EXPECT_FALSE(fs::exists(out() / "none.tsv"));
  expectOneLineFailure(runCli({"animate", prompt.string(), "-o", (out() / "bad.tsv").string(), "--articulation-model",
                               (out() / "model.tsv").string()},
                              logs()),
                       "model.tsv", "");
}

TEST_F(AnimateCliTest, BadInputsAndOutputsFailInOneLineAndLeaveNothing) {
  const std::string good = (out() / "a.csv").string();
  expectOneLineFailure(runCli({"animate", (folder_.path() / "missing.wav").string(), "-o", good}, logs()),
                       "missing.wav", "no such file");
  const fs::path text = folder_.path() / "text.wav";
  std::ofstream(text) << "not audio at all";
  expectOneLineFailure(runCli({"animate", text.string(), "-o", good}, logs()), "text.wav", "not a readable audio file");
  expectOneLineFailure(runCli({"animate", speech().string(), "-o", (out() / "a.txt").string()}, logs()), "a.txt",
                       "an animation is written as .csv, .json, .fap");
  expectOneLineFailure(runCli({"animate", speech().string(), "-o", (out() / "no" / "a.csv").string()}, logs()), "a.csv",
                       "folder does not exist");
  expectOneLineFailure(runCli({"animate", speech().string(), "-o", good, "--mouth-model", text.string()}, logs()),
                       "text.wav", "not valid JSON");
  const std::string mouthModel = (fs::path(TALKINGHEAD_SOURCE_DIR) / "models" / "mouth.json").string();
  expectOneLineFailure(runCli({"animate", speech().string(), "-o", good, "--head-model", mouthModel}, logs()),
                       "mouth.json", "not a head model");
  EXPECT_TRUE(fs::is_empty(out())) << "a partial output was left behind";
}

}  // namespace
