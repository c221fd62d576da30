#include "features/context.h"

#include <string>

#include "core/error.h"

namespace th::features {

Eigen::MatrixXd stackContext(const Eigen::MatrixXd& frames, int contextFrames) {
  ContextStacker stacker(frames.rows(), contextFrames);
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

ContextStacker::ContextStacker(Eigen::Index dimension, int contextFrames) : contextFrames_(contextFrames) {
  if (contextFrames < 0) throw Error("context stacking: the context must be >= 0 frames");
  recent_.resize(dimension, 2 * contextFrames + 1);
}

void ContextStacker::acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& frame) {
  if (finished_) throw Error("context stacking: a frame after the input finished");
  if (frame.size() != recent_.rows())
    throw Error("context stacking: a frame of " + std::to_string(frame.size()) + " values; expected " +
                std::to_string(recent_.rows()));
  // The slot about to be written holds frame received_ - (2 tc + 1), the first that a frame still to be stacked
  // may read.
  if (received_ - stacked_ > contextFrames_)
    throw Error("context stacking: a frame in before the ready ones were taken (call next() until it is false)");
  recent_.col(received_ % recent_.cols()) = frame;
  ++received_;
}

void ContextStacker::inputFinished() {
  finished_ = true;
}

bool ContextStacker::next(Eigen::VectorXd& stacked) {
  // Frame t's context reaches t + tc; at the end, the last frame stands in for those after it.
  if (stacked_ >= received_ || (!finished_ && stacked_ + contextFrames_ >= received_)) return false;
  const Eigen::Index rows = recent_.rows();
  const int tc = contextFrames_;
  stacked.resize(outputDimension());
  for (int offset = -tc; offset <= tc; ++offset) {
    const Eigen::Index source = contextSource(stacked_, offset, received_);
    stacked.segment(rows * (offset + tc), rows) = recent_.col(source % recent_.cols());
  }
  ++stacked_;
  return true;
}

}  // namespace th::features
