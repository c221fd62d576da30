#include "pipeline/offline.h"

#include <map>

#include "animation/fap_mapping.h"
#include "animation/recording_stages.h"
#include "audio/media_audio.h"
#include "core/error.h"

namespace th::pipeline {
namespace {

std::vector<animation::ProsodyFrame> prosodyFramesOf(const animation::SpeechAnalysis& heard) {
  std::vector<animation::ProsodyFrame> frames(static_cast<std::size_t>(heard.numFrames()));
  for (std::size_t t = 0; t < frames.size(); ++t) {
    frames[t].prosody = heard.prosody.col(static_cast<Eigen::Index>(t));
    frames[t].voiced = heard.voiced[static_cast<Eigen::Index>(t)] > 0.0;
  }
  return frames;
}

std::vector<animation::SpeechFrame> speechFramesOf(const animation::SpeechFrames& speech) {
  std::vector<animation::SpeechFrame> frames(static_cast<std::size_t>(speech.numFrames()));
  for (std::size_t t = 0; t < frames.size(); ++t) {
    frames[t].levelDb = speech.levelDb[static_cast<Eigen::Index>(t)];
    frames[t].mfcc = speech.mfcc.col(static_cast<Eigen::Index>(t));
  }
  return frames;
}

face::VisemeTrack visemeTrackOf(const std::vector<animation::VisemeFrame>& frames) {
  face::VisemeTrack track;
  track.posteriors.resize(face::kNumMouthClasses, static_cast<Eigen::Index>(frames.size()));
  for (std::size_t t = 0; t < frames.size(); ++t) {
    track.posteriors.col(static_cast<Eigen::Index>(t)) = frames[t].probabilities;
    track.classes.push_back(frames[t].mouthClass);
  }
  return track;
}

// The articulation's classes, one per animation frame (its frames are the subframes' thirds), as many as the
// other parts have: the last repeated where the subframes end early.
face::VisemeTrack articulatedVisemes(const animation::MouthNetwork& articulation, std::span<const float> samples16k,
                                     const AnimateOptions& options, Eigen::Index frames) {
  const bool wholeRecording = options.articulationLagFrames < 0;
  const auto network = animation::makeMouthNetworkStage(articulation, /*ownMean=*/wholeRecording);
  const auto classes =
      animation::makeArticulationVisemeStage(articulation, options.articulation, options.articulationLagFrames);
  const std::vector<animation::SpeechFrame> subframes = speechFramesOf(animation::speechSubframesOf(samples16k));
  face::VisemeTrack track = visemeTrackOf(animation::runToEnd(*classes, animation::runToEnd(*network, subframes)));
  if (track.classes.empty()) throw Error("animate: the recording is too short for the articulation");
  track.posteriors.conservativeResize(Eigen::NoChange, frames);
  for (Eigen::Index t = static_cast<Eigen::Index>(track.classes.size()); t < frames; ++t)
    track.posteriors.col(t) = track.posteriors.col(t - 1);
  track.classes.resize(static_cast<std::size_t>(frames), track.classes.back());
  return track;
}

}  // namespace

// The stages the live decoder runs, chosen by the options (animation/recording_stages.h): where an option asks for
// no bounded look-ahead, the batch decoder that hears the whole recording first.
face::FapTrack animate(std::span<const float> samples16k, const animation::HeadModel* head,
                       const animation::MouthModel* mouth, const AnimateOptions& options,
                       const animation::VisemeModel* visemes, const animation::MouthNetwork* articulation) {
  if (head == nullptr && mouth == nullptr) throw Error("animate: neither a head nor a mouth model");
  if (mouth != nullptr && !animation::drivesFaps(*mouth))
    throw Error("animate: the mouth model drives no FAPs (a sweep model?); make one with `talkinghead train mouth`");

  const animation::SpeechAnalysis heard = animation::analyseSpeech(samples16k);
  const Eigen::Index frames = heard.numFrames();
  if (frames <= 0) throw Error("animate: the recording is shorter than one animation frame");
  const std::vector<animation::SpeechFrame> speech = speechFramesOf(heard.speech);

  // FAP number → its curve; std::map keeps the rows in FAP order.
  std::map<int, Eigen::RowVectorXd> curves;
  const auto add = [&](const std::vector<int>& numbers, const Eigen::MatrixXd& values) {
    for (std::size_t i = 0; i < numbers.size(); ++i) curves[numbers[i]] = values.row(static_cast<Eigen::Index>(i));
  };
  if (head != nullptr) {
    const std::vector<animation::HeadFrame> decided =
        animation::runToEnd(*animation::makeHeadStage(*head, options.head), prosodyFramesOf(heard));
    Eigen::MatrixXd rotations(3, static_cast<Eigen::Index>(decided.size()));
    for (std::size_t t = 0; t < decided.size(); ++t)
      rotations.col(static_cast<Eigen::Index>(t)) = decided[t].rotationDegrees;
    add({animation::kHeadFaps.begin(), animation::kHeadFaps.end()}, animation::headFaps(rotations));
  }
  face::VisemeTrack articulated;
  if (articulation != nullptr) articulated = articulatedVisemes(*articulation, samples16k, options, frames);
  if (mouth != nullptr) {
    const std::vector<animation::MouthFrame> decided =
        animation::runToEnd(*animation::makeMouthStage(*mouth, options.mouth), speech);
    Eigen::MatrixXd components(decided.empty() ? 0 : decided.front().components.size(),
                               static_cast<Eigen::Index>(decided.size()));
    for (std::size_t t = 0; t < decided.size(); ++t)
      components.col(static_cast<Eigen::Index>(t)) = decided[t].components;
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
    track.visemes = visemeTrackOf(animation::runToEnd(*animation::makeVisemeStage(*visemes, -1), speech));
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
