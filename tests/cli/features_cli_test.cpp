// The `talkinghead features` command as a user meets it: the built executable run as a child process.
// Bad input or an unwritable output gives a non-zero exit, exactly one line on stderr naming the file and
// the reason, no crash and no partial output; good input gives one row per frame at the frame rate asked for.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "audio_test_files.h"
#include "cli_runner.h"

namespace {

namespace fs = std::filesystem;

using th::test::CliResult;
using th::test::expectOneLineFailure;
using th::test::readText;
using th::test::runCli;

using FeaturesCliTest = th::test::CliTest;

// ---- bad input ----

class BadInputCliTest : public FeaturesCliTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(BadInputCliTest, OneLineNonZeroExitNoOutputFile) {
  const auto inputs = th::test::makeBadInputs(folder_.path());
  const auto bad = std::find_if(inputs.begin(), inputs.end(), [&](const auto& b) { return b.name == GetParam(); });
  ASSERT_NE(bad, inputs.end());
  const fs::path output = out() / "features.csv";
  const CliResult result = runCli({"features", bad->path.string(), "-o", output.string()}, logs());
  expectOneLineFailure(result, bad->path.string(), bad->reason);
  EXPECT_FALSE(fs::exists(output));
  EXPECT_TRUE(outFolderIsEmpty()) << "a temporary file was left behind";
}

INSTANTIATE_TEST_SUITE_P(Inputs, BadInputCliTest,
                         ::testing::Values("missing", "directory", "text_renamed_wav", "mp3_like", "zero_bytes",
                                           "zero_frames", "truncated", "float_nan", "float_inf", "float_huge",
                                           "rate_2khz", "rate_192khz"),
                         [](const auto& testInfo) { return testInfo.param; });

// ---- unwritable output ----

fs::path arcticPath() {
  return th::test::readArcticPrompt().path;
}

TEST_F(FeaturesCliTest, OutputInAFolderThatDoesNotExist) {
  const std::string output = "/nonexistent-dir-talkinghead-test/x.csv";
  ASSERT_FALSE(fs::exists(fs::path(output).parent_path()));
  const CliResult result = runCli({"features", arcticPath().string(), "-o", output}, logs());
  expectOneLineFailure(result, output, "does not exist");
}

TEST_F(FeaturesCliTest, OutputInAReadOnlyFolder) {
  // The input is copied into a folder every user can read, so that a non-root child can read it.
  fs::permissions(folder_.path(), fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                      fs::perms::others_read | fs::perms::others_exec);
  const fs::path input = folder_.path() / "speech.wav";
  fs::copy_file(arcticPath(), input);
  fs::permissions(input, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const fs::path readOnly = folder_.path() / "read-only";
  fs::create_directory(readOnly);
  fs::permissions(readOnly, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  fs::permissions(logs(), fs::perms::all);
  const std::optional<uid_t> nobody = ::geteuid() == 0 ? std::optional<uid_t>(65534) : std::nullopt;
  const fs::path output = readOnly / "x.csv";
  const CliResult result = runCli({"features", input.string(), "-o", output.string()}, logs(), nobody);
  expectOneLineFailure(result, output.string(), "cannot be written");
  EXPECT_TRUE(fs::is_empty(readOnly));
}

TEST_F(FeaturesCliTest, OutputOnAReadOnlyFileSystem) {
  // /proc refuses new files even to root.
  const CliResult result = runCli({"features", arcticPath().string(), "-o", "/proc/x.csv"}, logs());
  expectOneLineFailure(result, "/proc/x.csv", "cannot be written");
}

TEST_F(FeaturesCliTest, OutputThatIsAFolder) {
  const CliResult result = runCli({"features", arcticPath().string(), "-o", out().string()}, logs());
  expectOneLineFailure(result, out().string(), "is a directory");
}

// ---- good runs ----

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};

Table readCsv(const fs::path& path) {
  Table table;
  std::ifstream in(path);
  std::string line;
  if (std::getline(in, line)) {
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) table.header.push_back(cell);
  }
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::vector<double> row;
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    table.rows.push_back(std::move(row));
  }
  return table;
}

