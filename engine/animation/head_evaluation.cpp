#include "animation/head_evaluation.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace th::animation {
namespace {

void requireSameShape(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth) {
  if (predicted.rows() != 3 || truth.rows() != 3 || predicted.cols() != truth.cols() || truth.cols() < 2) {
    throw Error("head evaluation: need two 3 x T rotation sequences of the same length (T >= 2)");
  }
}

// Plain loops: GCC's -Wnull-dereference misreads Eigen's reductions over dynamic-size temporaries.
double mean(const Eigen::MatrixXd& m, Eigen::Index row) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < m.cols(); ++t) sum += m(row, t);
  return sum / static_cast<double>(m.cols());
}

double pearson(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, Eigen::Index row) {
  const double meanA = mean(a, row);
  const double meanB = mean(b, row);
  double xy = 0.0;
  double xx = 0.0;
  double yy = 0.0;
  for (Eigen::Index t = 0; t < a.cols(); ++t) {
    const double x = a(row, t) - meanA;
    const double y = b(row, t) - meanB;
    xy += x * y;
    xx += x * x;
    yy += y * y;
  }
  const double denominator = std::sqrt(xx * yy);
  return denominator > 0.0 ? xy / denominator : 0.0;
}

Eigen::Vector3d rowStd(const Eigen::MatrixXd& m) {
  Eigen::Vector3d result;
  for (Eigen::Index axis = 0; axis < 3; ++axis) {
    const double average = mean(m, axis);
    double sum = 0.0;
    for (Eigen::Index t = 0; t < m.cols(); ++t) sum += (m(axis, t) - average) * (m(axis, t) - average);
    result[axis] = std::sqrt(sum / static_cast<double>(m.cols()));
  }
  return result;
}

Eigen::MatrixXd steps(const Eigen::MatrixXd& m) { return m.rightCols(m.cols() - 1) - m.leftCols(m.cols() - 1); }

}  // namespace

double headError(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth) {
  requireSameShape(predicted, truth);
  double sum = 0.0;
  for (Eigen::Index t = 0; t < truth.cols(); ++t) {
    const double denominator = predicted.col(t).squaredNorm() + truth.col(t).squaredNorm();
    // Both exactly at the rest pose: a perfect frame.
    sum += denominator > 0.0 ? (predicted.col(t) - truth.col(t)).squaredNorm() / denominator : 0.0;
  }
  return sum / static_cast<double>(truth.cols());
}

double stepQuantile(const Eigen::MatrixXd& rotations, double quantile) {
  if (rotations.cols() < 2) throw Error("head evaluation: need at least 2 frames for steps");
  const Eigen::MatrixXd rotationSteps = steps(rotations);
  std::vector<double> sorted;
  for (Eigen::Index t = 0; t < rotationSteps.cols(); ++t) sorted.push_back(rotationSteps.col(t).norm());
  std::sort(sorted.begin(), sorted.end());
  const auto index = static_cast<size_t>(std::clamp(quantile, 0.0, 1.0) * static_cast<double>(sorted.size() - 1));
  return sorted[index];
}

HeadMetrics evaluateHead(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth, double jumpThreshold) {
  requireSameShape(predicted, truth);
  HeadMetrics metrics;
  metrics.error = headError(predicted, truth);
  for (int axis = 0; axis < 3; ++axis) {
    metrics.correlation[axis] = pearson(predicted, truth, axis);
  }
  metrics.poseStd = rowStd(predicted);
  metrics.truthPoseStd = rowStd(truth);
  metrics.velocityStd = rowStd(steps(predicted));
  metrics.truthVelocityStd = rowStd(steps(truth));
  const Eigen::MatrixXd predictedSteps = steps(predicted);
  int jumps = 0;
  for (Eigen::Index t = 0; t < predictedSteps.cols(); ++t) jumps += predictedSteps.col(t).norm() > jumpThreshold;
  metrics.jumpRate = static_cast<double>(jumps) / static_cast<double>(predictedSteps.cols());
  return metrics;
}

}  // namespace th::animation
