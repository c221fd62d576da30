#include "pipeline/animation_models.h"

#include <cstdlib>
#include <string>

#include "core/error.h"

namespace th::pipeline {

AnimationModels loadAnimationModels(const std::filesystem::path& headModel, const std::filesystem::path& mouthModel,
                                    const std::filesystem::path& visemeModel,
                                    const std::filesystem::path& articulationModel) {
  if (headModel.empty() && mouthModel.empty()) throw Error("neither a head nor a mouth model: nothing to animate");
  AnimationModels models;
  if (!headModel.empty()) models.head = std::make_unique<animation::HeadModel>(animation::loadHeadModel(headModel));
  if (!mouthModel.empty()) {
    models.mouth = std::make_unique<animation::MouthModel>(animation::loadMouthModel(mouthModel));
    if (!animation::drivesFaps(*models.mouth))
      throw fileError(mouthModel, "drives no FAPs (a sweep model?); make one with `talkinghead train mouth`");
  }
  if (!visemeModel.empty())
    models.visemes = std::make_unique<animation::VisemeModel>(animation::loadVisemeModel(visemeModel));
  if (!articulationModel.empty()) {
    models.articulation = std::make_unique<animation::MouthNetwork>(animation::loadMouthNetwork(articulationModel));
    if (models.articulation->openingGradient.size() == 0)
      throw fileError(articulationModel,
                      "has no opening_gradient: the lips cannot be closed by it; make one with "
                      "`talkinghead train articulation`");
  }
  return models;
}

std::filesystem::path shippedModel(std::string_view file) {
  if (const char* own = std::getenv("TALKINGHEAD_MODELS"); own != nullptr && *own != '\0')
    return std::filesystem::path(own) / std::string(file);
  // The source tree's (a build), else the installed ones (libtalkinghead and the Python module, installed).
  const std::filesystem::path source = std::filesystem::path(TALKINGHEAD_SOURCE_DIR) / "models";
  std::error_code error;
  if (std::filesystem::is_directory(source, error)) return source / std::string(file);
  return std::filesystem::path(TALKINGHEAD_INSTALLED_MODELS) / std::string(file);
}

}  // namespace th::pipeline
