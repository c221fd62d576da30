// A mouth model of one's own speaker from talking videos (`talkinghead train --video DIR -o MODEL.json`): the
// tracked clips' jaw and lip FAPs become the visual part of the audio-visual HMM (tracking/video_training.h), and
// the model is checked on held-out clips against baselines and another model, by ε and ρ on the jaw and on the
// FAPs both hold.
//
//   tracking::VideoCorpus clips = ...;   // tracked with the sound's offset taken out (synchronise)
//   th::eval::trainMouthModelOnOwnClips(clips, {.output = "me.json"}, shipped, std::cout);
//
// Thread contract: one call at a time per stream.
#pragma once

#include <filesystem>
#include <ostream>

#include "animation/mouth_model.h"
#include "tracking/video_training.h"

namespace th::eval {

struct OwnMouthTraining {
  std::filesystem::path output;  // the model file (.json)
  std::filesystem::path folder;  // the videos' folder and where their tracks are kept, as the report names them
  std::filesystem::path tracks;
  int holdOutEvery = 5;  // every N-th clip (by name) held out and reported on; 0 trains on all
  // Chosen on the GRID s1 training clips alone, by tools/choose_video_mouth.sh (README: "Training from video").
  // FAPs are not standardised (trainVideoMouthModel), and the model file's options say so.
  // The speech normalised, the components' deltas generated as a trajectory and the spread compensated, as the
  // shipped models are (`train mouth`).
  animation::MouthModelOptions options{.states = 6,
                                       .mixtures = 1,
                                       .covariance = hmm::CovarianceType::kFull,
                                       .contextFrames = 2,
                                       .visualComponents = 3,
                                       .standardiseVisual = false,
                                       .normaliseSpeech = true,
                                       .visualDeltas = true,
                                       .varianceValidationEvery = 5};
};

// The tracking summarised, the model trained on the clips not held out and saved, then the held-out clips judged:
// this model by inversion and by MMSE, on its visual components (the paper's measure), `compared` (read from
// `comparedPath`), the training mean and this model on another clip's audio.
void trainMouthModelOnOwnClips(const tracking::VideoCorpus& corpus, const OwnMouthTraining& training,
                               const animation::MouthModel& compared, const std::filesystem::path& comparedPath,
                               std::ostream& out);

}  // namespace th::eval
