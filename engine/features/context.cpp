#include "features/context.h"

#include <string>

#include "core/error.h"

namespace th::features {

Eigen::MatrixXd stackContext(const Eigen::MatrixXd& frames, int contextFrames) {
  return stackContext(frames, contextFrames, contextFrames);
}

Eigen::MatrixXd stackContext(const Eigen::MatrixXd& frames, int pastFrames, int futureFrames) {
  ContextStacker stacker(frames.rows(), pastFrames, futureFrames);
  Eigen::MatrixXd stacked(stacker.outputDimension(), frames.cols());
  Eigen::VectorXd column;
  Eigen::Index done = 0;
  for (Eigen::Index t = 0; t < frames.cols(); ++t) {
    stacker.acceptFrame(frames.col(t));
    while (stacker.next(column)) stacked.col(done++) = column;
  }
  stacker.inputFinished();
  while (stacker.next(column)) stacked.col(done++) = column;
  return stacked;
}

ContextStacker::ContextStacker(Eigen::Index dimension, int contextFrames)
    : ContextStacker(dimension, contextFrames, contextFrames) {}

ContextStacker::ContextStacker(Eigen::Index dimension, int pastFrames, int futureFrames)
    : pastFrames_(pastFrames), futureFrames_(futureFrames) {
  if (pastFrames < 0 || futureFrames < 0) throw Error("context stacking: the context must be >= 0 frames");
  recent_.resize(dimension, pastFrames + futureFrames + 1);
}

void ContextStacker::acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& frame) {
  if (finished_) throw Error("context stacking: a frame after the input finished");
  if (frame.size() != recent_.rows())
    throw Error("context stacking: a frame of " + std::to_string(frame.size()) + " values; expected " +
                std::to_string(recent_.rows()));
  // The slot about to be written holds frame received_ - (past + future + 1), the first that a frame still to be
  // stacked may read.
  if (received_ - stacked_ > futureFrames_)
    throw Error("context stacking: a frame in before the ready ones were taken (call next() until it is false)");
  recent_.col(received_ % recent_.cols()) = frame;
  ++received_;
}

void ContextStacker::inputFinished() {
  finished_ = true;
}

bool ContextStacker::next(Eigen::VectorXd& stacked) {
  // Frame t's context reaches t + future; at the end, the last frame stands in for those after it.
  if (stacked_ >= received_ || (!finished_ && stacked_ + futureFrames_ >= received_)) return false;
  const Eigen::Index rows = recent_.rows();
  stacked.resize(outputDimension());
  for (int offset = -pastFrames_; offset <= futureFrames_; ++offset) {
    const Eigen::Index source = contextSource(stacked_, offset, received_);
    stacked.segment(rows * (offset + pastFrames_), rows) = recent_.col(source % recent_.cols());
  }
  ++stacked_;
  return true;
}

}  // namespace th::features
