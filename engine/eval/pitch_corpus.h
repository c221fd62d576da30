// A pitch-tracking test set on disk (WAV + reference F0 pairs, as FDA-UE) and scoring our tracker on it.
//
//   auto corpus = th::features::loadPitchCorpus(th::sharedDataPath("speech/fda-ue"), 0.015);
//   th::features::PitchScore score = th::features::scoreOurTracker(corpus, options);   // at options' frame rate
//
// Every track is sampled at the reference times (nearest frame within half a hop of the tracker), so trackers
// with different hops are compared on the same frames. Thread contract: no shared state.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "eval/pitch_evaluation.h"
#include "features/online_features.h"

namespace th::eval {

struct PitchRecording {
  std::string name;
  std::filesystem::path wav;
  F0Track reference;
};

// Every NAME.wav with a NAME.f0ref beside it, sorted by name. Throws th::Error if the folder has none.
std::vector<PitchRecording> loadPitchCorpus(const std::filesystem::path& folder, double referenceShiftSeconds);

// Our tracker as the feature extractor runs it (streaming object, fed whole), at options.framesPerSecond.
F0Track ourF0Track(const std::vector<float>& samples16k, const features::FeatureOptions& options);

// Score a track against a recording's reference.
PitchScore scoreTrack(const PitchRecording& recording, const F0Track& track, double trackHopSeconds);

PitchScore scoreOurTracker(const std::vector<PitchRecording>& corpus, const features::FeatureOptions& options);

}  // namespace th::eval
