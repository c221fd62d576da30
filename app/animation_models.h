// The head and mouth models as `animate` and `live` take them: `--head-model` / `--mouth-model` options, and
// loading the ones the chosen variants need ("none" skips a model).
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "animation/head_model.h"
#include "animation/mouth_model.h"

namespace th::app {

struct AnimationModels {
  std::unique_ptr<animation::HeadModel> head;    // null with --head none
  std::unique_ptr<animation::MouthModel> mouth;  // null with --mouth none
};

// Throws th::Error naming the file for a mouth model without a FAP map, and `command`'s error if both are none.
AnimationModels loadAnimationModels(const std::string& command, const std::string& headVariant,
                                    const std::string& headModel, const std::string& mouthMethod,
                                    const std::string& mouthModel);

// --head-model and --mouth-model, defaulting to the shipped models.
void addModelFileOptions(CLI::App& command, std::string& headModel, std::string& mouthModel);
std::string defaultHeadModel();
std::string defaultMouthModel();

}  // namespace th::app
