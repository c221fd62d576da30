#include "eval/pitch_corpus.h"

#include <algorithm>

#include "audio/audio_file.h"
#include "core/error.h"

namespace th::eval {

std::vector<PitchRecording> loadPitchCorpus(const std::filesystem::path& folder, double referenceShiftSeconds) {
  if (!std::filesystem::is_directory(folder)) throw fileError(folder, "no such folder");
  std::vector<PitchRecording> corpus;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".wav") continue;
    auto reference = entry.path();
    reference.replace_extension(".f0ref");
    if (!std::filesystem::exists(reference)) continue;
    corpus.push_back({entry.path().stem().string(), entry.path(), readReferenceF0(reference, referenceShiftSeconds)});
  }
  if (corpus.empty()) throw fileError(folder, "no WAV files with .f0ref references");
  std::sort(corpus.begin(), corpus.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return corpus;
}

F0Track ourF0Track(const std::vector<float>& samples16k, const features::FeatureOptions& options) {
  features::FeatureOptions pitchOnly = options;
  pitchOnly.contextFrames = 0;
  const features::FeatureMatrix matrix = features::computeFeatures(samples16k, pitchOnly);
  F0Track track;
  for (int frame = 0; frame < matrix.numFrames(); ++frame) {
    track.timesSeconds.push_back(frame / matrix.framesPerSecond);
    track.f0Hz.push_back(matrix.row(frame)[features::FeatureLayout::kF0Hz]);
  }
  return track;
}

PitchScore scoreTrack(const PitchRecording& recording, const F0Track& track, double trackHopSeconds) {
  const auto estimate = sampleTrackAt(track, recording.reference.timesSeconds, trackHopSeconds / 2.0 + 1e-9);
  PitchScore score;
  score.add(recording.reference.f0Hz, estimate);
  return score;
}

PitchScore scoreOurTracker(const std::vector<PitchRecording>& corpus, const features::FeatureOptions& options) {
  PitchScore total;
  for (const auto& recording : corpus) {
    const auto clip = audio::readAudioFile(recording.wav);
    total.merge(scoreTrack(recording, ourF0Track(clip.samples, options), 1.0 / options.framesPerSecond));
  }
  return total;
}

}  // namespace th::eval
