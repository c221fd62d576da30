// `talkinghead features IN -o OUT.csv|json`: one row per animation frame; without -o, a summary on screen.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "features/online_features.h"

namespace th::app {
namespace {

struct FeaturesArguments {
  std::string input;
  std::string output;
  std::string format = "auto";
  std::string energy = "utterance";
  features::FeatureOptions options = features::batchFeatureOptions();
};

void writeCsv(std::ostream& out, const features::FeatureMatrix& matrix) {
  out << "time_s";
  for (const auto& name : matrix.layout.columnNames()) out << ',' << name;
  out << '\n';
  out << std::setprecision(7);
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    out << std::fixed << std::setprecision(6) << frame / matrix.framesPerSecond << std::defaultfloat
        << std::setprecision(7);
    for (float value : matrix.row(frame)) out << ',' << value;
    out << '\n';
  }
}

void writeJson(std::ostream& out, const features::FeatureMatrix& matrix, const features::FeatureLookahead& lookahead) {
  nlohmann::json document;
  document["frames_per_second"] = matrix.framesPerSecond;
  document["num_frames"] = matrix.numFrames();
  std::vector<std::string> columns = {"time_s"};
  const auto names = matrix.layout.columnNames();
  columns.insert(columns.end(), names.begin(), names.end());
  document["columns"] = columns;
  document["lookahead_ms"] = {{"f0", lookahead.f0Ms},           {"energy", lookahead.energyMs},
                              {"mfcc", lookahead.mfccMs},       {"deltas", lookahead.deltasMs},
                              {"context", lookahead.contextMs}, {"total", lookahead.totalMs}};
  nlohmann::json rows = nlohmann::json::array();
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    nlohmann::json row = nlohmann::json::array();
    row.push_back(frame / matrix.framesPerSecond);
    for (float value : matrix.row(frame)) row.push_back(value);
    rows.push_back(std::move(row));
  }
  document["frames"] = std::move(rows);
  out << document.dump() << '\n';
}

void printSummary(const std::string& input, const audio::AudioClip& clip, const features::FeatureMatrix& matrix,
                  const features::FeatureLookahead& lookahead) {
  std::vector<float> voiced;
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    const float f0 = matrix.row(frame)[features::FeatureLayout::kF0Hz];
    if (f0 > 0) voiced.push_back(f0);
  }
  std::sort(voiced.begin(), voiced.end());
  const auto quantile = [&](double q) {
    return voiced.empty() ? 0.0f : voiced[static_cast<size_t>(q * static_cast<double>(voiced.size() - 1))];
  };
  std::cout << std::fixed << std::setprecision(1);
  std::cout << input << '\n'
            << "  source: " << clip.sourceRateHz << " Hz, " << clip.sourceChannels << " channel(s), "
            << std::setprecision(2) << clip.durationSeconds() << " s -> 16 kHz mono\n"
            << std::setprecision(1) << "  frames: " << matrix.numFrames() << " at " << matrix.framesPerSecond
            << " fps, " << matrix.layout.size() << " values per frame (f0, energy, 2 deltas, " << matrix.layout.numMfcc
            << " MFCC, +-" << matrix.layout.contextFrames << " frames of MFCC context)\n"
            << "  voiced: "
            << (matrix.numFrames() ? 100.0 * static_cast<double>(voiced.size()) / matrix.numFrames() : 0.0)
            << " % of frames; F0 median " << quantile(0.5) << " Hz, 5-95 % range " << quantile(0.05) << "-"
            << quantile(0.95) << " Hz\n"
            << "  look-ahead (ms): F0 " << lookahead.f0Ms << ", energy " << lookahead.energyMs << ", MFCC "
            << lookahead.mfccMs << ", deltas " << lookahead.deltasMs << ", context " << lookahead.contextMs
            << "; whole frame " << lookahead.totalMs << " (" << lookahead.totalFrames << " frames)\n";
  // A coarse picture of the F0 contour: one character per 100 ms, height by F0, '.' unvoiced.
  std::string contour;
  const int step = std::max(1, static_cast<int>(std::lround(matrix.framesPerSecond / 10.0)));
  const float low = quantile(0.05);
  const float high = std::max(quantile(0.95), low + 1.0f);
  const std::string levels = "_-=^";
  for (int frame = 0; frame < matrix.numFrames() && contour.size() < 100; frame += step) {
    const float f0 = matrix.row(frame)[features::FeatureLayout::kF0Hz];
    if (f0 <= 0) {
      contour += '.';
    } else {
      const int level = std::clamp(static_cast<int>((f0 - low) / (high - low) * 4.0f), 0, 3);
      contour += levels[static_cast<size_t>(level)];
    }
  }
  std::cout << "  F0 contour (100 ms per character): " << contour << '\n';
}

