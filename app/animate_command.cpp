// `talkinghead animate IN -o OUT [--format F]`: any recording in, an animation out: MPEG-4 FAP curves (head
// rotation from the head model, jaw and lips from the mouth model), ARKit weights, or the viseme model's visemes
// and mouth cues (Oculus, VRM, Rhubarb, Moho), in the format named or the one the output's extension picks.
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli_options.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "formats/animation_format.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"

namespace th::app {
namespace {

// animate's own options: how the offline path decodes.
struct DecodingChoices {
  bool online = false;
  std::string start = "conditional";
  void visitOptions(OptionVisitor& v) {
    v.option(online, {.name = "online",
                      .help = "Streaming forms, as live use runs them: fixed-lag head decoding, windowed inversion"});
    v.option(start, {.name = "start",
                     .help = "Inversion start: conditional (audio-only conditional mean) or random (the paper's)",
                     .choices = pipeline::kInversionStartNames});
  }
};

struct AnimateArguments {
  std::string input;
  std::string output;
  std::string format;
  pipeline::ModelOptions models;
  pipeline::HeadMotionOptions head;
  pipeline::IdleOptions idle;
  DecodingChoices decoding;
  pipeline::StreamingOptions streaming{.window = 30};  // --online: a second of inversion window
};

void runAnimate(const AnimateArguments& arguments) {
  // What can be checked without work is checked first, so a bad output path fails at once.
  const formats::AnimationFormat& format = formats::formatForWriting(arguments.output, arguments.format);
  checkOutputTarget(arguments.output);
  const pipeline::AnimateOptions options =
      pipeline::animateOptionsOf(arguments.models, arguments.head, arguments.idle,
                                 arguments.decoding.online ? &arguments.streaming : nullptr, arguments.decoding.start);
  const pipeline::AnimationModels models = pipeline::loadModels(arguments.models);
  const face::FapTrack track = pipeline::animateRecording(arguments.input, models, options);
  formats::writeAnimation(arguments.output, track, format);

  std::cout << "wrote " << arguments.output << " (" << format.name() << "): " << track.numFrames() << " frames at "
            << track.framesPerSecond << " fps (" << track.durationSeconds() << " s), FAPs";
  for (int fap : track.faps) std::cout << ' ' << fap;
  std::cout << "; head " << arguments.models.head << ", mouth " << arguments.models.mouth
            << (arguments.decoding.online ? ", online" : ", batch") << '\n';
}

}  // namespace

void addAnimateCommand(CLI::App& app) {
  auto arguments = std::make_shared<AnimateArguments>();
  CLI::App* animate = app.add_subcommand("animate",
                                         "Recording -> animation: MPEG-4 FAPs (.csv, .json, .fap), ARKit weights, "
                                         "Oculus or VRM visemes, Rhubarb mouth cues (.tsv, .xml, .json, Moho .dat)");
  animate->add_option("input", arguments->input, "Recording: WAV/FLAC/... or a video's audio track")->required();
  animate->add_option("-o,--output", arguments->output, "Animation file (its extension picks the format)")->required();
  std::vector<std::string> formatNames;
  for (const formats::AnimationFormat* format : formats::animationFormats()) formatNames.emplace_back(format->name());
  animate
      ->add_option("--format", arguments->format,
                   "Format: csv, json, fap (FAPs), arkit, oculus, vrm (weights; .json for JSON), rhubarb-tsv, "
                   "rhubarb-xml, rhubarb-json, moho (mouth cues); default: by the extension")
      ->check(CLI::IsMember(formatNames));
  addOptions(*animate, arguments->models);
  addOptions(*animate, arguments->decoding);
  addOptions(*animate, arguments->streaming);
  addOptions(*animate, arguments->head);
  addOptions(*animate, arguments->idle);
  animate->callback([arguments] { runAnimate(*arguments); });
}

}  // namespace th::app
