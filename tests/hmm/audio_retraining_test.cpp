// Audio re-training keeps the visual side and the structure, learns the new audio, and repairs covariances.
#include "hmm/audio_retraining.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "hmm/sampling.h"
#include "hmm_test_models.h"

namespace th::hmm {
namespace {

HmmModel jointModel(unsigned seed) {
  HmmModel model = test::randomModel(3, 2, 5, CovarianceType::kFull, seed);
  model.blocks = {{"audio", 0, 3}, {"visual", 3, 2}};
  return model;
}

TEST(AudioRetraining, KeepsStructureAndVisualSideAndLearnsTheNewAudio) {
  const HmmModel original = jointModel(12);
  // "Another speaker": the same model with every audio mean shifted by +1.5.
  HmmModel shifted = original;
  for (auto& state : shifted.states) {
    std::vector<Gaussian> components;
    for (const auto& g : state.components()) {
      Eigen::VectorXd mean = g.mean();
      mean.head(3).array() += 1.5;
      components.emplace_back(mean, g.covariance(), g.type());
    }
    state = GaussianMixture(state.weights(), std::move(components));
  }
  std::mt19937 random(12);
  std::vector<Eigen::MatrixXd> audio;
  for (int s = 0; s < 3; ++s) audio.push_back(sampleHmm(shifted, 3000, random).frames.topRows(3));
  const AudioRetrainingResult result = retrainAudio(original, audio, {.iterations = 15});

  EXPECT_EQ(result.model.initial, original.initial);
  EXPECT_EQ(result.model.transition, original.transition);
  for (size_t i = 1; i < result.logLikelihoods.size(); ++i) {
    EXPECT_GE(result.logLikelihoods[i], result.logLikelihoods[i - 1] - 1e-6);
  }
  double shift = 0.0;
  int count = 0;
  for (int j = 0; j < 3; ++j) {
    const auto& before = original.states[static_cast<size_t>(j)];
    const auto& after = result.model.states[static_cast<size_t>(j)];
    EXPECT_EQ(after.weights(), before.weights());
    for (int m = 0; m < 2; ++m) {
      const Gaussian& a = after.components()[static_cast<size_t>(m)];
      const Gaussian& b = before.components()[static_cast<size_t>(m)];
      EXPECT_EQ(a.mean().tail(2), b.mean().tail(2));
      EXPECT_EQ(a.covariance().bottomRightCorner(2, 2), b.covariance().bottomRightCorner(2, 2));
      shift += (a.mean().head(3) - b.mean().head(3)).mean();
      ++count;
      EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(a.covariance()).info(), Eigen::Success);
    }
  }
  EXPECT_NEAR(shift / count, 1.5, 0.3) << "the audio means moved to the new speaker";
}

TEST(AudioRetraining, ShrinksTheCrossCovarianceWhenTheJointWouldNotBePositiveDefinite) {
  // Strongly correlated audio and visual; the new audio variance is far smaller, so the old cross-covariance no
  // longer fits.
  const ObservationBlock audio{"audio", 0, 1};
  const ObservationBlock visual{"visual", 1, 1};
  const Eigen::MatrixXd newAudio = Eigen::MatrixXd::Constant(1, 1, 0.01);
  const Eigen::MatrixXd cross = Eigen::MatrixXd::Constant(1, 1, 0.9);
  const Eigen::MatrixXd visualCovariance = Eigen::MatrixXd::Constant(1, 1, 1.0);
  Eigen::MatrixXd joint;
  const double factor = assembleJointCovariance(newAudio, cross, visualCovariance, audio, visual, joint);
  EXPECT_LT(factor, 1.0);
  EXPECT_GT(factor, 0.0);
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(joint).info(), Eigen::Success);
  EXPECT_DOUBLE_EQ(joint(0, 0), 0.01);
  EXPECT_DOUBLE_EQ(joint(1, 1), 1.0);
  // A 2 x 2 covariance [[a, f c], [f c, v]] is positive definite when (f c)^2 < a v. The factor is the first of
  // 1, 0.9, 0.81, ... that satisfies it: the one before does not.
  const double c = 0.9;
  EXPECT_LT((factor * c) * (factor * c), 0.01 * 1.0);
  EXPECT_GE((factor / 0.9 * c) * (factor / 0.9 * c), 0.01 * 1.0);
}

}  // namespace
}  // namespace th::hmm
