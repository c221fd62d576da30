#include "video/animation_sampling.h"

#include <algorithm>
#include <cmath>

namespace th::video {

face::FapValues fapValuesAt(const Animation& animation, double seconds) {
  face::FapValues faps{};
  if (animation.numFrames() == 0) return faps;
  const double position = std::clamp(seconds * animation.framesPerSecond, 0.0, static_cast<double>(animation.numFrames() - 1));
  const int before = static_cast<int>(std::floor(position));
  const int after = std::min(before + 1, animation.numFrames() - 1);
  const double blend = position - before;
  for (std::size_t c = 0; c < animation.faps.size(); ++c) {
    const auto column = static_cast<Eigen::Index>(c);
    faps[static_cast<std::size_t>(animation.faps[c])] =
        (1.0 - blend) * animation.values(before, column) + blend * animation.values(after, column);
  }
  return faps;
}

double durationOf(const Animation& animation) { return animation.numFrames() / animation.framesPerSecond; }

}  // namespace th::video
