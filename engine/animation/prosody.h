// Prosody for the head-motion model: [pitch, energy, Δpitch, Δenergy] per animation frame, computed from the
// streaming feature rows (features/online_features.h) one frame at a time, so training (batch) and live use
// see identical values.
//
//   th::animation::ProsodyTracker prosody(30.0, {});
//   Eigen::Vector4d p = prosody.accept(featureRow);        // in frame order
//   Eigen::MatrixXd all = th::animation::prosodyOf(features);   // 4 x T, the same tracker over every row
//
// Pitch is in semitones relative to a running mean of the speaker's voiced log F0, so a model trained on one
// voice transfers to a higher or lower one. F0 does not exist where speech is unvoiced; instead of the 0 Hz the
// tracker reports there (which a Gaussian would read as an extreme pitch), unvoiced frames hold the last voiced
// pitch and let it relax towards the speaker's mean (time constant unvoicedDecaySeconds), with Δpitch 0. This is
// causal, so the live path needs no extra look-ahead. Energy and its delta are the feature rows' (use the
// running normalisation, as live audio must).
// Thread contract: one thread per instance.
#pragma once

#include <Eigen/Core>
#include <span>

#include "features/online_features.h"

namespace th::animation {

struct ProsodyOptions {
  double unvoicedDecaySeconds = 0.25;  // held pitch relaxes to the mean with this time constant
  double meanPitchSeconds = 10.0;      // time constant of the running mean of voiced log F0
};

class ProsodyTracker {
 public:
  static constexpr int kDimension = 4;  // pitch (semitones), energy, Δpitch (semitones/frame), Δenergy

  ProsodyTracker(double framesPerSecond, const ProsodyOptions& options);

  // One feature row (FeatureLayout) after another, in frame order.
  Eigen::Vector4d accept(std::span<const float> featureRow);

 private:
  double holdFactor_;  // per frame, for the unvoiced decay
  double meanFactor_;  // per frame, for the running mean
  bool haveMean_ = false;
  double meanLogHz_ = 0.0;
  double heldPitch_ = 0.0;
};

// Feature options for prosody: the batch extractor with the live (running) energy normalisation.
features::FeatureOptions prosodyFeatureOptions(double framesPerSecond = 30.0);

// The tracker over every row of `features`: 4 x numFrames.
Eigen::MatrixXd prosodyOf(const features::FeatureMatrix& features, const ProsodyOptions& options = {});

// Whether the pitch tracker found a voice in a feature row, and that over every row (1 voiced, 0 not).
bool isVoiced(std::span<const float> featureRow);
Eigen::RowVectorXd voicingOf(const features::FeatureMatrix& features);

}  // namespace th::animation
