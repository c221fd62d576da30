// `talkinghead train visemes` and `talkinghead eval visemes`: the viseme model (animation/viseme_model.h) from the
// shared data's phone-aligned speech, and its accuracy on speakers it never heard.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "eval/viseme_report.h"
#include "face/visemes.h"

namespace th::app {
namespace {

struct VisemeArguments {
  eval::VisemeReportOptions report;  // eval; its recipe, `model`, is train's too
  std::string output = "models/visemes.json";
};

void addRecipeOptions(CLI::App* command, VisemeArguments& arguments) {
  command->add_option("--context", arguments.report.model.contextFrames, "Context frames each side (30 fps)")
      ->check(CLI::Range(0, 20))
      ->capture_default_str();
  command->add_option("--dimensions", arguments.report.model.dimensions, "Discriminant directions kept")
      ->check(CLI::Range(1, face::kNumMouthClasses - 1))
      ->capture_default_str();
  command->add_option("--mixtures", arguments.report.model.mixtures, "Gaussians per mouth class")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  command->add_option("--min-hold", arguments.report.model.minHoldFrames, "Frames a viseme is shown at least")
      ->check(CLI::Range(1, 15))
      ->capture_default_str();
  command
      ->add_option("--emission-scale", arguments.report.model.emissionScale, "Weight of the sound against the sequence")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
}

}  // namespace

void addTrainVisemesCommand(CLI::App& train) {
  auto arguments = std::make_shared<VisemeArguments>();
  CLI::App* command = train.add_subcommand(
      "visemes", "Speech -> visemes (Oculus, VRM, Rhubarb) from BEAT2's and StyleTalk's phone-aligned speech");
  addRecipeOptions(command, *arguments);
  command->add_option("-o,--output", arguments->output, "Model file to write")->capture_default_str();
  command->callback([arguments] { eval::trainVisemesOnCorpus(arguments->output, arguments->report.model, std::cout); });
}

void addEvalVisemesCommand(CLI::App& eval) {
  auto arguments = std::make_shared<VisemeArguments>();
  CLI::App* command = eval.add_subcommand(
      "visemes",
      "Visemes from speech, leave one speaker out: accuracy against the phones, confusion matrices, hold times");
  addRecipeOptions(command, *arguments);
  command->add_option("--lag-frames,--lag", arguments->report.lagFrames, "Decision lag of the streamed decoder, frames")
      ->check(CLI::Range(0, 60))
      ->capture_default_str();
  command->add_flag("--sweep", arguments->report.sweep, "Also the minimum hold and the emission scale, one at a time");
  command->callback([arguments] { eval::reportVisemes(arguments->report, std::cout); });
}

}  // namespace th::app
