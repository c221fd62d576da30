#include "pipeline/offline.h"

#include <algorithm>
#include <map>

#include "animation/fap_mapping.h"
#include "animation/online_stages.h"
#include "audio/media_audio.h"
#include "core/error.h"

namespace th::pipeline {
namespace {

// The articulation's classes as a stream decides them (LiveDecoder, the same stage): the network from the
// training speech's mean, the classes by the fixed-lag decoder.
face::VisemeTrack streamedVisemes(const animation::MouthNetwork& articulation, const animation::SpeechFrames& subframes,
                                  const AnimateOptions& options) {
  const animation::MouthNetworkOutput heard = animation::runMouthNetwork(articulation, subframes);
  animation::ArticulationVisemeStage stage(articulation, options.articulation, options.articulationLagFrames);
  animation::MouthNetworkFrame frame;
  for (int t = 0; t < heard.numFrames(); ++t) {
    frame.classes = heard.classes.col(t);
    frame.shut = heard.shut[t];
    stage.accept(frame);
  }
  stage.inputFinished();
  face::VisemeTrack track;
  track.posteriors.resize(face::kNumMouthClasses, stage.numFramesReady());
  animation::VisemeFrame shown;
  for (int t = 0; t < stage.numFramesReady(); ++t) {
    stage.getFrame(t, shown);
    track.posteriors.col(t) = shown.probabilities;
    track.classes.push_back(shown.mouthClass);
  }
  return track;
}

}  // namespace

face::FapTrack animate(std::span<const float> samples16k, const animation::HeadModel* head,
                       const animation::MouthModel* mouth, const AnimateOptions& options,
                       const animation::VisemeModel* visemes, const animation::MouthNetwork* articulation) {
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
  // The articulation's classes, one per animation frame (its frames are the subframes' thirds).
  face::VisemeTrack articulated;
  if (articulation != nullptr) {
    const animation::SpeechFrames subframes = animation::speechSubframesOf(samples16k);
    if (options.articulationLagFrames < 0) {
      const Eigen::VectorXd ownMean = subframes.mfcc.rowwise().mean();
      const animation::MouthNetworkOutput heardSounds = animation::runMouthNetwork(*articulation, subframes, &ownMean);
      articulated = animation::networkVisemes(*articulation, heardSounds.classes, options.articulation);
    } else {
      articulated = streamedVisemes(*articulation, subframes, options);
    }
    if (articulated.classes.empty()) throw Error("animate: the recording is too short for the articulation");
    // As many frames as the other parts: the last repeated where the subframes end early.
    articulated.posteriors.conservativeResize(Eigen::NoChange, frames);
    for (Eigen::Index t = static_cast<Eigen::Index>(articulated.classes.size()); t < frames; ++t)
      articulated.posteriors.col(t) = articulated.posteriors.col(t - 1);
    articulated.classes.resize(static_cast<std::size_t>(frames), articulated.classes.back());
  }
  if (mouth != nullptr) {
    const Eigen::MatrixXd components = animation::synthesiseMouth(*mouth, heard.speech, options.mouth);
    Eigen::MatrixXd faps = animation::mouthFapsOf(*mouth, components);
    const std::vector<int> numbers = animation::mouthFapNumbers(*mouth);
    if (articulation != nullptr) {
      animation::blendPhoneMouth(*articulation, articulated.posteriors, numbers, faps, options.articulation);
      animation::articulateLips(*articulation, articulated.classes, numbers, faps, options.articulation);
    }
    add(numbers, faps);
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
  if (articulation != nullptr)
    track.visemes = std::move(articulated);
  else if (visemes != nullptr)
    track.visemes = animation::decodeVisemes(*visemes, heard.speech);
  return track;
}

face::FapTrack animate(std::span<const float> samples16k, const AnimationModels& models,
                       const AnimateOptions& options) {
  return animate(samples16k, models.head.get(), models.mouth.get(), options, models.visemes.get(),
                 models.articulation.get());
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
