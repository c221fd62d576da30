#include "animation/animate.h"

#include <algorithm>
#include <map>

#include "animation/fap_mapping.h"
#include "animation/prosody.h"
#include "core/error.h"
#include "features/online_features.h"

namespace th::animation {

face::FapTrack animate(std::span<const float> samples16k, const HeadModel* head, const MouthModel* mouth,
                         const AnimateOptions& options) {
  if (head == nullptr && mouth == nullptr) throw Error("animate: neither a head nor a mouth model");
  if (mouth != nullptr && !drivesFaps(*mouth))
    throw Error("animate: the mouth model drives no FAPs (a sweep model?); make one with `talkinghead train mouth`");

  // FAP number → its curve; std::map keeps the columns in FAP order.
  std::map<int, Eigen::RowVectorXd> curves;
  Eigen::Index frames = -1;
  const auto add = [&](const std::vector<int>& numbers, const Eigen::MatrixXd& values) {
    frames = frames < 0 ? values.cols() : std::min(frames, values.cols());
    for (std::size_t i = 0; i < numbers.size(); ++i) curves[numbers[i]] = values.row(static_cast<Eigen::Index>(i));
  };
  if (head != nullptr) {
    const features::FeatureMatrix rows = features::computeFeatures(samples16k, prosodyFeatureOptions(kAnimationFramesPerSecond));
    const Eigen::MatrixXd prosody = prosodyOf(rows);
    if (prosody.cols() > 0) {
      const Eigen::MatrixXd rotations = synthesiseHead(*head, prosody, voicingOf(rows), options.head);
      add({kHeadFaps.begin(), kHeadFaps.end()}, headFaps(rotations));
    } else {
      frames = 0;
    }
  }
  const SpeechFrames speech = speechFramesOf(samples16k);
  if (mouth != nullptr) {
    if (speech.numFrames() > 0) {
      const Eigen::MatrixXd components = synthesiseMouth(*mouth, speech, options.mouth);
      add(mouthFapNumbers(*mouth), mouthFapsOf(*mouth, components));
    } else {
      frames = 0;
    }
  }
  if (frames <= 0) throw Error("animate: the recording is shorter than one animation frame");

  face::FapTrack animation;
  animation.framesPerSecond = kAnimationFramesPerSecond;
  animation.values.resize(static_cast<Eigen::Index>(curves.size()), frames);
  Eigen::Index column = 0;
  for (const auto& [number, curve] : curves) {
    animation.faps.push_back(number);
    animation.values.row(column++) = curve.head(frames);
  }
  if (options.idle) {
    Eigen::RowVectorXd level = Eigen::RowVectorXd::Constant(frames, -140.0);  // past the sound's end: silence
    const Eigen::Index known = std::min<Eigen::Index>(frames, speech.levelDb.size());
    level.head(known) = speech.levelDb.head(known);
    addIdleMotion(animation, level, options.idleOptions, {});
  }
  return animation;
}

}  // namespace th::animation
