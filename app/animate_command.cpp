// `talkinghead animate IN -o OUT.(csv|json|fap)`: any recording in, MPEG-4 FAP curves out (head rotation from
// the head model, jaw and lips from the mouth model), in the file format the output's extension names.
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "pipeline/offline.h"
#include "audio/media_audio.h"
#include "animation_models.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/animation_format.h"

namespace th::app {
namespace {

using animation::HeadVariant;
using animation::MouthMethod;

struct AnimateArguments {
  std::string input;
  std::string output;
  std::string headVariant = "trajectory";
  std::string mouthMethod = "inversion";
  std::string start = "conditional";
  bool online = false;
  int lagFrames = 6;
  int windowFrames = 30;
  std::string headModel = defaultHeadModel();
  std::string mouthModel = defaultMouthModel();
  MotionControls motion;
};

const std::map<std::string, HeadVariant> kHeadVariants{
    {"paper", HeadVariant::kStateMeans}, {"trajectory", HeadVariant::kTrajectory}, {"posterior", HeadVariant::kPosteriorMeans}};
const std::map<std::string, MouthMethod> kMouthMethods{{"inversion", MouthMethod::kInversion}, {"mmse", MouthMethod::kMmse}};

void runAnimate(const AnimateArguments& arguments) {
  // What can be checked without work is checked first, so a bad output path fails at once.
  formats::animationFormatFor(arguments.output);
  checkOutputTarget(arguments.output);
  pipeline::AnimateOptions options;
  options.head.variant = kHeadVariants.count(arguments.headVariant) ? kHeadVariants.at(arguments.headVariant) : HeadVariant::kTrajectory;
  options.head.maxLagFrames = arguments.online ? arguments.lagFrames : -1;
  options.mouth.method = kMouthMethods.count(arguments.mouthMethod) ? kMouthMethods.at(arguments.mouthMethod) : MouthMethod::kInversion;
  options.mouth.start = arguments.start == "random" ? hmm::InversionStart::kRandom : hmm::InversionStart::kConditionalMean;
  options.mouth.windowFrames = arguments.online ? arguments.windowFrames : 0;
  applyMotionControls(arguments.motion, options);

  const AnimationModels models = loadAnimationModels("animate", arguments.headVariant, arguments.headModel,
                                                     arguments.mouthMethod, arguments.mouthModel);
  const face::FapTrack result = pipeline::animateRecording(arguments.input, models, options);
  formats::writeAnimation(arguments.output, result);

  std::cout << "wrote " << arguments.output << ": " << result.numFrames() << " frames at " << result.framesPerSecond
            << " fps (" << result.numFrames() / result.framesPerSecond << " s), FAPs";
  for (int fap : result.faps) std::cout << ' ' << fap;
  std::cout << "; head " << arguments.headVariant << ", mouth " << arguments.mouthMethod
            << (arguments.online ? ", online" : ", batch") << '\n';
}

}  // namespace

void addAnimateCommand(CLI::App& app) {
  auto arguments = std::make_shared<AnimateArguments>();
  CLI::App* animate = app.add_subcommand(
      "animate", "Recording -> MPEG-4 FAP animation (head FAPs 48-50, jaw FAP 3, lip FAPs, blinks and gaze) as .csv, .json or .fap");
  animate->add_option("input", arguments->input, "Recording: WAV/FLAC/... or a video's audio track")->required();
  animate->add_option("-o,--output", arguments->output, "Animation file: .csv, .json or .fap (MPEG-4 FAP stream)")
      ->required();
  animate->add_option("--head", arguments->headVariant,
                      "Head variant: paper (Viterbi state means), trajectory (smooth, ML with deltas), "
                      "posterior (posterior-weighted means), none")
      ->check(CLI::IsMember({"paper", "trajectory", "posterior", "none"}))
      ->capture_default_str();
  animate->add_option("--mouth", arguments->mouthMethod, "Mouth method: inversion (HMM inversion), mmse, none")
      ->check(CLI::IsMember({"inversion", "mmse", "none"}))
      ->capture_default_str();
  animate->add_option("--start", arguments->start,
                      "Inversion start: conditional (audio-only conditional mean) or random (the paper's)")
      ->check(CLI::IsMember({"conditional", "random"}))
      ->capture_default_str();
  animate->add_flag("--online", arguments->online,
                    "Streaming forms, as live use runs them: fixed-lag head decoding, windowed inversion");
  animate->add_option("--lag", arguments->lagFrames, "Online: head decoding lag, frames")
      ->check(CLI::Range(0, 300))
      ->capture_default_str();
  animate->add_option("--window", arguments->windowFrames, "Online: inversion window, frames")
      ->check(CLI::Range(1, 3000))
      ->capture_default_str();
  addModelFileOptions(*animate, arguments->headModel, arguments->mouthModel);
  addMotionControls(*animate, arguments->motion);
  animate->callback([arguments] { runAnimate(*arguments); });
}

}  // namespace th::app
