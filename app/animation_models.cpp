#include "animation_models.h"

#include "core/error.h"

namespace th::app {

AnimationModels loadAnimationModels(const std::string& command, const std::string& headVariant,
                                    const std::string& headModel, const std::string& mouthMethod,
                                    const std::string& mouthModel) {
  if (headVariant == "none" && mouthMethod == "none")
    throw Error(command + ": --head none and --mouth none leave nothing to animate");
  return pipeline::loadAnimationModels(headVariant == "none" ? "" : headModel, mouthMethod == "none" ? "" : mouthModel);
}

void addModelFileOptions(CLI::App& command, std::string& headModel, std::string& mouthModel) {
  command.add_option("--head-model", headModel, "Head model file")->capture_default_str();
  command.add_option("--mouth-model", mouthModel, "Mouth model file")->capture_default_str();
}

std::string defaultHeadModel() { return pipeline::shippedModel("head.json").string(); }
std::string defaultMouthModel() { return pipeline::shippedModel("mouth.json").string(); }

void addIdleControls(CLI::App& command, MotionControls& controls) {
  command.add_flag("--no-idle", [&controls](std::int64_t) { controls.idle = false; },
                   "No blinks, gaze shifts or head at rest in silence (on by default)");
  command.add_option("--blinks-per-minute", controls.blinksPerMinute, "Idle: spontaneous blinks a minute at rest")
      ->check(CLI::Range(1.0, 60.0))
      ->capture_default_str();
  command.add_option("--seed", controls.seed, "Seed of the head's variation and of the idle behaviour")
      ->capture_default_str();
}

void addMotionControls(CLI::App& command, MotionControls& controls) {
  command.add_option("--head-amplitude", controls.headAmplitude, "Head rotations times this")
      ->check(CLI::Range(0.0, 5.0))
      ->capture_default_str();
  command.add_option("--head-smoothing", controls.headSmoothing,
                     "Head trajectory: above 1 slower and smoother, below 1 quicker")
      ->check(CLI::Range(0.1, 10.0))
      ->capture_default_str();
  command.add_option("--head-variation", controls.headVariation,
                     "Head: the motion the voice does not explain, times this (0: the smooth curve alone)")
      ->check(CLI::Range(0.0, 3.0))
      ->capture_default_str();
  addIdleControls(command, controls);
}

animation::IdleMotionOptions idleOptionsOf(const MotionControls& controls) {
  animation::IdleMotionOptions idle;
  idle.blinksPerMinute = controls.blinksPerMinute;
  idle.seed = controls.seed;
  return idle;
}

void applyMotionControls(const MotionControls& controls, pipeline::AnimateOptions& options) {
  options.head.amplitude = controls.headAmplitude;
  options.head.smoothing = controls.headSmoothing;
  options.head.variation = controls.headVariation;
  options.head.seed = controls.seed;
  options.idle = controls.idle;
  options.idleOptions = idleOptionsOf(controls);
}

}  // namespace th::app
