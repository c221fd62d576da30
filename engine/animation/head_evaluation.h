// How close synthesised head rotations come to the recorded ones, by the first source paper's error and by
// what a viewer notices: correlation, how much the head moves and how fast, and sudden jumps.
//
//   th::animation::HeadMetrics m = th::animation::evaluateHead(predicted, truth, jumpThreshold);
//
// Both are 3 x T (pitch, yaw, roll in degrees) relative to the same rest pose (the training mean), since the
// paper's error E = mean over frames of ‖x̂ − x‖² / (‖x̂‖² + ‖x‖²) is only meaningful for rotations measured
// from a rest pose: with absolute angles a constant prediction would score near 0. With this convention the
// constant rest pose scores exactly 1, and an unrelated motion of the right size scores about 1.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>

namespace th::animation {

struct HeadMetrics {
  double error = 0.0;                 // the paper's E
  Eigen::Vector3d correlation;        // per axis, Pearson (0 when either side is constant)
  Eigen::Vector3d poseStd;            // per axis, of the prediction (degrees)
  Eigen::Vector3d truthPoseStd;
  Eigen::Vector3d velocityStd;        // per axis, of the frame-to-frame step (degrees per frame)
  Eigen::Vector3d truthVelocityStd;
  double jumpRate = 0.0;              // fraction of steps whose length exceeds the jump threshold
};

// The paper's E alone.
double headError(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth);

// The length of the frame-to-frame rotation step (‖x_t − x_{t−1}‖) that the truth exceeds in (1 − quantile)
// of its steps: with quantile 0.99, its 99th percentile.
double stepQuantile(const Eigen::MatrixXd& rotations, double quantile);

HeadMetrics evaluateHead(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth, double jumpThreshold);

}  // namespace th::animation
