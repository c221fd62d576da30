// The mouth's speech normalisation: real speech at −20 dB gives the same frames, a fixed spectral tilt (a
// microphone, a voice) is taken out by the running cepstral mean, the prior weighs as stated, and bad options
// are refused.
#include "features/speech_normaliser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "animation/mouth_data.h"
#include "core/error.h"
#include "feature_test_audio.h"

namespace {

using th::features::OnlineSpeechNormaliser;
using th::features::SpeechNormalisationOptions;

Eigen::VectorXd priorOf(const th::animation::SpeechFrames& speech) {
  return speech.mfcc.rowwise().mean();
}

TEST(SpeechNormaliser, TheSameSpeechTwentyDecibelsDownGivesTheSameFrames) {
  const std::vector<float>& loud = th::test::beat2Speech(20.0);
  std::vector<float> quiet(loud.size());
  for (std::size_t i = 0; i < loud.size(); ++i) quiet[i] = 0.1F * loud[i];
  const th::animation::SpeechFrames a = th::animation::speechFramesOf(loud);
  const th::animation::SpeechFrames b = th::animation::speechFramesOf(quiet);
  ASSERT_EQ(a.numFrames(), b.numFrames());
  // The raw level drops by 20 dB...
  EXPECT_NEAR((a.levelDb - b.levelDb).mean(), 20.0, 0.01);
  const Eigen::VectorXd prior = priorOf(a);
  const Eigen::MatrixXd x = th::features::normaliseSpeech({}, 30.0, prior, a.levelDb, a.mfcc);
  const Eigen::MatrixXd y = th::features::normaliseSpeech({}, 30.0, prior, b.levelDb, b.mfcc);
  // ...and the normalised level does not move at all (up to rounding): the peak moves with it.
  EXPECT_LT((x.bottomRows(1) - y.bottomRows(1)).cwiseAbs().maxCoeff(), 1e-4);
  // The MFCCs differ only where the quieter signal meets the filterbank's floor, in near-silence: over the
  // frames less than 40 dB below the peak, they agree to within a hundredth of their spread.
  const Eigen::RowVectorXd level = x.bottomRows(1);
  double worst = 0.0;
  int speechFrames = 0;
  for (Eigen::Index t = 0; t < x.cols(); ++t) {
    if (level[t] < -4.0) continue;
    ++speechFrames;
    for (Eigen::Index k = 0; k < prior.size(); ++k) {
      const double spread = std::sqrt((a.mfcc.row(k).array() - a.mfcc.row(k).mean()).square().mean());
      worst = std::max(worst, std::abs(x(k, t) - y(k, t)) / spread);
    }
  }
  EXPECT_GT(speechFrames, x.cols() / 2);
  EXPECT_LT(worst, 0.01) << "the largest difference, as a share of that coefficient's spread";
}

TEST(SpeechNormaliser, ARunningMeanTakesOutAFixedSpectralTilt) {
  const th::animation::SpeechFrames speech = th::animation::speechFramesOf(th::test::beat2Speech(40.0));
  const Eigen::VectorXd prior = priorOf(speech);
  // Another microphone: every cepstral coefficient shifted by a constant.
  Eigen::VectorXd tilt(prior.size());
  for (Eigen::Index k = 0; k < tilt.size(); ++k) tilt[k] = 3.0 * std::cos(static_cast<double>(k));
  const Eigen::MatrixXd tilted = speech.mfcc.colwise() + tilt;
  const SpeechNormalisationOptions options{.meanSeconds = 5.0};
  const Eigen::MatrixXd x = th::features::normaliseSpeech(options, 30.0, prior, speech.levelDb, speech.mfcc);
  const Eigen::MatrixXd y = th::features::normaliseSpeech(options, 30.0, prior, speech.levelDb, tilted);
  // The difference decays as the mean catches up: after six time constants it is e^-6 of the tilt.
  const Eigen::Index late = static_cast<Eigen::Index>(30.0 * 30.0);
  const double left = (y.col(late) - x.col(late)).head(prior.size()).norm();
  EXPECT_LT(left, 0.01 * tilt.norm());
  EXPECT_GT((y.col(0) - x.col(0)).head(prior.size()).norm(), 0.5 * tilt.norm()) << "the first frame still carries it";
}

TEST(SpeechNormaliser, ThePriorWeighsAsSoManySecondsOfFrames) {
  const Eigen::VectorXd prior = Eigen::VectorXd::Constant(3, 1.0);
  OnlineSpeechNormaliser normaliser({.priorSeconds = 1.0}, 10.0, prior);  // the prior as 10 frames
  EXPECT_EQ(normaliser.outputDimension(), 4);
  Eigen::VectorXd out(4);
  normaliser.accept(-20.0, Eigen::VectorXd::Constant(3, 12.0), out);
  // The mean after one frame: (10 · 1 + 12) / 11 = 2; the frame less that is 10.
  EXPECT_NEAR(out[0], 10.0, 1e-12);
  EXPECT_DOUBLE_EQ(out[3], 0.0) << "the first frame is its own peak";
  normaliser.accept(-30.0, Eigen::VectorXd::Constant(3, 12.0), out);
  // The peak falls 2 dB a second, 0.2 dB a frame: -30 - (-20.2) = -9.8 dB, in 10 dB units.
  EXPECT_NEAR(out[3], -0.98, 1e-12);
  normaliser.accept(-10.0, Eigen::VectorXd::Constant(3, 12.0), out);
  EXPECT_DOUBLE_EQ(out[3], 0.0) << "a louder frame is the new peak";
  normaliser.reset();
  normaliser.accept(-20.0, Eigen::VectorXd::Constant(3, 12.0), out);
  EXPECT_NEAR(out[0], 10.0, 1e-12) << "reset starts again from the prior";
}

TEST(SpeechNormaliser, BadOptionsAndShapesAreRefused) {
  const Eigen::VectorXd prior = Eigen::VectorXd::Zero(11);
  EXPECT_THROW(OnlineSpeechNormaliser({.meanSeconds = 0.0}, 30.0, prior), th::Error);
  EXPECT_THROW(OnlineSpeechNormaliser({.priorSeconds = -1.0}, 30.0, prior), th::Error);
  EXPECT_THROW(OnlineSpeechNormaliser({.peakDecayDbPerSecond = 0.0}, 30.0, prior), th::Error);
  EXPECT_THROW(OnlineSpeechNormaliser({.levelUnitDb = std::nan("")}, 30.0, prior), th::Error);
  EXPECT_THROW(OnlineSpeechNormaliser({}, 30.0, Eigen::VectorXd()), th::Error);
  EXPECT_THROW(
      th::features::normaliseSpeech({}, 30.0, prior, Eigen::RowVectorXd::Zero(5), Eigen::MatrixXd::Zero(11, 6)),
      th::Error);
  EXPECT_THROW(
      th::features::normaliseSpeech({}, 30.0, prior, Eigen::RowVectorXd::Zero(6), Eigen::MatrixXd::Zero(10, 6)),
      th::Error);
}

}  // namespace
