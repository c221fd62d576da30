#include "eval/head_evaluation.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "animation/head_measures.h"
#include "core/error.h"
#include "core/statistics.h"

namespace th::eval {
namespace {

void requireSameShape(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth) {
  if (predicted.rows() != 3 || truth.rows() != 3 || predicted.cols() != truth.cols() || truth.cols() < 2) {
    throw Error("head evaluation: need two 3 x T rotation sequences of the same length (T >= 2)");
  }
}

Eigen::MatrixXd steps(const Eigen::MatrixXd& m) {
  return m.rightCols(m.cols() - 1) - m.leftCols(m.cols() - 1);
}

// The symmetric square root of a symmetric positive semi-definite matrix (negative round-off clipped).
Eigen::MatrixXd symmetricSqrt(const Eigen::MatrixXd& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(0.5 * (m + m.transpose()));
  const Eigen::VectorXd roots = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return solver.eigenvectors() * roots.asDiagonal() * solver.eigenvectors().transpose();
}

// One row per window: the pose at 6 equally spaced frames and the mean velocity over the 6 parts.
Eigen::MatrixXd windowFeatures(const Eigen::MatrixXd& rotations, double fps, int windowFrames) {
  constexpr int kParts = 6;
  constexpr int kHop = 5;
  if (rotations.cols() < windowFrames || windowFrames < kParts)
    throw Error("head evaluation: a motion shorter than one window (" + std::to_string(windowFrames) + " frames)");
  const Eigen::MatrixXd centred = rotations.colwise() - rotations.rowwise().mean();
  const Eigen::Index windows = (rotations.cols() - windowFrames) / kHop + 1;
  Eigen::MatrixXd features(windows, 2 * 3 * kParts);
  const int partFrames = windowFrames / kParts;
  for (Eigen::Index w = 0; w < windows; ++w) {
    const Eigen::Index begin = w * kHop;
    for (int part = 0; part < kParts; ++part) {
      const Eigen::Index first = begin + part * partFrames;
      const Eigen::Index last = std::min<Eigen::Index>(first + partFrames, rotations.cols() - 1);
      features.block<1, 3>(w, 3 * part) = centred.col(first).transpose();
      features.block<1, 3>(w, 3 * (kParts + part)) = ((centred.col(last) - centred.col(first)) * fps /
                                                      static_cast<double>(std::max<Eigen::Index>(1, last - first)))
                                                         .transpose();
    }
  }
  return features;
}

}  // namespace

double frechetDistance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double fps, int windowFrames) {
  return frechetDistance(std::vector<Eigen::MatrixXd>{a}, std::vector<Eigen::MatrixXd>{b}, fps, windowFrames);
}

double frechetDistance(const std::vector<Eigen::MatrixXd>& a, const std::vector<Eigen::MatrixXd>& b, double fps,
                       int windowFrames) {
  const auto stacked = [&](const std::vector<Eigen::MatrixXd>& clips) {
    std::vector<Eigen::MatrixXd> parts;
    Eigen::Index rows = 0;
    for (const auto& clip : clips) {
      parts.push_back(windowFeatures(clip, fps, windowFrames));
      rows += parts.back().rows();
    }
    if (parts.empty()) throw Error("head evaluation: no motion for the Fréchet distance");
    Eigen::MatrixXd all(rows, parts.front().cols());
    Eigen::Index row = 0;
    for (const auto& part : parts) {
      all.middleRows(row, part.rows()) = part;
      row += part.rows();
    }
    return all;
  };
  const Eigen::MatrixXd fa = stacked(a);
  const Eigen::MatrixXd fb = stacked(b);
  const Eigen::RowVectorXd ma = fa.colwise().mean();
  const Eigen::RowVectorXd mb = fb.colwise().mean();
  const Eigen::MatrixXd ca = fa.rowwise() - ma;
  const Eigen::MatrixXd cb = fb.rowwise() - mb;
  const Eigen::MatrixXd sa = ca.transpose() * ca / static_cast<double>(std::max<Eigen::Index>(1, fa.rows() - 1));
  const Eigen::MatrixXd sb = cb.transpose() * cb / static_cast<double>(std::max<Eigen::Index>(1, fb.rows() - 1));
  const Eigen::MatrixXd rootA = symmetricSqrt(sa);
  const double crossTrace = symmetricSqrt(rootA * sb * rootA).trace();
  return std::max(0.0, (ma - mb).squaredNorm() + sa.trace() + sb.trace() - 2.0 * crossTrace);
}

Eigen::MatrixXd matchedRandomWalk(const Eigen::Vector3d& poseStd, const Eigen::Vector3d& stepStd, int numFrames,
                                  unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd out(3, std::max(0, numFrames));
  for (int axis = 0; axis < 3; ++axis) {
    // x_t = a x_{t-1} + σ ε: stationary std s = σ / √(1 − a²), step std √(2(1 − a)) s.
    const double s = std::max(poseStd[axis], 1e-9);
    const double a = std::clamp(1.0 - stepStd[axis] * stepStd[axis] / (2.0 * s * s), -0.999, 0.99999);
    const double sigma = s * std::sqrt(1.0 - a * a);
    double x = s * normal(random);
    for (int t = 0; t < numFrames; ++t) {
      if (t > 0) x = a * x + sigma * normal(random);
      out(axis, t) = x;
    }
  }
  return out;
}

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
    metrics.correlation[axis] = pearsonCorrelation(predicted.row(axis), truth.row(axis));
  }
  metrics.poseStd = animation::axisStd(predicted);
  metrics.truthPoseStd = animation::axisStd(truth);
  metrics.velocityStd = animation::axisStd(steps(predicted));
  metrics.truthVelocityStd = animation::axisStd(steps(truth));
  const Eigen::MatrixXd predictedSteps = steps(predicted);
  int jumps = 0;
  for (Eigen::Index t = 0; t < predictedSteps.cols(); ++t) jumps += predictedSteps.col(t).norm() > jumpThreshold;
  metrics.jumpRate = static_cast<double>(jumps) / static_cast<double>(predictedSteps.cols());
  return metrics;
}

double beatAlign(const std::vector<int>& speech, const std::vector<int>& motion, double sigmaFrames) {
  if (speech.empty() || motion.empty()) return 0.0;
  double sum = 0.0;
  for (const int beat : speech) {
    int nearest = std::numeric_limits<int>::max();
    for (const int m : motion) nearest = std::min(nearest, std::abs(m - beat));
    sum += std::exp(-static_cast<double>(nearest) * nearest / (2.0 * sigmaFrames * sigmaFrames));
  }
  return sum / static_cast<double>(speech.size());
}

double chanceBeatAlign(const std::vector<int>& speech, const std::vector<int>& motion, int numFrames,
                       double sigmaFrames) {
  if (numFrames <= 0) return 0.0;
  constexpr int kShifts[] = {30, 45, 60, 75, 90};
  double sum = 0.0;
  for (const int shift : kShifts) {
    std::vector<int> moved;
    moved.reserve(speech.size());
    for (const int beat : speech) moved.push_back((beat + shift) % numFrames);
    sum += beatAlign(moved, motion, sigmaFrames);
  }
  return sum / static_cast<double>(std::size(kShifts));
}

double poseDiversity(const Eigen::MatrixXd& rotations) {
  if (rotations.cols() < 2) return 0.0;
  const Eigen::MatrixXd centred = rotations.colwise() - rotations.rowwise().mean();
  return (centred.rowwise().squaredNorm() / static_cast<double>(rotations.cols() - 1)).cwiseSqrt().mean();
}

}  // namespace th::eval
