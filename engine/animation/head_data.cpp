#include "animation/head_data.h"

#include <algorithm>
#include <cmath>

#include "audio/audio_file.h"
#include "animation/time_split.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/numeric_csv.h"

namespace th::animation {

HeadRecording loadHeadRecording(const std::filesystem::path& wav, const std::filesystem::path& headPoseCsv,
                                const ProsodyOptions& prosody) {
  const NumericTable pose = readNumericCsv(headPoseCsv);
  const int pitch = pose.column("neckhead_pitch_deg");
  const int yaw = pose.column("neckhead_yaw_deg");
  const int roll = pose.column("neckhead_roll_deg");
  if (pose.rows.size() < 2) throw fileError(headPoseCsv, "has fewer than 2 frames of head pose");

  const audio::AudioClip clip = audio::readAudioFile(wav);
  const features::FeatureMatrix features = features::computeFeatures(clip.samples, prosodyFeatureOptions(30.0));
  const Eigen::MatrixXd allProsody = prosodyOf(features, prosody);

  HeadRecording take;
  const int frames = std::min(static_cast<int>(pose.rows.size()), static_cast<int>(allProsody.cols()));
  take.rotations.resize(3, frames);
  for (int t = 0; t < frames; ++t) {
    const auto& row = pose.rows[static_cast<size_t>(t)];
    take.rotations.col(t) << row[static_cast<size_t>(pitch)], row[static_cast<size_t>(yaw)], row[static_cast<size_t>(roll)];
  }
  take.prosody = allProsody.leftCols(frames);
  return take;
}

HeadRecording loadBeat2Head(const ProsodyOptions& prosody) {
  return loadHeadRecording(sharedDataPath("beat2/2_scott_0_1_1.wav"),
                           sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"), prosody);
}

std::pair<HeadRecording, HeadRecording> splitByTime(const HeadRecording& take, double trainingFraction) {
  const int boundary = trainingFrames(take.numFrames(), trainingFraction, "head data");
  HeadRecording train = take;
  HeadRecording test = take;
  train.rotations = take.rotations.leftCols(boundary);
  train.prosody = take.prosody.leftCols(boundary);
  test.rotations = take.rotations.rightCols(take.numFrames() - boundary);
  test.prosody = take.prosody.rightCols(take.numFrames() - boundary);
  test.startSeconds = take.startSeconds + boundary / take.framesPerSecond;
  return {train, test};
}

}  // namespace th::animation
