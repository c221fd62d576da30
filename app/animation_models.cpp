#include "animation_models.h"

#include "core/error.h"

namespace th::app {

AnimationModels loadAnimationModels(const std::string& command, const std::string& headVariant,
                                    const std::string& headModel, const std::string& mouthMethod,
                                    const std::string& mouthModel) {
  AnimationModels models;
  if (headVariant != "none") models.head = std::make_unique<animation::HeadModel>(animation::loadHeadModel(headModel));
  if (mouthMethod != "none") {
    models.mouth = std::make_unique<animation::MouthModel>(animation::loadMouthModel(mouthModel));
    if (!animation::drivesFaps(*models.mouth))
      throw fileError(mouthModel, "drives no FAPs (a sweep model?); make one with `talkinghead train mouth`");
  }
  if (!models.head && !models.mouth) throw Error(command + ": --head none and --mouth none leave nothing to animate");
  return models;
}

void addModelFileOptions(CLI::App& command, std::string& headModel, std::string& mouthModel) {
  command.add_option("--head-model", headModel, "Head model file")->capture_default_str();
  command.add_option("--mouth-model", mouthModel, "Mouth model file")->capture_default_str();
}

std::string defaultHeadModel() { return std::string(TALKINGHEAD_SOURCE_DIR) + "/models/head.json"; }
std::string defaultMouthModel() { return std::string(TALKINGHEAD_SOURCE_DIR) + "/models/mouth.json"; }

}  // namespace th::app
