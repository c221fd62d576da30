#include "pipeline/offline.h"

#include <algorithm>
#include <map>

#include "animation/fap_mapping.h"
#include "audio/media_audio.h"
#include "core/error.h"

namespace th::pipeline {

face::FapTrack animate(std::span<const float> samples16k, const animation::HeadModel* head,
                       const animation::MouthModel* mouth, const AnimateOptions& options,
                       const animation::VisemeModel* visemes) {
  if (head == nullptr && mouth == nullptr) throw Error("animate: neither a head nor a mouth model");
  if (mouth != nullptr && !animation::drivesFaps(*mouth))
    throw Error("animate: the mouth model drives no FAPs (a sweep model?); make one with `talkinghead train mouth`");

  const animation::SpeechAnalysis heard = animation::analyseSpeech(samples16k);
  const Eigen::Index frames = heard.numFrames();
  if (frames <= 0) throw Error("animate: the recording is shorter than one animation frame");

  // FAP number → its curve; std::map keeps the rows in FAP order.
  std::map<int, Eigen::RowVectorXd> curves;
  const auto add = [&](const std::vector<int>& numbers, const Eigen::MatrixXd& values) {
    for (std::size_t i = 0; i < numbers.size(); ++i) curves[numbers[i]] = values.row(static_cast<Eigen::Index>(i));
  };
  if (head != nullptr) {
    const Eigen::MatrixXd rotations = animation::synthesiseHead(*head, heard.prosody, heard.voiced, options.head);
    add({animation::kHeadFaps.begin(), animation::kHeadFaps.end()}, animation::headFaps(rotations));
  }
  if (mouth != nullptr) {
    const Eigen::MatrixXd components = animation::synthesiseMouth(*mouth, heard.speech, options.mouth);
    add(animation::mouthFapNumbers(*mouth), animation::mouthFapsOf(*mouth, components));
  }

  face::FapTrack track;
  track.framesPerSecond = animation::kAnimationFramesPerSecond;
  track.values.resize(static_cast<Eigen::Index>(curves.size()), frames);
  Eigen::Index row = 0;
  for (const auto& [number, curve] : curves) {
    track.faps.push_back(number);
    track.values.row(row++) = curve.head(frames);
  }
  if (options.idle) animation::addIdleMotion(track, heard.speech.levelDb, options.idleOptions, {});
  if (visemes != nullptr) track.visemes = animation::decodeVisemes(*visemes, heard.speech);
  return track;
}

face::FapTrack animate(std::span<const float> samples16k, const AnimationModels& models,
                       const AnimateOptions& options) {
  return animate(samples16k, models.head.get(), models.mouth.get(), options, models.visemes.get());
}

face::FapTrack animateRecording(const std::filesystem::path& recording, const AnimationModels& models,
                                const AnimateOptions& options, audio::AudioClip* clip) {
  audio::AudioClip sound = audio::readRecording(recording);
  if (sound.samples.empty()) throw fileError(recording, "has no samples");
  face::FapTrack track;
  try {
    track = animate(sound.samples, models, options);
  } catch (const Error& error) {
    throw fileError(recording, error.what());
  }
  track.name = recording.stem().string();
  track.source = std::filesystem::absolute(recording).lexically_normal().string();
  if (clip != nullptr) *clip = std::move(sound);
  return track;
}

}  // namespace th::pipeline
