// Context stacking (Terissi & Gómez 2008, after Choi et al.): the audio vector of frame t is
// [a(t−tc) … a(t) … a(t+tc)], the earliest frame first, so the mouth model hears the co-articulation around
// each frame. Frames before the first and after the last repeat them. The streaming extractor's context columns
// (online_features.h), the mouth model's training and its live synthesiser all stack through this file.
//
//   Eigen::MatrixXd stacked = th::features::stackContext(mfcc, 3);   // batch: 11 x T in, 11·7 x T out
//
//   th::features::ContextStacker stacker(11, 3);                       // streaming, the same values
//   stacker.acceptFrame(mfcc.col(t));                                  // frames in order
//   Eigen::VectorXd out;
//   while (stacker.next(out)) use(out);                                // frame t once frame t + tc is in
//   th::features::ContextStacker past(11, 2, 0);                       // a(t−2), a(t−1), a(t): no wait
//   stacker.inputFinished();                                           // then the last tc frames
//
// Matrices hold one frame per column.
// Thread contract: pure functions; a ContextStacker belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace th::features {

// The frame that stands `offset` frames from frame t among frames [0, count): the edge frames repeat.
inline Eigen::Index contextSource(Eigen::Index t, int offset, Eigen::Index count) {
  return std::clamp<Eigen::Index>(t + offset, 0, count - 1);
}

// D x T in, D·(2 contextFrames + 1) x T out. Throws th::Error for contextFrames < 0.
Eigen::MatrixXd stackContext(const Eigen::MatrixXd& frames, int contextFrames);
// [a(t−past) … a(t) … a(t+future)]: D·(past + future + 1) x T. A live model that hears no future frames waits
// for none (its look-ahead is the features' alone).
Eigen::MatrixXd stackContext(const Eigen::MatrixXd& frames, int pastFrames, int futureFrames);

class ContextStacker {
 public:
  ContextStacker(Eigen::Index dimension, int contextFrames);  // throws th::Error for contextFrames < 0
  ContextStacker(Eigen::Index dimension, int pastFrames, int futureFrames);

  // `dimension` values. Only the last past + future + 1 frames are kept: take the ready frames (next() until false)
  // before the next one, or this throws th::Error.
  void acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& frame);
  void inputFinished();
  // The next stacked frame, in order, once its context has arrived (or the input has finished).
  bool next(Eigen::VectorXd& stacked);

  int pastFrames() const { return pastFrames_; }
  int futureFrames() const { return futureFrames_; }
  Eigen::Index outputDimension() const { return recent_.rows() * recent_.cols(); }

 private:
  int pastFrames_;
  int futureFrames_;
  Eigen::MatrixXd recent_;  // the last past + future + 1 frames, circular by frame number
  Eigen::Index received_ = 0;
  Eigen::Index stacked_ = 0;
  bool finished_ = false;
};

}  // namespace th::features
