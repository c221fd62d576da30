#include "animation/mouth_data.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "animation/time_split.h"
#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "core/error.h"
#include "features/online_features.h"

namespace th::animation {
SpeechFrames SpeechFrames::middleFrames(Eigen::Index first, Eigen::Index count) const {
  return {mfcc.middleCols(first, count), levelDb.segment(first, count)};
}

SpeechFrames speechFramesOf(const std::filesystem::path& recording) {
  return speechFramesOf(audio::readRecording(recording).samples);
}

SpeechFrames speechFramesOf(const features::FeatureMatrix& rows) {
  const int frames = rows.numFrames();
  const int numMfcc = rows.layout.numMfcc;
  SpeechFrames speech{Eigen::MatrixXd(numMfcc, frames), Eigen::RowVectorXd(frames)};
  for (int t = 0; t < frames; ++t) {
    const std::span<const float> row = rows.row(t);
    for (int k = 0; k < numMfcc; ++k)
      speech.mfcc(k, t) = row[static_cast<std::size_t>(features::FeatureLayout::kMfccBegin + k)];
    speech.levelDb[t] = rows.levelDb[static_cast<std::size_t>(t)];
  }
  return speech;
}

SpeechFrames speechFramesOf(std::span<const float> samples16k) {
  features::FeatureOptions options = features::batchFeatureOptions();
  options.contextFrames = 0;
  options.trackPitch = false;  // neither F0 nor the normalised energy is read: the level is
  options.energyNormalisation = features::EnergyNormalisation::kNone;
  features::OnlineFeatureExtractor extractor(options);
  extractor.acceptWaveform(samples16k);
  extractor.inputFinished();
  const int frames = extractor.numBaseFramesReady();
  const int numMfcc = extractor.layout().numMfcc;
  SpeechFrames speech{Eigen::MatrixXd(numMfcc, frames), Eigen::RowVectorXd(frames)};
  std::vector<float> mfcc(static_cast<std::size_t>(numMfcc));
  for (int t = 0; t < frames; ++t) {
    extractor.getMfcc(t, mfcc);
    for (int k = 0; k < numMfcc; ++k) speech.mfcc(k, t) = mfcc[static_cast<std::size_t>(k)];
    speech.levelDb[t] = extractor.getLevelDb(t);
  }
  return speech;
}

MouthRecording framesOf(const MouthRecording& take, int begin, int count) {
  if (begin < 0 || count < 0 || begin + count > take.numFrames()) throw Error("mouth data: frames out of range");
  MouthRecording part = take;
  part.visual = take.visual.middleCols(begin, count);
  part.speech = take.speech.middleFrames(begin, count);
  part.startSeconds = take.startSeconds + begin / take.framesPerSecond;
  return part;
}

}  // namespace th::animation
