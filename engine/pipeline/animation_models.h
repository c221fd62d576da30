// The speech models a run animates with: the head model, the mouth model, the viseme model and the
// articulation (the mouth network: animation/articulation.h), each optional, and where the shipped ones are.
// With the articulation, the visemes are its and the mouth model's lips close and meet as it hears the sounds;
// the viseme model is then not needed.
//
//   const th::pipeline::AnimationModels models =
//       th::pipeline::loadAnimationModels(th::pipeline::shippedModel("head.json"), th::pipeline::shippedModel("mouth.json"));
//
// Thread contract: loaded models are immutable and shared read-only by any number of decoders.
#pragma once

#include <filesystem>
#include <memory>
#include <string_view>

#include "animation/head_model.h"
#include "animation/mouth_model.h"
#include "animation/mouth_network.h"
#include "animation/viseme_model.h"

namespace th::pipeline {

struct AnimationModels {
  std::unique_ptr<animation::HeadModel> head;       // null: the head left out
  std::unique_ptr<animation::MouthModel> mouth;     // null: the mouth left out
  std::unique_ptr<animation::VisemeModel> visemes;  // null: no visemes (the viseme and mouth-cue formats need them)
  std::unique_ptr<animation::MouthNetwork> articulation;  // null: the mouth model's lips and the viseme model's visemes
};

// An empty path leaves that model out. Throws th::Error naming the file for an unreadable model or a mouth
// model that drives no FAPs (a sweep model), an articulation with no opening gradient, and when both the head
// and the mouth paths are empty.
AnimationModels loadAnimationModels(const std::filesystem::path& headModel, const std::filesystem::path& mouthModel,
                                    const std::filesystem::path& visemeModel = {},
                                    const std::filesystem::path& articulationModel = {});

// Where a shipped model is ("head.json", "mouth_live.json", ...): in $TALKINGHEAD_MODELS if set, else the
// source tree's models/ if it is there, else the installed share/talkinghead/models.
std::filesystem::path shippedModel(std::string_view file);

}  // namespace th::pipeline
