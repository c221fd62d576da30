#include "animation/speech_analysis.h"

#include "features/online_features.h"

namespace th::animation {

SpeechAnalysis analyseSpeech(std::span<const float> samples16k, const ProsodyOptions& options) {
  const features::FeatureMatrix rows =
      features::computeFeatures(samples16k, prosodyFeatureOptions(kAnimationFramesPerSecond));
  SpeechAnalysis analysis;
  analysis.prosody = prosodyOf(rows, options);
  analysis.voiced = voicingOf(rows);
  analysis.speech = speechFramesOf(rows);
  return analysis;
}

}  // namespace th::animation
