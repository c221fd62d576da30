// `talkinghead style CLIP [-o STYLE.json]`: a person's head style from a clip of them talking (a video, or a
// head-pose CSV with its WAV), the head model fitted to move like them, saved as a small file that --head-style
// takes on animate, export, sidebyside and live, and that the live panel offers (app/head_style_clip.h).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

#include "animation/head_model.h"
#include "animation/head_style.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "head_style_clip.h"
#include "pipeline/options.h"

namespace th::app {
namespace {

struct StyleArguments {
  std::string clip;
  std::string output;     // empty: headStyleFolder()/CLIP's name.json
  std::string headModel;  // empty: the shipped one
};

void runStyle(const StyleArguments& arguments) {
  std::filesystem::path output = arguments.output;
  if (output.empty()) {
    const std::filesystem::path folder = headStyleFolder();
    if (folder.empty()) throw Error("style: no HOME or XDG_CONFIG_HOME to keep the style in; give -o FILE.json");
    output = folder / (std::filesystem::path(arguments.clip).stem().string() + ".json");
  }
  if (output.extension() != ".json") throw fileError(output, "a head style is written as JSON: give a .json name");
  if (std::filesystem::path(arguments.clip) == output)
    throw fileError(output, "the style would overwrite its own clip; give another -o");
  const bool inTheFolder = arguments.output.empty();
  if (!inTheFolder) checkOutputTarget(output);
  pipeline::ModelOptions models;
  models.headModel = arguments.headModel;
  const animation::HeadModel model = animation::loadHeadModel(models.headModelPath());
  const animation::HeadStyle style = headStyleOfClip(arguments.clip, model, std::cerr);
  if (inTheFolder) {
    std::error_code error;
    std::filesystem::create_directories(output.parent_path(), error);
    if (error) throw fileError(output.parent_path(), "cannot be made: " + error.message());
  }
  animation::saveHeadStyle(output, style);
  std::cout << "wrote " << output.string() << ": " << describeHeadStyle(style) << '\n';
}

}  // namespace

void addStyleCommand(CLI::App& app) {
  auto arguments = std::make_shared<StyleArguments>();
  CLI::App* command = app.add_subcommand(
      "style",
      "Talking clip -> a head style file: how this person's head moves (spread, speed, rest pose, pauses, beats), "
      "the head model fitted to move like it, for --head-style");
  command
      ->add_option("clip", arguments->clip,
                   "20-60 s of the person talking: a video (tracked), a head-pose CSV with its WAV beside it "
                   "(track's), or a style file")
      ->required();
  command->add_option("-o,--output", arguments->output,
                      "Style file (.json; default: NAME.json in ~/.config/talkinghead/head-styles, where the live "
                      "panel finds it)");
  command->add_option("--head-model", arguments->headModel,
                      "The head model to fit (default: the shipped one; a style is for the model it was fitted to)");
  command->callback([arguments] { runStyle(*arguments); });
}

}  // namespace th::app
