#include "avatar/avatar_input.h"

#include <algorithm>
#include <cmath>

#include "formats/arkit_format.h"

namespace th::avatar {

AvatarInput avatarInputOf(const face::FapFrame& faps, const float* classProbabilities) {
  AvatarInput input;
  face::FapTrack track;
  track.values.resize(face::kNumFaps, 1);
  for (int fap = 1; fap <= face::kNumFaps; ++fap) {
    track.faps.push_back(fap);
    track.values(fap - 1, 0) = faps[static_cast<std::size_t>(fap)];
  }
  const Eigen::MatrixXd weights = formats::arkitWeights(track, formats::ArkitScale{});
  for (std::size_t k = 0; k < input.arkit.size(); ++k)
    input.arkit[k] = static_cast<float>(weights(static_cast<Eigen::Index>(k), 0));
  input.headDegrees = face::headDegreesOf(faps);
  if (classProbabilities != nullptr) {
    Eigen::VectorXd classes(face::kNumMouthClasses);
    for (int c = 0; c < face::kNumMouthClasses; ++c) classes[c] = classProbabilities[c];
    const Eigen::VectorXd oculus = face::oculusWeights(classes), vrm = face::vrmWeights(classes);
    for (int k = 0; k < face::kNumOculusVisemes; ++k)
      input.oculus[static_cast<std::size_t>(k)] = static_cast<float>(oculus[k]);
    for (int k = 0; k < 5; ++k) input.vrm[static_cast<std::size_t>(k)] = static_cast<float>(vrm[k]);
    input.hasVisemes = true;
  }
  return input;
}

AvatarInput avatarInputAt(const face::FapTrack& animation, double seconds) {
  if (animation.visemes.empty()) return avatarInputOf(animation.at(seconds), nullptr);
  const Eigen::MatrixXd& posteriors = animation.visemes.posteriors;
  const auto frame = std::clamp(static_cast<Eigen::Index>(std::lround(seconds * animation.visemes.framesPerSecond)),
                                Eigen::Index{0}, posteriors.cols() - 1);
  std::array<float, face::kNumMouthClasses> classes{};
  for (int c = 0; c < face::kNumMouthClasses && c < posteriors.rows(); ++c)
    classes[static_cast<std::size_t>(c)] = static_cast<float>(posteriors(c, frame));
  return avatarInputOf(animation.at(seconds), classes.data());
}

}  // namespace th::avatar
