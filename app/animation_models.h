// The head and mouth models as `animate` and `live` take them: `--head-model` / `--mouth-model` options, and
// loading the ones the chosen variants need ("none" skips a model).
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "animation/head_model.h"
#include "animation/mouth_model.h"
#include "pipeline/animation_models.h"
#include "pipeline/offline.h"

namespace th::app {

using pipeline::AnimationModels;

// Throws th::Error naming the file for a mouth model without a FAP map, and `command`'s error if both are none.
AnimationModels loadAnimationModels(const std::string& command, const std::string& headVariant,
                                    const std::string& headModel, const std::string& mouthMethod,
                                    const std::string& mouthModel);

// --head-model and --mouth-model, defaulting to the shipped models.
void addModelFileOptions(CLI::App& command, std::string& headModel, std::string& mouthModel);
std::string defaultHeadModel();
std::string defaultMouthModel();

// How the head moves and what the face does besides speaking: the same options, under the same names, in
// animate, export, sidebyside and live (live keeps them in its settings too).
struct MotionControls {
  double headAmplitude = 1.0;  // times the model's head rotations
  double headSmoothing = 1.0;  // times the trajectory's velocity and acceleration precisions
  double headVariation = 1.0;  // times the motion the voice does not explain
  bool idle = true;            // blinks, gaze shifts, the head at rest in silence
  double blinksPerMinute = animation::IdleMotionOptions{}.blinksPerMinute;
  unsigned seed = 1;           // of the head's variation and of the idle behaviour
};

// --head-amplitude, --head-smoothing, --head-variation and the idle options.
void addMotionControls(CLI::App& command, MotionControls& controls);
// --no-idle, --blinks-per-minute, --seed (for commands that play a finished animation).
void addIdleControls(CLI::App& command, MotionControls& controls);
// Into animate()'s options.
void applyMotionControls(const MotionControls& controls, pipeline::AnimateOptions& options);
animation::IdleMotionOptions idleOptionsOf(const MotionControls& controls);

}  // namespace th::app
