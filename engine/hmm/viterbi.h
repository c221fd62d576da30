// The most likely state sequence: batch Viterbi, and online Viterbi that emits each frame's state as soon as
// every surviving path agrees on it (the convergence point), or when a maximum lag forces a decision.
//
//   std::vector<int> path = th::hmm::viterbi(model, logEmissions).states;
//
//   th::hmm::OnlineViterbi decoder(model, {.maxLagFrames = 10});
//   decoder.acceptFrame(logEmissions.col(t));        // one frame's log bⱼ(xₜ), N values
//   while (decoder.numDecided() > next) use(decoder.state(next++));
//   decoder.finish();                                // decides the rest from the best final state
//
// Online decoding keeps back-pointers only for undecided frames. With an unbounded lag (maxLagFrames < 0) the
// online path equals the batch path exactly: a frame is emitted only when all surviving paths share it, and the
// rest is traced back from the best final state as the batch decoder does. With a finite lag, a forced
// decision takes the state on the currently best path; later frames are decoded as usual.
// Thread contract: viterbi() is a pure function; an OnlineViterbi belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

#include "core/frame_store.h"
#include "hmm/hmm_model.h"

namespace th::hmm {

struct ViterbiPath {
  std::vector<int> states;
  double logProbability = 0.0;  // of the best path and the observations
};

ViterbiPath viterbi(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions);

struct OnlineViterbiOptions {
  int maxLagFrames = -1;  // < 0: unbounded (decide only at convergence points and at the end)
};

class OnlineViterbi {
 public:
  OnlineViterbi(const HmmModel& model, const OnlineViterbiOptions& options);

  void acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& logEmission);
  void finish();

  int numFramesSeen() const { return static_cast<int>(framesSeen_); }
  int numDecided() const { return static_cast<int>(decided_.size()); }
  int state(int frame) const { return decided_[static_cast<size_t>(frame)]; }
  // How many frames later a decided frame was decided (0 = at once).
  int decisionLag(int frame) const { return lags_[static_cast<size_t>(frame)]; }
  // Decided frames before `frame` will not be read again (state, decisionLag): they are freed.
  void forgetBefore(int frame) {
    decided_.forgetBefore(static_cast<size_t>(std::max(0, frame)));
    lags_.forgetBefore(static_cast<size_t>(std::max(0, frame)));
  }
  std::size_t framesHeld() const { return decided_.held(); }

 private:
  void decideFrom(long long frame, int stateAtFrame);

  Eigen::MatrixXd logTransition_;
  Eigen::VectorXd logInitial_;
  OnlineViterbiOptions options_;
  Eigen::VectorXd score_;                       // δ for the latest frame
  std::vector<std::vector<int>> backPointers_;  // [k]: frame firstUndecided + k → its best predecessor
  long long framesSeen_ = 0;
  FrameStore<int> decided_;
  FrameStore<int> lags_;
  bool finished_ = false;
};

}  // namespace th::hmm
