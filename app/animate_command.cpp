// `talkinghead animate IN -o OUT [--format F]`: any recording in, an animation out: MPEG-4 FAP curves (head
// rotation from the head model, jaw and lips from the mouth model), ARKit weights, or the viseme model's visemes
// and mouth cues (Oculus, VRM, Rhubarb, Moho), in the format named or the one the output's extension picks; or,
// with --avatar, the user's character with the speech as its glTF animation (.glb, .gltf, .vrm), or that
// animation alone (--animation-only).
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "avatar/avatar_animation.h"
#include "avatar/avatar_pose.h"
#include "character.h"
#include "cli_options.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text_files.h"
#include "formats/animation_format.h"
#include "formats/gltf_animation.h"
#include "head_style_clip.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"

namespace th::app {
namespace {

// animate's own options: how the offline path decodes.
struct DecodingChoices {
  bool online = false;
  std::string preset;  // a live preset's streaming (pipeline/live_presets.h); empty: animate's own
  std::string start = "conditional";
  void visitOptions(OptionVisitor& v) {
    v.option(online, {.name = "online",
                      .help = "Streaming forms, as live use runs them: fixed-lag head decoding, windowed inversion"});
    v.option(preset, {.name = "preset",
                      .help = "With --online: stream as live's preset does (its mouth and articulation models, "
                              "window and iterations), frame for frame what live shows of the file with its head "
                              "on time (the web package's frames)",
                      .choices = pipeline::kLivePresetNames});
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
  std::string avatar;                                  // --avatar: a glTF animation of this character
  bool animationOnly = false;                          // --animation-only: the animation without the character's meshes
};

bool isGltf(const std::string& path) {
  const std::string extension = lowercaseExtension(path);
  return extension == ".glb" || extension == ".gltf" || extension == ".vrm";
}

// The glTF output's arguments, checked before any work.
void checkGltfArguments(const AnimateArguments& arguments) {
  if (arguments.avatar.empty()) {
    if (isGltf(arguments.output))
      throw fileError(arguments.output, "a glTF animation moves a character: give --avatar FILE");
    if (arguments.animationOnly)
      throw fileError(arguments.output, "--animation-only is a character's animation alone: give --avatar FILE");
    return;
  }
  avatar::checkAvatarAnimationOutput(arguments.avatar, arguments.output, arguments.animationOnly);
  if (!arguments.format.empty())
    throw fileError(arguments.output, "--format is for the other formats: a glTF animation's extension is its format");
}

void writeCharacterAnimation(const AnimateArguments& arguments, const avatar::Avatar& character,
                             const face::FapTrack& track) {
  const formats::GltfAnimationTracks tracks =
      avatar::writeSpeechOnAvatar(arguments.avatar, character, track, arguments.output, arguments.animationOnly);
  const int frames = avatar::avatarAnimationFrames(track);
  std::cout << "wrote " << arguments.output << " (glTF, "
            << (arguments.animationOnly ? "the animation alone" : "the character") << "): " << frames << " frames at "
            << tracks.framesPerSecond << " fps (" << track.durationSeconds() << " s), " << tracks.morphs.size()
            << " morph weight tracks, " << tracks.rotations.size() << " bone rotation tracks; head "
            << arguments.models.head << ", mouth " << arguments.models.mouth
            << (arguments.decoding.online ? ", online" : ", batch") << '\n';
}

void runAnimate(const AnimateArguments& arguments) {
  // What can be checked without work is checked first, so a bad output path or character fails at once.
  checkGltfArguments(arguments);
  const formats::AnimationFormat* format =
      arguments.avatar.empty() ? &formats::formatForWriting(arguments.output, arguments.format) : nullptr;
  checkOutputTarget(arguments.output);
  const std::optional<avatar::Avatar> character = loadCharacter(arguments.avatar);
  if (!arguments.decoding.preset.empty() && !arguments.decoding.online)
    throw fileError(arguments.output, "--preset is a live preset's streaming: give --online too");
  pipeline::HeadMotionOptions head = arguments.head;
  pipeline::IdleOptions idle = arguments.idle;
  resolveHeadStyleClip(head, idle, arguments.models, std::cerr);
  pipeline::AnimateOptions options;
  pipeline::AnimationModels models;
  if (arguments.decoding.preset.empty()) {
    options = pipeline::animateOptionsOf(arguments.models, head, idle,
                                         arguments.decoding.online ? &arguments.streaming : nullptr,
                                         arguments.decoding.start);
    models = pipeline::loadModels(arguments.models);
  } else {
    pipeline::LiveSettings live;
    live.models = arguments.models;
    live.head = head;
    live.idle = idle;
    pipeline::applyLivePreset(live, arguments.decoding.preset);
    live.check();
    options = pipeline::livePresetAnimateOptions(live, arguments.decoding.start);
    models = pipeline::loadModels(live);
  }
  const face::FapTrack track = pipeline::animateRecording(arguments.input, models, options);
  if (character) {
    writeCharacterAnimation(arguments, *character, track);
    return;
  }
  formats::writeAnimation(arguments.output, track, *format);

  std::cout << "wrote " << arguments.output << " (" << format->name() << "): " << track.numFrames() << " frames at "
            << track.framesPerSecond << " fps (" << track.durationSeconds() << " s), FAPs";
  for (int fap : track.faps) std::cout << ' ' << fap;
  std::cout << "; head " << arguments.models.head << ", mouth " << arguments.models.mouth
            << (arguments.decoding.online ? ", online" : ", batch") << '\n';
}

}  // namespace

void addAnimateCommand(CLI::App& app) {
  auto arguments = std::make_shared<AnimateArguments>();
  CLI::App* animate =
      app.add_subcommand("animate",
                         "Recording -> animation: MPEG-4 FAPs (.csv, .json, .fap), ARKit weights, "
                         "Oculus or VRM visemes, Rhubarb mouth cues (.tsv, .xml, .json, Moho .dat), or a "
                         "character's glTF animation (.glb, .gltf, .vrm with --avatar)");
  animate->add_option("input", arguments->input, "Recording: WAV/FLAC/... or a video's audio track")->required();
  animate
      ->add_option("-o,--output", arguments->output,
                   "Animation file (its extension picks the format); .glb, .gltf or .vrm with --avatar")
      ->required();
  std::vector<std::string> formatNames;
  for (const formats::AnimationFormat* format : formats::animationFormats()) formatNames.emplace_back(format->name());
  animate
      ->add_option("--format", arguments->format,
                   "Format: csv, json, fap (FAPs), arkit, oculus, vrm (weights; .json for JSON), rhubarb-tsv, "
                   "rhubarb-xml, rhubarb-json, moho (mouth cues); default: by the extension")
      ->check(CLI::IsMember(formatNames));
  animate->add_option("--avatar", arguments->avatar,
                      "A character (.glb, .gltf, .vrm): write it with the speech as its glTF animation (morph "
                      "target weights, neck, head and eye rotations, 30 a second)");
  animate->add_flag("--animation-only", arguments->animationOnly,
                    "With --avatar: the animation alone (the character's nodes and morph target names, no meshes)");
  addOptions(*animate, arguments->models);
  addOptions(*animate, arguments->decoding);
  addOptions(*animate, arguments->streaming);
  addOptions(*animate, arguments->head);
  addOptions(*animate, arguments->idle);
  animate->callback([arguments] { runAnimate(*arguments); });
}

}  // namespace th::app
