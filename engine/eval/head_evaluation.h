// How close synthesised head rotations come to the recorded ones, by the first source paper's error and by
// what a viewer notices: correlation, how much the head moves and how fast, and sudden jumps.
//
//   th::animation::HeadMetrics m = th::animation::evaluateHead(predicted, truth, jumpThreshold);
//
// Both are 3 x T (pitch, yaw, roll in degrees) relative to the same rest pose (the training mean), since the
// paper's error E = mean over frames of ‖x̂ − x‖² / (‖x̂‖² + ‖x‖²) is only meaningful for rotations measured
// from a rest pose: with absolute angles a constant prediction would score near 0. With this convention the
// constant rest pose scores exactly 1, and an unrelated motion of the right size scores about 1.
// What a viewer sees besides: the head's angular speed ‖Δ(pitch, yaw, roll)‖ in deg/s (its 95th percentile), how
// much slower it moves in pauses than in speech (a pause: a frame more than pauseMarginDb below the take's loud
// frames, their 95th percentile level), and how far the distribution of its motion lies from the truth's: the
// Fréchet distance between Gaussians fitted to 1 s windows of pose and velocity (frechetDistance), the measure
// gesture-generation work uses.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "animation/head_measures.h"

namespace th::eval {

// The Fréchet distance between the motions' window distributions: windows of windowFrames (hop 5 frames), each
// described by its pose (relative to the sequence's own mean) and its mean velocity (deg/s) over 6 equal parts
// (36 numbers); ‖μa − μb‖² + tr(Σa + Σb − 2(Σa Σb)^½). Throws th::Error if either is shorter than a window.
double frechetDistance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double fps, int windowFrames = 30);
// The same over the windows of several clips on each side.
double frechetDistance(const std::vector<Eigen::MatrixXd>& a, const std::vector<Eigen::MatrixXd>& b, double fps,
                       int windowFrames = 30);

// The baseline that has the truth's statistics but no voice: per axis an Ornstein-Uhlenbeck process (a random
// walk pulled back to 0) with the given pose std and frame-to-frame step std (degrees). 3 x numFrames.
Eigen::MatrixXd matchedRandomWalk(const Eigen::Vector3d& poseStd, const Eigen::Vector3d& stepStd, int numFrames,
                                  unsigned seed);

// Beat Align as SadTalker reports it (after Bailando, Siyao et al. 2022): the mean over the speech's beats of
// exp(−d² / 2σ²), d the frames from the beat to the nearest motion beat, σ = sigmaFrames (3 at 30 fps: 100 ms);
// 0 without motion beats. The beats: animation/head_measures.h's motionBeats and speechBeats.
double beatAlign(const std::vector<int>& speech, const std::vector<int>& motion, double sigmaFrames = 3.0);
// Beat Align by chance for the same beats: the mean over the speech's beats moved by 1, 1.5, 2, 2.5 and 3 s (at
// 30 fps; circularly within numFrames). Beat Align rises with the motion's beats per second whatever their
// timing; the excess over this says how much of it is timing.
double chanceBeatAlign(const std::vector<int>& speech, const std::vector<int>& motion, int numFrames,
                       double sigmaFrames = 3.0);

// Diversity as SadTalker reports it: how far the head's pose spreads over a clip, the mean over the axes of its
// standard deviation (degrees).
double poseDiversity(const Eigen::MatrixXd& rotations);

struct HeadMetrics {
  double error = 0.0;           // the paper's E
  Eigen::Vector3d correlation;  // per axis, Pearson (0 when either side is constant)
  Eigen::Vector3d poseStd;      // per axis, of the prediction (degrees)
  Eigen::Vector3d truthPoseStd;
  Eigen::Vector3d velocityStd;  // per axis, of the frame-to-frame step (degrees per frame)
  Eigen::Vector3d truthVelocityStd;
  double jumpRate = 0.0;  // fraction of steps whose length exceeds the jump threshold
};

// The paper's E alone.
double headError(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth);

// The length of the frame-to-frame rotation step (‖x_t − x_{t−1}‖) that the truth exceeds in (1 − quantile)
// of its steps: with quantile 0.99, its 99th percentile.
double stepQuantile(const Eigen::MatrixXd& rotations, double quantile);

HeadMetrics evaluateHead(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& truth, double jumpThreshold);

}  // namespace th::eval