void runFeatures(const FeaturesArguments& arguments) {
  features::FeatureOptions options = arguments.options;
  if (arguments.energy == "utterance") options.energyNormalisation = features::EnergyNormalisation::kUtterance;
  if (arguments.energy == "running") options.energyNormalisation = features::EnergyNormalisation::kRunning;
  if (arguments.energy == "none") options.energyNormalisation = features::EnergyNormalisation::kNone;
  options.check();

  std::string format = arguments.format;
  if (format == "auto") {
    format = arguments.output.size() >= 5 && arguments.output.substr(arguments.output.size() - 5) == ".json" ? "json"
                                                                                                             : "csv";
  }
  // Open the output first so that an unwritable path fails before any work is done.
  std::unique_ptr<AtomicFile> output;
  if (!arguments.output.empty()) output = std::make_unique<AtomicFile>(arguments.output);

  const audio::AudioClip clip = audio::readRecording(arguments.input);
  const features::FeatureMatrix matrix = features::computeFeatures(clip.samples, options);
  const features::OnlineFeatureExtractor probe(options);
  if (output) {
    if (format == "json") {
      writeJson(output->stream(), matrix, probe.lookahead());
    } else {
      writeCsv(output->stream(), matrix);
    }
    output->commit();
    std::cerr << "wrote " << matrix.numFrames() << " frames to " << arguments.output << '\n';
  } else {
    printSummary(arguments.input, clip, matrix, probe.lookahead());
  }
}

}  // namespace

void addFeaturesCommand(CLI::App& app) {
  auto arguments = std::make_shared<FeaturesArguments>();
  CLI::App* command = app.add_subcommand(
      "features", "Speech features per animation frame (F0, energy, deltas, MFCC, context) of a recording");
  command
      ->add_option("input", arguments->input,
                   "Recording: WAV, FLAC, OGG (any rate 8-96 kHz, any channels), or a video's or MP3's sound")
      ->required();
  command->add_option("-o,--output", arguments->output, "CSV or JSON file to write; without it, print a summary");
  command->add_option("--format", arguments->format, "csv, json, or auto (from the output's extension)")
      ->check(CLI::IsMember({"auto", "csv", "json"}));
  command->add_option("--fps", arguments->options.framesPerSecond, "Frames per second (10-200)")
      ->check(CLI::Range(10.0, 200.0));
  command->add_option("--context", arguments->options.contextFrames, "MFCC context stacking, +-frames (0-20)")
      ->check(CLI::Range(0, 20));
  command->add_option("--mfcc", arguments->options.mfcc.numCoefficients, "Number of MFCCs c1..cN (1-23)")
      ->check(CLI::Range(1, 23));
  command->add_option("--min-f0-hz,--min-f0", arguments->options.pitch.minF0Hz, "Lowest F0 searched (Hz)")
      ->check(CLI::Range(30.0, 400.0));
  command->add_option("--max-f0-hz,--max-f0", arguments->options.pitch.maxF0Hz, "Highest F0 searched (Hz)")
      ->check(CLI::Range(80.0, 1500.0));
  command->add_option("--energy", arguments->energy, "Energy normalisation: utterance, running or none")
      ->check(CLI::IsMember({"utterance", "running", "none"}));
  command->callback([arguments] { runFeatures(*arguments); });
}

}  // namespace th::app
