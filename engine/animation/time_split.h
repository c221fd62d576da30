// Splitting a take by time, and the "another segment" baseline, shared by the head and mouth evaluations.
//
//   auto [train, test] = th::animation::splitByTime(take, 0.75);   // a HeadRecording or a MouthRecording
//   int boundary = th::animation::trainingFrames(take.numFrames(), 0.75, "head data");  // frames [0, boundary) train
//   Eigen::MatrixXd other = th::animation::anotherSegment(prosody);   // the same frames, shifted by half their length
//
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"

namespace th::animation {

// round(fraction · numFrames); throws th::Error ("WHAT: the split leaves a part empty") if either part is empty.
inline int trainingFrames(int numFrames, double trainingFraction, const std::string& what) {
  const int boundary = static_cast<int>(std::lround(trainingFraction * numFrames));
  if (boundary < 1 || boundary >= numFrames) throw Error(what + ": the split leaves a part empty");
  return boundary;
}

// Frames [0, fraction·T) and [fraction·T, T) of a recording: any type with numFrames() and a framesOf(take,
// begin, count) found by argument-dependent lookup (head_data.h, mouth_data.h), whose frames carry their start
// time. Throws th::Error if either part is empty.
template <typename Recording>
std::pair<Recording, Recording> splitByTime(const Recording& take, double trainingFraction) {
  const int boundary = trainingFrames(take.numFrames(), trainingFraction, "the split by time");
  return {framesOf(take, 0, boundary), framesOf(take, boundary, take.numFrames() - boundary)};
}

// Input from another segment of the same speaker: the frames (one per column) rotated by half their length, so
// every frame meets input from elsewhere while the statistics stay the speaker's.
inline Eigen::MatrixXd anotherSegment(const Eigen::MatrixXd& frames) {
  const Eigen::Index half = frames.cols() / 2;
  Eigen::MatrixXd shifted(frames.rows(), frames.cols());
  shifted << frames.rightCols(frames.cols() - half), frames.leftCols(half);
  return shifted;
}

}  // namespace th::animation
