// `talkinghead features IN -o OUT.csv|json`: one row per animation frame; without -o, a summary on screen.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "pipeline/feature_output.h"

namespace th::app {
namespace {

struct FeaturesArguments {
  pipeline::FeatureOutput request;
  std::string energy = "utterance";
};

void runFeatures(FeaturesArguments arguments) {
  features::FeatureOptions& options = arguments.request.options;
  if (arguments.energy == "utterance") options.energyNormalisation = features::EnergyNormalisation::kUtterance;
  if (arguments.energy == "running") options.energyNormalisation = features::EnergyNormalisation::kRunning;
  if (arguments.energy == "none") options.energyNormalisation = features::EnergyNormalisation::kNone;
  options.check();
  pipeline::writeRecordingFeatures(arguments.request, std::cout, std::cerr);
}

}  // namespace

void addFeaturesCommand(CLI::App& app) {
  auto arguments = std::make_shared<FeaturesArguments>();
  CLI::App* command = app.add_subcommand(
      "features", "Speech features per animation frame (F0, energy, deltas, MFCC, context) of a recording");
  command
      ->add_option("input", arguments->request.input,
                   "Recording: WAV, FLAC, OGG (any rate 8-96 kHz, any channels), or a video's or MP3's sound")
      ->required();
  command->add_option("-o,--output", arguments->request.output,
                      "CSV or JSON file to write; without it, print a summary");
  command->add_option("--format", arguments->request.format, "csv, json, or auto (from the output's extension)")
      ->check(CLI::IsMember({"auto", "csv", "json"}));
  command->add_option("--fps", arguments->request.options.framesPerSecond, "Frames per second (10-200)")
      ->check(CLI::Range(10.0, 200.0));
  command->add_option("--context", arguments->request.options.contextFrames, "MFCC context stacking, +-frames (0-20)")
      ->check(CLI::Range(0, 20));
  command->add_option("--mfcc", arguments->request.options.mfcc.numCoefficients, "Number of MFCCs c1..cN (1-23)")
      ->check(CLI::Range(1, 23));
  command->add_option("--min-f0-hz,--min-f0", arguments->request.options.pitch.minF0Hz, "Lowest F0 searched (Hz)")
      ->check(CLI::Range(30.0, 400.0));
  command->add_option("--max-f0-hz,--max-f0", arguments->request.options.pitch.maxF0Hz, "Highest F0 searched (Hz)")
      ->check(CLI::Range(80.0, 1500.0));
  command->add_option("--energy", arguments->energy, "Energy normalisation: utterance, running or none")
      ->check(CLI::IsMember({"utterance", "running", "none"}));
  command->callback([arguments] { runFeatures(*arguments); });
}

}  // namespace th::app
