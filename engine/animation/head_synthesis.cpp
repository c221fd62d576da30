#include <algorithm>
#include <memory>
#include <vector>

#include "animation/head_model.h"
#include "animation/head_states.h"
#include "core/error.h"
#include "core/frame_store.h"
#include "hmm/forward_backward.h"
#include "hmm/forward_filter.h"
#include "hmm/viterbi.h"

namespace th::animation {
namespace {

// The rest pose added to rotations (none added when it is zero: that would turn a -0 into 0, and a file's text
// with it).
Eigen::MatrixXd rotationsAtRest(Eigen::MatrixXd rotations, const Eigen::Vector3d& restPose) {
  if (!restPose.isZero(0.0)) rotations.colwise() += restPose;
  return rotations;
}

Eigen::Vector3d rotationAtRest(const Eigen::Vector3d& rotation, const Eigen::Vector3d& restPose) {
  return restPose.isZero(0.0) ? rotation : Eigen::Vector3d(rotation + restPose);
}

// Shortens each frame-to-frame step longer than the options' maxStepDegrees (times the amplitude) to that length,
// frame by frame as they come, so the batch and the online synthesis limit alike.
class StepLimiter {
 public:
  StepLimiter() = default;  // no limit
  explicit StepLimiter(double limit) : limit_(limit) {}
  explicit StepLimiter(const HeadSynthesisOptions& options) : StepLimiter(options.maxStepDegrees * options.amplitude) {}

  Eigen::Vector3d next(const Eigen::Vector3d& rotation) {
    if (limit_ <= 0.0) return rotation;
    if (started_) {
      const Eigen::Vector3d step = rotation - last_;
      const double length = step.norm();
      last_ = length > limit_ ? Eigen::Vector3d(last_ + step * (limit_ / length)) : rotation;
    } else {
      last_ = rotation;
      started_ = true;
    }
    return last_;
  }

  void apply(Eigen::MatrixXd& rotations) {
    if (limit_ <= 0.0) return;
    for (Eigen::Index t = 0; t < rotations.cols(); ++t) rotations.col(t) = next(rotations.col(t));
  }

 private:
  double limit_ = 0.0;
  bool started_ = false;
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
};

}  // namespace

void limitHeadSteps(Eigen::MatrixXd& rotations, double maxStepDegrees) {
  StepLimiter(maxStepDegrees).apply(rotations);
}

Eigen::MatrixXd synthesiseHead(const HeadModel& model, const Eigen::MatrixXd& prosody, const Eigen::RowVectorXd& voiced,
                               const HeadSynthesisOptions& options) {
  if (prosody.rows() != ProsodyTracker::kDimension) throw Error("head synthesis: prosody must have 4 rows");
  if (voiced.size() != 0 && voiced.size() != prosody.cols())
    throw Error("head synthesis: voicing and prosody differ in length");
  if (prosody.cols() == 0) return Eigen::MatrixXd(3, 0);
  if (options.maxLagFrames >= 0) {
    HeadSynthesiser online(model, options);
    for (Eigen::Index t = 0; t < prosody.cols(); ++t)
      online.acceptProsody(prosody.col(t), voiced.size() == 0 || voiced[t] > 0.0);
    online.finish();
    Eigen::MatrixXd out(3, prosody.cols());
    for (int t = 0; t < online.numReady(); ++t) out.col(t) = online.rotation(t);
    return out;
  }
  const hmm::HmmModel decoder = prosodyModel(model);
  const StateTables tables = tablesOf(model, options.smoothing);
  const Eigen::MatrixXd logB = gatedEmissions(decoder, prosody, voiced, options.voicedOnly);
  const Eigen::Vector3d scale = outputScale(model, options);
  Eigen::MatrixXd out;
  if (options.variant == HeadVariant::kPosteriorMeans) {
    out = scale.asDiagonal() * (tables.poseMeans * hmm::forwardBackward(decoder, logB).stateGivenAll);
  } else {
    const std::vector<int> states = hmm::viterbi(decoder, logB).states;
    if (options.variant == HeadVariant::kTrajectory) {
      out = trajectoryFor(tables, states, 0, states.size());
      ResidualMotion residual(model, options);
      for (Eigen::Index t = 0; t < out.cols(); ++t) out.col(t) += residual.next(voiced.size() == 0 || voiced[t] > 0.0);
      out = scale.asDiagonal() * out;
    } else {
      out.resize(3, prosody.cols());
      for (size_t t = 0; t < states.size(); ++t)
        out.col(static_cast<Eigen::Index>(t)) = scale.cwiseProduct(tables.poseMean[static_cast<size_t>(states[t])]);
    }
  }
  StepLimiter(options).apply(out);
  return rotationsAtRest(std::move(out), options.restPose);
}

struct HeadSynthesiser::Impl {
  HeadSynthesisOptions options;
  HeadModel model;
  hmm::HmmModel decoder;
  StateTables tables;
  std::unique_ptr<hmm::OnlineViterbi> viterbi;
  std::unique_ptr<hmm::FixedLagSmoother> smoother;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();  // model units to degrees
  std::unique_ptr<ResidualMotion> residual;         // trajectory: drawn frame by frame as the prosody comes
  FrameStore<Eigen::Vector3d> residuals;
  std::vector<Eigen::Vector4d> pending;  // batch mode: everything, solved at finish()
  std::vector<double> pendingVoiced;
  FrameStore<int> decided;  // online trajectory: states decided so far (the recent ones kept)
  FrameStore<Eigen::Vector3d> ready;
  bool finished = false;
  std::unique_ptr<hmm::ForwardFilter> filter;  // P(state | prosody so far), for display
  StepLimiter limiter;

