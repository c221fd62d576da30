#include "animation/mouth_data.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "animation/time_split.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/numeric_csv.h"
#include "features/online_features.h"

namespace th::animation {
namespace {

constexpr int kExpressionCoefficients = 100;

}  // namespace

SpeechFrames SpeechFrames::middleFrames(Eigen::Index first, Eigen::Index count) const {
  return {mfcc.middleCols(first, count), levelDb.segment(first, count)};
}

SpeechFrames speechFramesOf(const std::filesystem::path& recording) {
  return speechFramesOf(audio::readRecording(recording).samples);
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

MouthRecording loadMouthRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                  const std::filesystem::path& expressionCsv) {
  const NumericTable pose = readNumericCsv(headPoseCsv);
  const NumericTable expressions = readNumericCsv(expressionCsv);
  const int jaw = pose.column("jaw_aa_x_deg");
  std::vector<int> columns;
  for (int k = 0; k < kExpressionCoefficients; ++k) columns.push_back(expressions.column("e" + std::to_string(k)));
  if (pose.rows.size() != expressions.rows.size()) {
    throw fileError(expressionCsv, "has " + std::to_string(expressions.rows.size()) + " frames, the head pose " +
                                       std::to_string(pose.rows.size()));
  }
  const SpeechFrames speech = speechFramesOf(wav);
  const int frames = std::min(static_cast<int>(pose.rows.size()), speech.numFrames());
  if (frames < 2) throw fileError(expressionCsv, "has fewer than 2 frames");
  MouthRecording take;
  take.visual.resize(1 + kExpressionCoefficients, frames);
  for (int t = 0; t < frames; ++t) {
    take.visual(0, t) = pose.rows[static_cast<size_t>(t)][static_cast<size_t>(jaw)];
    for (int k = 0; k < kExpressionCoefficients; ++k) {
      take.visual(1 + k, t) = expressions.rows[static_cast<size_t>(t)][static_cast<size_t>(columns[static_cast<size_t>(k)])];
    }
  }
  take.speech = speech.middleFrames(0, frames);
  return take;
}

MouthRecording loadBeat2Mouth() {
  return loadMouthRecording(sharedDataPath("beat2/2_scott_0_1_1.wav"),
                            sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"),
                            sharedDataPath("beat2/2_scott_0_1_1_flame_expr_30fps.csv"));
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
