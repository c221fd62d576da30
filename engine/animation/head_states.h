// What the head model's training and synthesis share (head_model.cpp, head_synthesis.cpp), not part of the
// API: the layout of the joint observation, the per-state tables the trajectory is solved from, the prosody
// decoder and its voicing gate, and the residual motion.
//
// Thread contract: values and pure functions; a ResidualMotion belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "animation/head_model.h"
#include "core/portable_random.h"
#include "hmm/hmm_model.h"

namespace th::animation {

// Layout of the joint model's observation: motion | motion_delta | motion_acceleration | prosody. Models made
// before the acceleration block (motion | motion_delta | prosody) still load: their trajectory has no
// acceleration term.
inline constexpr int kMotionBegin = 0;
inline constexpr int kDeltaBegin = 3;
inline constexpr int kAccelerationBegin = 6;
inline constexpr int kProsodyBegin = 9;
inline constexpr int kDimension = 13;
inline constexpr int kOldProsodyBegin = 6;
inline constexpr int kOldDimension = 10;

inline int prosodyBegin(const HeadModel& model) {
  return model.hasAcceleration ? kProsodyBegin : kOldProsodyBegin;
}

// Per state: the pose and velocity Gaussians that synthesis reads.
struct StateTables {
  std::vector<Eigen::Vector3d> poseMean;
  std::vector<Eigen::Matrix3d> posePrecision;
  std::vector<Eigen::Vector3d> deltaMean;
  std::vector<Eigen::Matrix3d> deltaPrecision;
  std::vector<Eigen::Vector3d> accelerationMean;  // empty without the acceleration block
  std::vector<Eigen::Matrix3d> accelerationPrecision;
  Eigen::MatrixXd poseMeans;  // 3 x N, for posterior-weighted means
};

// smoothing multiplies the velocity and acceleration precisions: above 1 the trajectory moves more slowly.
StateTables tablesOf(const HeadModel& model, double smoothing = 1.0);

// The smooth trajectory (MLPG) through states[begin, end), in model units.
Eigen::MatrixXd trajectoryFor(const StateTables& tables, const std::vector<int>& states, size_t begin, size_t end);

// The HMM over a block of the observation (the same transitions; each component's marginal Gaussian).
hmm::HmmModel marginal(const hmm::HmmModel& model, int begin, int size);

// Unvoiced and silent frames carry no prosody the model knows (the pitch is held, the energy is the room's):
// their emissions are made equal for every state, so only the transitions (which favour staying) decide there.
Eigen::MatrixXd gatedEmissions(const hmm::HmmModel& decoder, const Eigen::MatrixXd& prosody,
                               const Eigen::RowVectorXd& voiced, bool voicedOnly);

// Rotations in the model's units to degrees.
Eigen::Vector3d outputScale(const HeadModel& model, const HeadSynthesisOptions& options);

// The trajectory through the Viterbi states, in model units (batch).
Eigen::MatrixXd meanTrajectory(const HeadModel& model, const Eigen::MatrixXd& prosody, const Eigen::RowVectorXd& voiced,
                               bool voicedOnly, double smoothing);

// The motion the voice does not explain — the variance the states' smooth trajectory leaves out of the training
// motion's, in pose and in frame-to-frame step — as a random process with that spread and step. Per axis a
// second-order autoregression with a double pole r, x_t = 2r x_{t−1} − r² x_{t−2} + σ ε_t: unlike a first-order
// one (white steps) its velocity is smooth, as a head's is. With ρ₁ its lag-1 autocorrelation, the step variance
// is 2 s² (1 − ρ₁), so ρ₁ = 1 − v² / (2 s²), r solves 2r / (1 + r²) = ρ₁, and σ gives the stationary variance s².
// It is quieter in pauses: after kHoldSeconds without a voice its gain eases to pauseVariation (people move less
// while silent). Deterministic for a seed; frames in order, so the batch and the online synthesis agree.
class ResidualMotion {
 public:
  static constexpr double kHoldSeconds = 0.3;
  static constexpr double kEaseSeconds = 0.3;

  ResidualMotion(const HeadModel& model, const HeadSynthesisOptions& options)
      : random_(options.seed), variation_(options.variation), pauseGain_(options.pauseVariation) {
    for (int axis = 0; axis < 3; ++axis) {
      const double s = model.residualStd[axis];
      const double v = model.residualStepStd[axis];
      if (s <= 0.0 || v <= 0.0) continue;  // a1 = a2 = σ = 0: no residual on this axis
      const double rho = std::clamp(1.0 - v * v / (2.0 * s * s), 0.0, 0.9999);
      const double r = rho > 0.0 ? (1.0 - std::sqrt(1.0 - rho * rho)) / rho : 0.0;
      a1_[axis] = 2.0 * r;
      a2_[axis] = -r * r;
      // γ₀ = σ² (1 − φ₂) / ((1 + φ₂)((1 − φ₂)² − φ₁²)) for x_t = φ₁ x_{t−1} + φ₂ x_{t−2} + σ ε_t.
      const double phi1 = a1_[axis], phi2 = a2_[axis];
      sigma_[axis] = s * std::sqrt((1.0 + phi2) * ((1.0 - phi2) * (1.0 - phi2) - phi1 * phi1) / (1.0 - phi2));
    }
  }

  Eigen::Vector3d next(bool voiced) {
    constexpr double kFps = kHeadFramesPerSecond;
    framesSinceVoice_ = voiced ? 0 : framesSinceVoice_ + 1;
    const double target = framesSinceVoice_ <= kHoldSeconds * kFps ? 1.0 : pauseGain_;
    gain_ += (target - gain_) / (kEaseSeconds * kFps);
    for (int axis = 0; axis < 3; ++axis) {
      const double x = a1_[axis] * last_[axis] + a2_[axis] * beforeLast_[axis] + sigma_[axis] * normal_(random_);
      beforeLast_[axis] = last_[axis];
      last_[axis] = x;
    }
    return variation_ * gain_ * last_;
  }

 private:
  std::mt19937 random_;
  NormalDraws normal_;
  double variation_;
  double pauseGain_;
  Eigen::Vector3d a1_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d a2_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d beforeLast_ = Eigen::Vector3d::Zero();
  int framesSinceVoice_ = 1 << 20;  // the start counts as a pause
  double gain_ = 0.0;
};

}  // namespace th::animation
