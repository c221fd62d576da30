// What a viewer sees of a head's motion, measured on 3 x T rotations (pitch, yaw, roll in degrees) beside the
// level of the speech it goes with: how fast it moves, how much it moves in pauses against speech, how far it
// spreads, and its beats (where one movement ends and the next begins). The evaluation (eval/head_evaluation.h)
// scores models with these, and a head style (head_style.h) is fitted to them.
//
//   const Eigen::RowVectorXd pauses = th::animation::pauseFrames(take.levelDb);
//   const th::animation::HeadMotionStatistics s = th::animation::motionStatistics(take.rotations, pauses, 30.0);
//
// A pause is a frame more than marginDb below the take's loud frames (the 95th percentile of its level).
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace th::animation {

struct HeadMotionStatistics {
  double speedP95 = 0.0;          // deg/s
  double speedP99 = 0.0;          // deg/s: a step longer than this is what eval head counts as a jump
  double pauseSpeechRatio = 0.0;  // mean speed in pauses / in speech (0 without pauses or speech)
  Eigen::Vector3d poseStd = Eigen::Vector3d::Zero();
};

// Per axis, the standard deviation over the frames (degrees): how far the head spreads.
Eigen::Vector3d axisStd(const Eigen::MatrixXd& rotations);

// The longest frame-to-frame step of 3 x T rotations, degrees (0 with fewer than two frames): a step longer than
// the person's longest is what a viewer sees as a jump.
double longestStep(const Eigen::MatrixXd& rotations);

// pauses: T, 1 in a pause (pauseFrames); empty: no pauses known. fps: frames per second.
HeadMotionStatistics motionStatistics(const Eigen::MatrixXd& rotations, const Eigen::RowVectorXd& pauses, double fps);

// 1 where the level is more than marginDb below the 95th percentile of levelDb, else 0.
Eigen::RowVectorXd pauseFrames(const Eigen::RowVectorXd& levelDb, double marginDb = 30.0);

// Motion beats: the local minima of the head's angular speed ‖Δ(pitch, yaw, roll)‖ smoothed by a Gaussian of
// sigmaFrames (where one movement ends and the next begins). Speech beats: onsets, the peaks of the level's rise
// (its frame-to-frame increase, half-wave rectified, smoothed by a Gaussian of one frame) of at least minRiseDb,
// at least minGapFrames apart (the larger kept): syllables that start loud, stressed ones and phrase starts, as
// an onset detector marks them.
std::vector<int> motionBeats(const Eigen::MatrixXd& rotations, double sigmaFrames = 5.0);
std::vector<int> speechBeats(const Eigen::RowVectorXd& levelDb, double minRiseDb = 2.0, int minGapFrames = 6);

}  // namespace th::animation
