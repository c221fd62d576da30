#include "animation/head_measures.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/statistics.h"

namespace th::animation {
Eigen::Vector3d axisStd(const Eigen::MatrixXd& rotations) {
  Eigen::Vector3d result;
  for (Eigen::Index axis = 0; axis < 3; ++axis) result[axis] = standardDeviation(rotations.row(axis));
  return result;
}

double longestStep(const Eigen::MatrixXd& rotations) {
  if (rotations.cols() < 2) return 0.0;
  return (rotations.rightCols(rotations.cols() - 1) - rotations.leftCols(rotations.cols() - 1))
      .colwise()
      .norm()
      .maxCoeff();
}

HeadMotionStatistics motionStatistics(const Eigen::MatrixXd& rotations, const Eigen::RowVectorXd& pauses, double fps) {
  if (rotations.rows() != 3 || rotations.cols() < 2) throw Error("head motion: need a 3 x T motion with T >= 2");
  if (pauses.size() != 0 && pauses.size() != rotations.cols())
    throw Error("head motion: pauses and motion differ in length");
  HeadMotionStatistics statistics;
  std::vector<double> speeds;
  double pauseSum = 0.0, speechSum = 0.0;
  int pauseCount = 0, speechCount = 0;
  for (Eigen::Index t = 1; t < rotations.cols(); ++t) {
    const double speed = (rotations.col(t) - rotations.col(t - 1)).norm() * fps;
    speeds.push_back(speed);
    if (pauses.size() == 0) continue;
    // A step belongs to a pause when both its frames do.
    if (pauses[t] > 0.0 && pauses[t - 1] > 0.0) {
      pauseSum += speed;
      ++pauseCount;
    } else {
      speechSum += speed;
      ++speechCount;
    }
  }
  statistics.speedP95 = quantile(speeds, 0.95);
  statistics.speedP99 = quantile(speeds, 0.99);
  if (pauseCount > 0 && speechCount > 0 && speechSum > 0.0)
    statistics.pauseSpeechRatio = (pauseSum / pauseCount) / (speechSum / speechCount);
  statistics.poseStd = axisStd(rotations);
  return statistics;
}

Eigen::RowVectorXd pauseFrames(const Eigen::RowVectorXd& levelDb, double marginDb) {
  std::vector<double> levels(levelDb.data(), levelDb.data() + levelDb.size());
  const double loud = quantile(levels, 0.95);
  Eigen::RowVectorXd pauses(levelDb.size());
  for (Eigen::Index t = 0; t < levelDb.size(); ++t) pauses[t] = levelDb[t] < loud - marginDb ? 1.0 : 0.0;
  return pauses;
}

namespace {

// Each value smoothed by a Gaussian of sigma frames (edges: the edge value repeated).
std::vector<double> gaussianSmoothed(const std::vector<double>& values, double sigma) {
  const int reach = static_cast<int>(std::ceil(4.0 * sigma));
  std::vector<double> kernel;
  double total = 0.0;
  for (int k = -reach; k <= reach; ++k) total += kernel.emplace_back(std::exp(-0.5 * k * k / (sigma * sigma)));
  const int n = static_cast<int>(values.size());
  std::vector<double> out(values.size(), 0.0);
  for (int t = 0; t < n; ++t) {
    double sum = 0.0;
    for (int k = -reach; k <= reach; ++k)
      sum +=
          kernel[static_cast<std::size_t>(k + reach)] * values[static_cast<std::size_t>(std::clamp(t + k, 0, n - 1))];
    out[static_cast<std::size_t>(t)] = sum / total;
  }
  return out;
}

}  // namespace

std::vector<int> motionBeats(const Eigen::MatrixXd& rotations, double sigmaFrames) {
  // speed[t]: from frame t - 1 to frame t (Bailando's alignment); frame 0 takes frame 1's.
  if (rotations.cols() < 4) return {};
  std::vector<double> speed(static_cast<std::size_t>(rotations.cols()));
  for (Eigen::Index t = 1; t < rotations.cols(); ++t)
    speed[static_cast<std::size_t>(t)] = (rotations.col(t) - rotations.col(t - 1)).norm();
  speed[0] = speed[1];
  const std::vector<double> smooth = gaussianSmoothed(speed, sigmaFrames);
  std::vector<int> beats;
  for (std::size_t t = 1; t + 1 < smooth.size(); ++t)
    if (smooth[t] < smooth[t - 1] && smooth[t] < smooth[t + 1]) beats.push_back(static_cast<int>(t));
  return beats;
}

std::vector<int> speechBeats(const Eigen::RowVectorXd& levelDb, double minRiseDb, int minGapFrames) {
  std::vector<double> rise(static_cast<std::size_t>(levelDb.size()), 0.0);
  for (Eigen::Index t = 1; t < levelDb.size(); ++t)
    rise[static_cast<std::size_t>(t)] = std::max(0.0, levelDb[t] - levelDb[t - 1]);
  if (rise.size() < 3) return {};
  const std::vector<double> smooth = gaussianSmoothed(rise, 1.0);
  std::vector<int> beats;
  for (std::size_t t = 1; t + 1 < smooth.size(); ++t) {
    if (smooth[t] < minRiseDb || smooth[t] < smooth[t - 1] || smooth[t] <= smooth[t + 1]) continue;
    const int frame = static_cast<int>(t);
    if (!beats.empty() && frame - beats.back() < minGapFrames) {
      if (smooth[t] > smooth[static_cast<std::size_t>(beats.back())]) beats.back() = frame;  // the larger kept
      continue;
    }
    beats.push_back(frame);
  }
  return beats;
}

}  // namespace th::animation
