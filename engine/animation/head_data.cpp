#include "animation/head_data.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "animation/time_split.h"
#include "core/error.h"

namespace th::animation {

Eigen::MatrixXd smoothFrames(const Eigen::MatrixXd& frames, double sigmaFrames) {
  const int radius = static_cast<int>(std::ceil(3.0 * sigmaFrames));
  std::vector<double> kernel(static_cast<size_t>(2 * radius + 1));
  for (int k = -radius; k <= radius; ++k)
    kernel[static_cast<size_t>(k + radius)] = std::exp(-0.5 * k * k / (sigmaFrames * sigmaFrames));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(frames.rows(), frames.cols());
  const Eigen::Index last = frames.cols() - 1;
  for (Eigen::Index t = 0; t <= last; ++t) {
    double weight = 0.0;
    for (int k = -radius; k <= radius; ++k) {
      const Eigen::Index u = std::clamp<Eigen::Index>(t + k, 0, last);  // the edge frame repeated
      out.col(t) += kernel[static_cast<size_t>(k + radius)] * frames.col(u);
      weight += kernel[static_cast<size_t>(k + radius)];
    }
    out.col(t) /= weight;
  }
  return out;
}

HeadRecording framesOf(const HeadRecording& take, int begin, int count) {
  if (begin < 0 || count < 0 || begin + count > take.numFrames()) throw Error("head data: frames out of range");
  HeadRecording part = take;
  part.rotations = take.rotations.middleCols(begin, count);
  part.prosody = take.prosody.middleCols(begin, count);
  part.voiced = take.voiced.segment(begin, count);
  part.levelDb = take.levelDb.segment(begin, count);
  part.startSeconds = take.startSeconds + begin / take.framesPerSecond;
  return part;
}

}  // namespace th::animation