class GoodRunCliTest : public FeaturesCliTest {
 protected:
  void SetUp() override {
    FeaturesCliTest::SetUp();
    input_ = arcticPath();
    durationSeconds_ = th::audio::readAudioFile(input_).durationSeconds();
  }
  Table run(const std::vector<std::string>& extra, const std::string& fileName) {
    const fs::path output = out() / fileName;
    std::vector<std::string> arguments = {"features", input_.string(), "-o", output.string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const CliResult result = runCli(arguments, logs());
    EXPECT_TRUE(result.exited && result.exitCode == 0) << "exit " << result.exitCode << ": " << result.err;
    EXPECT_TRUE(fs::exists(output));
    return readCsv(output);
  }

  fs::path input_;
  double durationSeconds_ = 0.0;
};

TEST_F(GoodRunCliTest, CsvHasOneRowPerFrameAt30Fps) {
  const Table table = run({}, "features.csv");
  ASSERT_GE(table.header.size(), 2u);
  EXPECT_EQ(table.header[0], "time_s");
  EXPECT_EQ(table.header[1], "f0_hz");
  EXPECT_NEAR(static_cast<double>(table.rows.size()), durationSeconds_ * 30.0, 1.0);
  for (size_t i = 0; i < table.rows.size(); ++i) {
    ASSERT_EQ(table.rows[i].size(), table.header.size()) << "row " << i;
    EXPECT_NEAR(table.rows[i][0], static_cast<double>(i) / 30.0, 1e-6) << "row " << i;
  }
  // Speech: some frames voiced, F0 in a human range.
  const auto voiced = std::count_if(table.rows.begin(), table.rows.end(), [](const auto& r) { return r[1] > 0; });
  EXPECT_GT(voiced, static_cast<long>(table.rows.size() / 4));
  EXPECT_TRUE(std::all_of(table.rows.begin(), table.rows.end(),
                          [](const auto& r) { return r[1] == 0 || (r[1] > 50 && r[1] < 500); }));
  EXPECT_TRUE(std::all_of(fs::directory_iterator(out()), fs::directory_iterator(), [](const auto& entry) {
    return entry.path().filename() == "features.csv";
  })) << "a temporary file was left behind";
}

TEST_F(GoodRunCliTest, FpsOptionSetsTheRowRate) {
  const Table table = run({"--fps", "100"}, "features100.csv");
  EXPECT_NEAR(static_cast<double>(table.rows.size()), durationSeconds_ * 100.0, 1.0);
  ASSERT_GE(table.rows.size(), 2u);
  EXPECT_NEAR(table.rows[1][0], 0.01, 1e-9);
}

TEST_F(GoodRunCliTest, JsonHoldsTheSameFramesAsCsv) {
  const Table csv = run({}, "features.csv");
  const fs::path jsonPath = out() / "features.out";
  const CliResult result = runCli({"features", input_.string(), "-o", jsonPath.string(), "--format", "json"}, logs());
  ASSERT_TRUE(result.exited && result.exitCode == 0) << result.err;
  nlohmann::json document;
  ASSERT_NO_THROW(document = nlohmann::json::parse(readText(jsonPath))) << "not valid JSON";
  ASSERT_TRUE(document.contains("frames") && document["frames"].is_array());
  const auto& frames = document["frames"];
  EXPECT_EQ(frames.size(), csv.rows.size());
  EXPECT_EQ(document["num_frames"].get<size_t>(), csv.rows.size());
  EXPECT_EQ(document["columns"].get<std::vector<std::string>>(), csv.header);
  for (size_t i = 0; i < std::min<size_t>(frames.size(), csv.rows.size()); ++i) {
    ASSERT_EQ(frames[i].size(), csv.rows[i].size()) << "frame " << i;
    for (size_t k = 0; k < csv.rows[i].size(); ++k) {
      // The CSV prints 7 significant digits; JSON keeps the float.
      const double fromJson = frames[i][k].get<double>();
      EXPECT_NEAR(fromJson, csv.rows[i][k], 1e-6 * std::max(1.0, std::abs(fromJson))) << "frame " << i << " " << k;
    }
  }
}

}  // namespace

// ---- the hmm subcommands ----

