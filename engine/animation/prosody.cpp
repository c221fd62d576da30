#include "animation/prosody.h"

#include <cmath>
#include <numbers>

namespace th::animation {
namespace {

constexpr double kSemitonesPerNat = 12.0 / std::numbers::ln2;

}  // namespace

ProsodyTracker::ProsodyTracker(double framesPerSecond, const ProsodyOptions& options)
    : holdFactor_(std::exp(-1.0 / (framesPerSecond * options.unvoicedDecaySeconds))),
      meanFactor_(1.0 / (framesPerSecond * options.meanPitchSeconds)) {}

Eigen::Vector4d ProsodyTracker::accept(std::span<const float> featureRow) {
  using Layout = features::FeatureLayout;
  const double f0 = featureRow[Layout::kF0Hz];
  double deltaPitch = 0.0;
  if (f0 > 0.0) {
    const double logHz = std::log(f0);
    if (!haveMean_) {
      meanLogHz_ = logHz;
      haveMean_ = true;
    } else {
      meanLogHz_ += meanFactor_ * (logHz - meanLogHz_);
    }
    heldPitch_ = kSemitonesPerNat * (logHz - meanLogHz_);
    // d log F0 = dF0 / F0 (the row's delta is in Hz per frame).
    deltaPitch = kSemitonesPerNat * featureRow[Layout::kDeltaF0] / f0;
  } else {
    heldPitch_ *= holdFactor_;
  }
  return {heldPitch_, featureRow[Layout::kEnergy], deltaPitch, featureRow[Layout::kDeltaEnergy]};
}

features::FeatureOptions prosodyFeatureOptions(double framesPerSecond) {
  features::FeatureOptions options = features::batchFeatureOptions();
  options.framesPerSecond = framesPerSecond;
  options.energyNormalisation = features::EnergyNormalisation::kRunning;
  options.contextFrames = 0;
  return options;
}

Eigen::MatrixXd prosodyOf(const features::FeatureMatrix& features, const ProsodyOptions& options) {
  ProsodyTracker tracker(features.framesPerSecond, options);
  Eigen::MatrixXd prosody(ProsodyTracker::kDimension, features.numFrames());
  for (int t = 0; t < features.numFrames(); ++t) prosody.col(t) = tracker.accept(features.row(t));
  return prosody;
}

bool isVoiced(std::span<const float> featureRow) {
  return featureRow[features::FeatureLayout::kF0Hz] > 0.0f;
}

Eigen::RowVectorXd voicingOf(const features::FeatureMatrix& features) {
  Eigen::RowVectorXd voiced(features.numFrames());
  for (int t = 0; t < features.numFrames(); ++t) voiced[t] = isVoiced(features.row(t)) ? 1.0 : 0.0;
  return voiced;
}

}  // namespace th::animation