  // The next ready rotation, from its value in degrees relative to the rest pose.
  void emit(const Eigen::Vector3d& rotation) {
    ready.push_back(rotationAtRest(limiter.next(rotation), options.restPose));
  }

  void drain() {
    if (options.variant == HeadVariant::kPosteriorMeans) {
      while (smoother->numReady() > static_cast<int>(ready.size())) {
        emit(scale.cwiseProduct(tables.poseMeans * smoother->posterior(static_cast<int>(ready.size()))));
      }
      return;
    }
    while (viterbi->numDecided() > static_cast<int>(decided.size()))
      decided.push_back(viterbi->state(static_cast<int>(decided.size())));
    viterbi->forgetBefore(static_cast<int>(decided.size()));  // copied here
    if (options.variant == HeadVariant::kStateMeans) {
      while (decided.size() > ready.size())
        emit(scale.cwiseProduct(tables.poseMean[static_cast<size_t>(decided[ready.size()])]));
      return;
    }
    // Trajectory: frame t once the states up to t + lookahead are known (or all of them, at the end).
    const auto lookahead = static_cast<size_t>(options.trajectoryLookaheadFrames);
    while (ready.size() < decided.size() && (finished || ready.size() + lookahead < decided.size())) {
      const size_t t = ready.size();
      const size_t begin = t > static_cast<size_t>(options.trajectoryWindowFrames)
                               ? t - static_cast<size_t>(options.trajectoryWindowFrames)
                               : 0;
      const size_t end = std::min(decided.size(), t + lookahead + 1);
      std::vector<int> window(end - begin);
      for (size_t i = begin; i < end; ++i) window[i - begin] = decided[i];
      emit(scale.cwiseProduct(
          trajectoryFor(tables, window, 0, window.size()).col(static_cast<Eigen::Index>(t - begin)) + residuals[t]));
    }
  }
};

HeadSynthesiser::HeadSynthesiser(const HeadModel& model, const HeadSynthesisOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->model = model;
  impl_->decoder = prosodyModel(model);
  impl_->tables = tablesOf(model, options.smoothing);
  impl_->scale = outputScale(model, options);
  if (options.variant == HeadVariant::kTrajectory) impl_->residual = std::make_unique<ResidualMotion>(model, options);
  impl_->filter = std::make_unique<hmm::ForwardFilter>(impl_->decoder);
  impl_->limiter = StepLimiter(options);
  if (options.maxLagFrames < 0) return;
  if (options.variant == HeadVariant::kPosteriorMeans) {
    impl_->smoother = std::make_unique<hmm::FixedLagSmoother>(impl_->decoder, options.maxLagFrames);
  } else {
    impl_->viterbi =
        std::make_unique<hmm::OnlineViterbi>(impl_->decoder, hmm::OnlineViterbiOptions{options.maxLagFrames});
  }
}

HeadSynthesiser::~HeadSynthesiser() = default;

void HeadSynthesiser::acceptProsody(const Eigen::Vector4d& prosody, bool voiced) {
  if (impl_->finished) throw Error("head synthesis: prosody after finish()");
  if (impl_->options.maxLagFrames < 0) {
    impl_->pending.push_back(prosody);
    impl_->pendingVoiced.push_back(voiced ? 1.0 : 0.0);
    return;
  }
  Eigen::VectorXd logB = impl_->decoder.emissionLogLikelihoods(prosody).col(0);
  if (impl_->options.voicedOnly && !voiced) logB.setZero();
  if (impl_->residual) impl_->residuals.push_back(impl_->residual->next(voiced));
  impl_->filter->accept(logB);
  if (impl_->smoother) {
    impl_->smoother->acceptFrame(logB);
  } else {
    impl_->viterbi->acceptFrame(logB);
  }
  impl_->drain();
}

void HeadSynthesiser::finish() {
  if (impl_->finished) return;
  impl_->finished = true;
  if (impl_->options.maxLagFrames < 0) {
    Eigen::MatrixXd prosody(ProsodyTracker::kDimension, static_cast<Eigen::Index>(impl_->pending.size()));
    for (size_t t = 0; t < impl_->pending.size(); ++t) prosody.col(static_cast<Eigen::Index>(t)) = impl_->pending[t];
    const Eigen::RowVectorXd voiced = Eigen::Map<const Eigen::RowVectorXd>(
        impl_->pendingVoiced.data(), static_cast<Eigen::Index>(impl_->pendingVoiced.size()));
    const Eigen::MatrixXd rotations = synthesiseHead(impl_->model, prosody, voiced, impl_->options);
    for (Eigen::Index t = 0; t < rotations.cols(); ++t) impl_->ready.push_back(rotations.col(t));
    return;
  }
  if (impl_->smoother) {
    impl_->smoother->finish();
  } else {
    impl_->viterbi->finish();
  }
  impl_->drain();
}

int HeadSynthesiser::numReady() const {
  return static_cast<int>(impl_->ready.size());
}

Eigen::Vector3d HeadSynthesiser::rotation(int frame) const {
  const auto f = static_cast<size_t>(frame);
  if (frame < 0 || f < impl_->ready.firstKept() || f >= impl_->ready.size())
    throw Error("head synthesis: frame " + std::to_string(frame) + " is not held");
  return impl_->ready[f];
}

void HeadSynthesiser::forgetBefore(int frame) {
  const auto f = static_cast<size_t>(std::max(0, frame));
  impl_->ready.forgetBefore(f);
  // The trajectory of a later frame is solved over the trajectoryWindowFrames states before it.
  const auto window = static_cast<size_t>(std::max(0, impl_->options.trajectoryWindowFrames));
  impl_->decided.forgetBefore(f > window ? f - window : 0);
  impl_->residuals.forgetBefore(f);
}

const Eigen::VectorXd& HeadSynthesiser::filteredPosterior() const {
  return impl_->filter->posterior();
}

int HeadSynthesiser::numStates() const {
  return impl_->decoder.numStates();
}

std::size_t HeadSynthesiser::framesHeld() const {
  return impl_->ready.held() + impl_->decided.held() + impl_->residuals.held() +
         (impl_->viterbi ? impl_->viterbi->framesHeld() : 0);
}

int headLookaheadFrames(const HeadSynthesisOptions& options) {
  if (options.maxLagFrames < 0) return -1;
  return options.maxLagFrames + (options.variant == HeadVariant::kTrajectory ? options.trajectoryLookaheadFrames : 0);
}

int HeadSynthesiser::lookaheadFrames() const {
  return headLookaheadFrames(impl_->options);
}

Eigen::MatrixXd randomWalkHead(const HeadModel& model, int numFrames, unsigned seed) {
  std::mt19937 random(seed);
  const StateTables tables = tablesOf(model);
  const hmm::HmmModel& hmm = model.hmm;
  auto draw = [&random](const Eigen::VectorXd& probabilities) {
    std::discrete_distribution<int> pick(probabilities.data(), probabilities.data() + probabilities.size());
    return pick(random);
  };
  Eigen::MatrixXd out(3, numFrames);
  int state = draw(hmm.initial);
  for (int t = 0; t < numFrames; ++t) {
    if (t > 0) state = draw(hmm.transition.row(state).transpose());
    out.col(t) = model.amplitude.cwiseProduct(tables.poseMean[static_cast<size_t>(state)]);
  }
  return out;
}

}  // namespace th::animation