namespace hmmcli {

// A CSV of 2 sequences from a 3-state model whose 2-D observations are "a1" (audio) and "v1" (visual), with
// v1 = a1 + small noise, so inversion has something to recover.
void writeTrainingCsv(const fs::path& path, int framesPerSequence) {
  std::ofstream out(path);
  out << "seq,a1,v1\n";
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (int s = 0; s < 2; ++s) {
    int state = 0;
    for (int t = 0; t < framesPerSequence; ++t) {
      if (t % 40 == 39) state = (state + 1) % 3;
      const double a = 4.0 * state + noise(random);
      out << s << ',' << a << ',' << a + 0.1 * noise(random) << '\n';
    }
  }
}

int countLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace hmmcli

TEST_F(FeaturesCliTest, TrainHeadThenEvaluateItBesideItsBaselines) {
  const fs::path model = out() / "head.json";
  // Few states and iterations: the test is of the commands, not of the model (docs/head.md has its numbers).
  CliResult result =
      runCli({"train", "head", "--start-states", "8", "--iterations", "20", "-o", model.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  ASSERT_TRUE(fs::exists(model));
  EXPECT_NE(result.err.find("4 speakers"), std::string::npos) << result.err;
  result = runCli({"eval", "head", "--start-states", "8", "--iterations", "20", "--residual-from-training", "--model",
                   model.string(), "--lag", "4"},
                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  for (const std::string expected :
       {"scott left out", "Obama left out", "KristiNoem left out", "andrew left out", "trajectory (the default)",
        "Viterbi state means (paper)", "online (live, lag 4)", "the mean pose", "another clip's real motion",
        "random walk, matched statistics", "FD", "on BEAT2's held-out part", "Blinks"}) {
    EXPECT_NE(result.out.find(expected), std::string::npos) << expected;
  }
  // A model file that is not a head model: one line naming it.
  const fs::path plain = folder_.path() / "data.csv";
  hmmcli::writeTrainingCsv(plain, 100);
  const fs::path hmmFile = out() / "plain.json";
  ASSERT_EQ(
      runCli({"hmm", "train", "--data", plain.string(), "--states", "2", "-o", hmmFile.string()}, logs()).exitCode, 0);
  expectOneLineFailure(runCli({"eval", "head", "--model", hmmFile.string()}, logs()), hmmFile.string(),
                       "not a head model");
}

TEST_F(FeaturesCliTest, EvalMouthReportsThePapersMeasuresAndTheSweepWritesPlots) {
  CliResult result = runCli({"eval", "mouth", "--beat2"}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  for (const std::string expected : {"held-out part", "inversion, random start (paper)", "MMSE estimate",
                                     "baseline: mean prediction", "another segment", "ρ = 0.75"}) {
    EXPECT_NE(result.out.find(expected), std::string::npos) << expected;
  }
  const fs::path model = out() / "mouth.json";
  result = runCli({"train", "mouth", "--beat2", "--beat2-states", "3", "--beat2-mixtures", "1", "-o", model.string()},
                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  result = runCli({"eval", "mouth", "--beat2", "--model", model.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("held-out part"), std::string::npos) << result.out;
  const fs::path folder = out() / "sweep";
  result = runCli({"eval", "mouth", "--beat2", "--sweep", "--states", "3,4", "--mixtures", "1", "--contexts", "2",
                   "--iterations", "5", "--output", folder.string()},
                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const std::string csv = readText(folder / "mouth_sweep.csv");
  EXPECT_EQ(hmmcli::countLines(csv), 5) << "a header and 2 covariances x 2 state counts:\n" << csv;
  for (const char* png : {"mouth_sweep_full.png", "mouth_sweep_diag.png"}) {
    const std::string bytes = readText(folder / png);
    ASSERT_GT(bytes.size(), 1000u) << png;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
  }
  expectOneLineFailure(
      runCli({"eval", "mouth", "--beat2", "--sweep", "--states", "3,x", "--output", folder.string()}, logs()),
      "--states", "not a positive integer");
}

TEST_F(FeaturesCliTest, HmmTrainWithTheEntropicPriorPrunesAndRecordsEveryStep) {
  const fs::path data = folder_.path() / "data.csv";
  hmmcli::writeTrainingCsv(data, 400);
  const fs::path model = out() / "model.json";
  const CliResult result = runCli({"hmm", "train", "--data", data.string(), "--states", "8", "--entropic", "80",
                                   "--warmup", "5", "--ramp", "5", "-o", model.string()},
                                  logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto file = nlohmann::json::parse(readText(model));
  EXPECT_LT(file["states"].size(), 8u) << "the prior removes states the 3-state data does not need";
  const auto& history = file["training"]["history"];
  ASSERT_GT(history.size(), 10u);
  for (size_t i = 0; i + 1 < history.size(); ++i) {
    const double posterior = history[i]["log_likelihood"].get<double>() + history[i]["log_prior"].get<double>();
    EXPECT_GE(history[i]["step_gain"].get<double>(), -1e-9 * std::abs(posterior)) << "iteration " << i;
    EXPECT_TRUE(history[i].contains("trim_retries") && history[i].contains("states_merged"));
  }
  EXPECT_EQ(file["training"]["options"]["merge_candidates"], 8);
}

TEST_F(FeaturesCliTest, HmmTrainInfoDecodeInvert) {
  const fs::path data = folder_.path() / "data.csv";
  hmmcli::writeTrainingCsv(data, 400);
  const fs::path model = out() / "model.json";
  CliResult result =
      runCli({"hmm", "train", "--data", data.string(), "--states", "3", "--visual-columns", "v1", "-o", model.string()},
             logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  ASSERT_TRUE(fs::exists(model));

  result = runCli({"hmm", "info", model.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto info = nlohmann::json::parse(result.out);
  EXPECT_EQ(info["states"], 3);
  EXPECT_EQ(info["dimension"], 2);
  EXPECT_EQ(info["blocks"].size(), 2u);
  EXPECT_GT(info["iterations"].get<int>(), 0);
  EXPECT_TRUE(std::isfinite(info["final_log_likelihood_per_frame"].get<double>()));

  const fs::path states = out() / "states.csv";
  result = runCli({"hmm", "decode", model.string(), "--data", data.string(), "-o", states.string()}, logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const std::string decoded = readText(states);
  EXPECT_EQ(decoded.substr(0, 6), "state\n");
  EXPECT_EQ(hmmcli::countLines(decoded), 801);

  result = runCli(
      {"hmm", "decode", model.string(), "--data", data.string(), "--online", "--max-lag", "3", "-o", states.string()},
      logs());
  ASSERT_EQ(result.exitCode, 0) << result.err;
  std::istringstream online(readText(states));
  std::string line;
  std::getline(online, line);
  EXPECT_EQ(line, "state,lag_frames");
  while (std::getline(online, line)) EXPECT_LE(std::stoi(line.substr(line.find(',') + 1)), 3) << line;

  for (const std::string method : {"inversion", "mmse"}) {
    const fs::path visual = out() / ("visual-" + method + ".csv");
    result = runCli(
        {"hmm", "invert", model.string(), "--data", data.string(), "--method", method, "-o", visual.string()}, logs());
    ASSERT_EQ(result.exitCode, 0) << result.err;
    std::istringstream rows(readText(visual));
    std::getline(rows, line);
    EXPECT_EQ(line, "v1");
    // The visual estimate follows the audio: within the noise of a1 = v1.
    std::ifstream original(data);
    std::string input;
    std::getline(original, input);
    int checked = 0;
    while (std::getline(rows, line) && std::getline(original, input)) {
      const double a = std::stod(input.substr(input.find(',') + 1));
      EXPECT_NEAR(std::stod(line), a, 0.5) << method;
      ++checked;
    }
    EXPECT_EQ(checked, 800);
  }
}

TEST_F(FeaturesCliTest, HmmBadInputsGiveOneLine) {
  const fs::path ragged = folder_.path() / "ragged.csv";
  std::ofstream(ragged) << "a,b\n1,2\n3\n";
  const fs::path model = out() / "m.json";
  expectOneLineFailure(
      runCli({"hmm", "train", "--data", ragged.string(), "--states", "2", "-o", model.string()}, logs()),
      ragged.string(), "line 3 has 1 values");
  EXPECT_TRUE(outFolderIsEmpty());

  const fs::path text = folder_.path() / "text.csv";
  std::ofstream(text) << "a,b\n1,x\n";
  expectOneLineFailure(runCli({"hmm", "train", "--data", text.string(), "--states", "2", "-o", model.string()}, logs()),
                       text.string(), "is not a finite number");

  const fs::path notModel = folder_.path() / "not-a-model.json";
  std::ofstream(notModel) << "{\"format\": \"something else\"}\n";
  expectOneLineFailure(runCli({"hmm", "info", notModel.string()}, logs()), notModel.string(), "format");

  // A model without audio/visual blocks cannot be inverted.
  const fs::path data = folder_.path() / "data.csv";
  hmmcli::writeTrainingCsv(data, 200);
  ASSERT_EQ(runCli({"hmm", "train", "--data", data.string(), "--states", "2", "-o", model.string()}, logs()).exitCode,
            0);
  const fs::path visual = out() / "v.csv";
  expectOneLineFailure(
      runCli({"hmm", "invert", model.string(), "--data", data.string(), "-o", visual.string()}, logs()), model.string(),
      "no audio and visual blocks");
  EXPECT_FALSE(fs::exists(visual));
}
