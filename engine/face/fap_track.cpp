#include "face/fap_track.h"

#include <algorithm>
#include <cmath>

namespace th::face {

int FapTrack::rowOf(int fap) const {
  const auto it = std::find(faps.begin(), faps.end(), fap);
  return it == faps.end() ? -1 : static_cast<int>(it - faps.begin());
}

FapFrame FapTrack::frame(int index) const {
  FapFrame frame{};
  for (std::size_t row = 0; row < faps.size(); ++row)
    frame[static_cast<std::size_t>(faps[row])] = values(static_cast<Eigen::Index>(row), index);
  return frame;
}

FapFrame FapTrack::at(double seconds) const {
  FapFrame frame{};
  if (numFrames() == 0) return frame;
  const double position = std::clamp(seconds * framesPerSecond, 0.0, static_cast<double>(numFrames() - 1));
  const int before = static_cast<int>(std::floor(position));
  const int after = std::min(before + 1, numFrames() - 1);
  const double blend = position - before;
  for (std::size_t row = 0; row < faps.size(); ++row) {
    const auto r = static_cast<Eigen::Index>(row);
    frame[static_cast<std::size_t>(faps[row])] = (1.0 - blend) * values(r, before) + blend * values(r, after);
  }
  return frame;
}

}  // namespace th::face
