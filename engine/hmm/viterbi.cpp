#include "hmm/viterbi.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace th::hmm {
namespace {

constexpr double kMinusInfinity = -std::numeric_limits<double>::infinity();

Eigen::MatrixXd logOf(const Eigen::MatrixXd& probabilities) {
  return probabilities.unaryExpr([](double p) { return p > 0.0 ? std::log(p) : kMinusInfinity; });
}

// δₜ(j) = maxᵢ δₜ₋₁(i) + log A(i,j), with its argmax.
void step(const Eigen::VectorXd& previous, const Eigen::MatrixXd& logTransition, Eigen::VectorXd& next,
          std::vector<int>& argmax) {
  const Eigen::Index n = previous.size();
  next.resize(n);
  argmax.assign(static_cast<size_t>(n), 0);
  for (Eigen::Index j = 0; j < n; ++j) {
    double best = kMinusInfinity;
    int from = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double value = previous[i] + logTransition(i, j);
      if (value > best) {
        best = value;
        from = static_cast<int>(i);
      }
    }
    next[j] = best;
    argmax[static_cast<size_t>(j)] = from;
  }
}

int argMax(const Eigen::VectorXd& values) {
  Eigen::Index best = 0;
  values.maxCoeff(&best);
  return static_cast<int>(best);
}

}  // namespace

ViterbiPath viterbi(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& logEmissions) {
  const Eigen::Index numFrames = logEmissions.cols();
  ViterbiPath path;
  if (numFrames == 0) return path;
  const Eigen::MatrixXd logTransition = logOf(model.transition);
  Eigen::VectorXd score = logOf(model.initial) + logEmissions.col(0);
  std::vector<std::vector<int>> back(static_cast<size_t>(numFrames));
  Eigen::VectorXd next;
  for (Eigen::Index t = 1; t < numFrames; ++t) {
    step(score, logTransition, next, back[static_cast<size_t>(t)]);
    score = next + logEmissions.col(t);
  }
  int state = argMax(score);
  path.logProbability = score[state];
  if (!std::isfinite(path.logProbability)) throw Error("Viterbi: the sequence is impossible under the model");
  path.states.resize(static_cast<size_t>(numFrames));
  for (Eigen::Index t = numFrames - 1; t >= 0; --t) {
    path.states[static_cast<size_t>(t)] = state;
    if (t > 0) state = back[static_cast<size_t>(t)][static_cast<size_t>(state)];
  }
  return path;
}

OnlineViterbi::OnlineViterbi(const HmmModel& model, const OnlineViterbiOptions& options)
    : logTransition_(logOf(model.transition)), logInitial_(logOf(model.initial)), options_(options) {}

void OnlineViterbi::decideFrom(long long frame, int stateAtFrame) {
  // Trace back from (frame, stateAtFrame) to the first undecided frame and emit those decisions in order.
  const long long first = static_cast<long long>(decided_.size());
  std::vector<int> states(static_cast<size_t>(frame - first + 1));
  int state = stateAtFrame;
  for (long long t = frame; t >= first; --t) {
    states[static_cast<size_t>(t - first)] = state;
    if (t > first) state = backPointers_[static_cast<size_t>(t - first)][static_cast<size_t>(state)];
  }
  for (size_t k = 0; k < states.size(); ++k) {
    decided_.push_back(states[k]);
    lags_.push_back(static_cast<int>(framesSeen_ - 1 - (first + static_cast<long long>(k))));
  }
  // Back-pointers of frames up to `frame` are no longer needed; the next frame becomes the first undecided.
  backPointers_.erase(backPointers_.begin(), backPointers_.begin() + (frame - first + 1));
}

void OnlineViterbi::acceptFrame(const Eigen::Ref<const Eigen::VectorXd>& logEmission) {
  if (finished_) throw Error("online Viterbi: acceptFrame after finish");
  if (framesSeen_ == 0) {
    score_ = logInitial_ + logEmission;
    backPointers_.emplace_back();  // frame 0 has no predecessor
  } else {
    Eigen::VectorXd next;
    std::vector<int> argmax;
    step(score_, logTransition_, next, argmax);
    score_ = next + logEmission;
    backPointers_.push_back(std::move(argmax));
  }
  ++framesSeen_;
  // Keep numbers bounded on endless streams; only differences matter.
  const double top = score_.maxCoeff();
  if (!std::isfinite(top)) throw Error("online Viterbi: the stream is impossible under the model");
  score_.array() -= top;

  // Convergence point: follow every surviving path back; where they all meet, everything before is settled.
  const long long first = static_cast<long long>(decided_.size());
  const long long latest = framesSeen_ - 1;
  std::vector<int> frontier;
  for (Eigen::Index j = 0; j < score_.size(); ++j) {
    if (std::isfinite(score_[j])) frontier.push_back(static_cast<int>(j));
  }
  long long meetFrame = -1;
  int meetState = -1;
  for (long long t = latest; t >= first; --t) {
    if (std::all_of(frontier.begin(), frontier.end(), [&](int s) { return s == frontier.front(); })) {
      meetFrame = t;
      meetState = frontier.front();
      break;
    }
    if (t == first) break;
    for (int& s : frontier) s = backPointers_[static_cast<size_t>(t - first)][static_cast<size_t>(s)];
    std::sort(frontier.begin(), frontier.end());
    frontier.erase(std::unique(frontier.begin(), frontier.end()), frontier.end());
  }
  if (meetFrame >= first) decideFrom(meetFrame, meetState);

  // Forced decision: no frame may wait longer than maxLagFrames.
  if (options_.maxLagFrames >= 0 && latest - static_cast<long long>(decided_.size()) >= options_.maxLagFrames) {
    const long long forced = latest - options_.maxLagFrames;
    int state = argMax(score_);
    for (long long t = latest; t > forced; --t) {
      state =
          backPointers_[static_cast<size_t>(t - static_cast<long long>(decided_.size()))][static_cast<size_t>(state)];
    }
    decideFrom(forced, state);
  }
}

void OnlineViterbi::finish() {
  if (finished_) return;
  finished_ = true;
  if (framesSeen_ > static_cast<long long>(decided_.size())) decideFrom(framesSeen_ - 1, argMax(score_));
}

}  // namespace th::hmm
