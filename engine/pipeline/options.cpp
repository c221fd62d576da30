#include "pipeline/options.h"

#include <array>

#include "core/error.h"

namespace th::pipeline {

void ModelOptions::visitOptions(OptionVisitor& v) {
  v.option(head, {.name = "head",
                  .help = "Head motion: trajectory (smooth, ML with deltas), paper (Viterbi state means), posterior "
                          "(posterior-weighted means), none",
                  .choices = kHeadVariantNames});
  v.option(mouth,
           {.name = "mouth", .help = "Mouth: inversion (HMM inversion), mmse, none", .choices = kMouthMethodNames});
  v.option(headModel,
           {.name = "head-model", .help = "Head model file (default: the shipped models/head.json)", .panel = false});
  v.option(mouthModel,
           {.name = "mouth-model", .help = "Mouth model file (default: the shipped one in models/)", .panel = false});
  v.option(visemeModel, {.name = "viseme-model",
                         .help = "Viseme model file, the visemes' source with --articulation-model none (default: the "
                                 "shipped models/visemes.json; none: no visemes)",
                         .panel = false});
  v.option(articulationModel,
           {.name = "articulation-model",
            .help = "Articulation file: the mouth network that gives the visemes and closes, rounds and spreads the "
                    "lips (default: the shipped models/articulation.json, live the preset's; none: the mouth "
                    "model's lips and the viseme model's visemes)",
            .panel = false});
}

std::filesystem::path ModelOptions::articulationModelPath(std::string_view shipped) const {
  if (articulationModel == "none") return {};
  return articulationModel.empty() ? shippedModel(shipped) : std::filesystem::path(articulationModel);
}

std::filesystem::path ModelOptions::headModelPath() const {
  if (head == "none") return {};
  return headModel.empty() ? shippedModel("head.json") : std::filesystem::path(headModel);
}

std::filesystem::path ModelOptions::visemeModelPath() const {
  if (visemeModel == "none") return {};
  return visemeModel.empty() ? shippedModel("visemes.json") : std::filesystem::path(visemeModel);
}

std::filesystem::path ModelOptions::mouthModelPath(std::string_view shippedMouth) const {
  if (mouth == "none") return {};
  return mouthModel.empty() ? shippedModel(shippedMouth) : std::filesystem::path(mouthModel);
}

void HeadMotionOptions::visitOptions(OptionVisitor& v) {
  v.option(amplitude, {.name = "head-amplitude", .help = "Head rotations times this", .min = 0.0, .max = 5.0});
  v.option(smoothing, {.name = "head-smoothing",
                       .help = "Head trajectory: above 1 slower and smoother, below 1 quicker",
                       .min = 0.1,
                       .max = 10.0,
                       .logarithmic = true});
  v.option(variation, {.name = "head-variation",
                       .help = "Head: the motion the voice does not explain, times this (0: the smooth curve alone)",
                       .min = 0.0,
                       .max = 3.0});
  v.option(style, {.name = "head-style",
                   .help = "Head: move like the person in this clip (a talking video, a head-pose CSV with its "
                           "WAV beside it, or a style file); 20-60 s of them talking",
                   .panel = false});
}

void useHeadStyle(const animation::HeadStyle& style, HeadMotionOptions& head, IdleOptions& idle) {
  head.fittedStyle = style;
  idle.headRestDegrees = style.restPose;
}

void clearHeadStyle(HeadMotionOptions& head, IdleOptions& idle) {
  head.style.clear();
  head.fittedStyle.reset();
  idle.headRestDegrees.setZero();
}

void IdleOptions::visitOptions(OptionVisitor& v) {
  v.option(idle, {.name = "idle", .help = "the idle behaviour: blinks, gaze shifts and the head at rest in silence"});
  v.option(blinksPerMinute,
           {.name = "blinks-per-minute", .help = "Idle: spontaneous blinks a minute at rest", .min = 1.0, .max = 60.0});
  v.option(seed, {.name = "seed",
                  .help = "Seed of the head's variation and of the idle behaviour",
                  .min = 0.0,
                  .max = 4294967295.0,
                  .panel = false});
}

animation::IdleMotionOptions IdleOptions::motionOptions() const {
  animation::IdleMotionOptions options;
  options.blinksPerMinute = blinksPerMinute;
  options.seed = seed;
  options.headRestDegrees = headRestDegrees;
  return options;
}

void StreamingOptions::visitOptions(OptionVisitor& v) {
  v.option(lag, {.name = "lag-frames",
                 .help = "Head: online Viterbi's decision lag",
                 .unit = "frames",
                 .min = 0,
                 .max = 300,
                 .logarithmic = true,
                 .formerName = "lag"});
  v.option(window, {.name = "window-frames",
                    .help = "Mouth: inversion window (window - 1 frames of look-ahead)",
                    .unit = "frames",
                    .min = 1,
                    .max = 300,
                    .logarithmic = true,
                    .formerName = "window"});
}

void LiveOptions::visitOptions(OptionVisitor& v) {
  v.option(preset, {.name = "preset",
                    .help = "default (~85 ms), low-latency (~67 ms, less accurate), accurate (~200 ms, smooth)",
                    .choices = kLivePresetNames});
  v.option(device,
           {.name = "device", .help = "Sound input: default, or a device number from --list-devices", .panel = false});
  v.option(covariance, {.name = "covariance",
                        .help = "The shipped mouth model's covariance: full, or its diagonal twin",
                        .choices = kCovarianceNames});
  v.option(iterations, {.name = "iterations",
                        .help = "Mouth inversion: the most EM iterations a window",
                        .min = 1,
                        .max = 1000,
                        .logarithmic = true});
  v.option(waitForHead, {.name = "wait-for-head",
                         .help = "Each frame waits for its own head (~400 ms) instead of showing the head late"});
  v.option(minF0, {.name = "min-f0-hz",
                   .help = "Lowest F0 the prosody tracker searches",
                   .unit = "Hz",
                   .min = 20.0,
                   .max = 1000.0,
                   .logarithmic = true,
                   .formerName = "min-f0"});
  v.option(maxF0, {.name = "max-f0-hz",
                   .help = "Highest F0 the prosody tracker searches",
                   .unit = "Hz",
                   .min = 40.0,
                   .max = 2000.0,
                   .logarithmic = true,
                   .formerName = "max-f0"});
  v.option(interpolate, {.name = "interpolate", .help = "Smooth 60 Hz motion between frames (+33 ms)"});
  v.option(blinks, {.name = "blinks", .help = "the idle behaviour's blinks"});
  v.option(gaze, {.name = "gaze", .help = "the idle behaviour's small gaze shifts"});
}

void LiveSettings::visitOptions(OptionVisitor& v) {
  live.visitOptions(v);
  models.visitOptions(v);
  streaming.visitOptions(v);
  head.visitOptions(v);
  idle.visitOptions(v);
}

void LiveSettings::check() {
  checkOptions(*this);
  if (!(live.minF0 < live.maxF0)) throw Error("min-f0-hz must be below max-f0-hz");
}

std::filesystem::path LiveSettings::mouthModelPath() const {
  const LivePreset* preset = findLivePreset(live.preset);
  std::string file(preset != nullptr ? preset->mouthModelFile : kLivePresets[0].mouthModelFile);
  if (live.covariance == "diagonal") file.insert(file.size() - std::string_view(".json").size(), "_diagonal");
  return models.mouthModelPath(file);
}

std::filesystem::path LiveSettings::articulationModelPath() const {
  const LivePreset* preset = findLivePreset(live.preset);
  return models.articulationModelPath(preset != nullptr ? preset->articulationFile : kLivePresets[0].articulationFile);
}

LiveDecoderOptions LiveSettings::decoderOptions() const {
  return decoderOptionsOf(models, head, idle, streaming, live);
}

void applyLivePreset(LiveSettings& settings, std::string_view preset) {
  const LivePreset* found = findLivePreset(preset);
  if (found == nullptr) {
    std::string names;
    for (const LivePreset& p : kLivePresets) names += (names.empty() ? "" : ", ") + std::string(p.name);
    throw Error("no preset \"" + std::string(preset) + "\" (there are " + names + ")");
  }
  settings.live.preset = std::string(preset);
  for (const PresetValue& value : found->values) setOption(settings, value.option, value.value);
}

std::optional<int> LiveOptions::deviceIndex() const {
  if (device == "default") return std::nullopt;
  std::size_t used = 0;
  int index = -1;
  try {
    index = std::stoi(device, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != device.size() || index < 0)
    throw Error("device: \"" + device + "\" is not \"default\" or a device number from --list-devices");
  return index;
}

namespace {

animation::HeadVariant headVariantOf(const std::string& name) {
  if (name == "paper") return animation::HeadVariant::kStateMeans;
  if (name == "posterior") return animation::HeadVariant::kPosteriorMeans;
  return animation::HeadVariant::kTrajectory;
}

animation::MouthMethod mouthMethodOf(const std::string& name) {
  return name == "mmse" ? animation::MouthMethod::kMmse : animation::MouthMethod::kInversion;
}

}  // namespace

AnimateOptions animateOptionsOf(const ModelOptions& models, const HeadMotionOptions& head, const IdleOptions& idle,
                                const StreamingOptions* online, std::string_view start) {
  AnimateOptions options;
  options.head.variant = headVariantOf(models.head);
  options.head.maxLagFrames = online != nullptr ? online->lag : -1;
  options.head.amplitude = head.amplitude;
  options.head.smoothing = head.smoothing;
  options.head.variation = head.variation;
  options.head.seed = idle.seed;
  if (head.fittedStyle) animation::applyHeadStyle(*head.fittedStyle, options.head);
  options.mouth.method = mouthMethodOf(models.mouth);
  options.mouth.start = start == "random" ? hmm::InversionStart::kRandom : hmm::InversionStart::kConditionalMean;
  options.mouth.windowFrames = online != nullptr ? online->window : 0;
  options.articulationLagFrames = online != nullptr ? LiveDecoderOptions{}.articulationLagFrames : -1;
  options.idle = idle.idle;
  options.idleOptions = idle.motionOptions();
  return options;
}

AnimateOptions livePresetAnimateOptions(const LiveSettings& settings, std::string_view start) {
  AnimateOptions options = animateOptionsOf(settings.models, settings.head, settings.idle, &settings.streaming, start);
  options.mouth.maxIterations = settings.live.iterations;
  return options;
}

LiveDecoderOptions decoderOptionsOf(const ModelOptions& models, const HeadMotionOptions& head, const IdleOptions& idle,
                                    const StreamingOptions& streaming, const LiveOptions& live) {
  LiveDecoderOptions options;
  options.head.variant = headVariantOf(models.head);
  options.head.maxLagFrames = streaming.lag;
  options.head.amplitude = head.amplitude;
  options.head.smoothing = head.smoothing;
  options.head.variation = head.variation;
  options.head.seed = idle.seed;
  if (head.fittedStyle) animation::applyHeadStyle(*head.fittedStyle, options.head);
  options.mouth.method = mouthMethodOf(models.mouth);
  options.mouth.windowFrames = streaming.window;
  options.mouth.maxIterations = live.iterations;
  options.waitForHead = live.waitForHead;
  options.minF0Hz = live.minF0;
  options.maxF0Hz = live.maxF0;
  return options;
}

AnimationModels loadModels(const ModelOptions& models, std::string_view shippedMouth) {
  if (models.head == "none" && models.mouth == "none")
    throw Error("--head none and --mouth none leave nothing to animate");
  return loadAnimationModels(models.headModelPath(), models.mouthModelPath(shippedMouth), models.visemeModelPath(),
                             models.articulationModelPath());
}

AnimationModels loadModels(const LiveSettings& settings) {
  ModelOptions models = settings.models;
  if (models.mouth != "none") models.mouthModel = settings.mouthModelPath().string();
  if (models.articulationModel != "none") models.articulationModel = settings.articulationModelPath().string();
  return loadModels(models);
}

}  // namespace th::pipeline
