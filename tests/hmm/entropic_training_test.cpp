// The entropic training hooks: Z = 0 is maximum likelihood exactly, and state deletion keeps the model valid.
#include "hmm/entropic_training.h"

#include <gtest/gtest.h>

#include <random>

#include "hmm/sampling.h"
#include "hmm_test_models.h"

namespace th::hmm {
namespace {

TEST(EntropicTraining, ZeroWeightReproducesMaximumLikelihoodExactly) {
  const HmmModel truth = test::stickyModel1d(3, 0.9);
  std::mt19937 random(8);
  const std::vector<Eigen::MatrixXd> sequences = {sampleHmm(truth, 3000, random).frames};
  TrainingOptions options;
  options.numStates = 4;
  options.maxIterations = 15;
  const TrainingResult ml = trainHmm(sequences, options);
  const TrainingResult zero =
      trainHmm(sequences, options, entropicHooks({.multinomialWeight = 0.0, .covarianceWeight = 0.0}));
  ASSERT_EQ(ml.history.size(), zero.history.size());
  for (size_t i = 0; i < ml.history.size(); ++i) EXPECT_EQ(ml.history[i].logLikelihood, zero.history[i].logLikelihood);
  EXPECT_EQ(ml.model.transition, zero.model.transition);
  EXPECT_EQ(ml.model.initial, zero.model.initial);
}

TEST(EntropicTraining, CovariancePriorShrinksByOccupancy) {
  // One state, one component: Σ_MAP = S / (Γ + Z_Σ) = Σ_ML · Γ / (Γ + Z_Σ).
  const HmmModel truth = test::stickyModel1d(1 + 1, 1.0 - 1e-9);
  std::mt19937 random(2);
  Eigen::MatrixXd frames = sampleHmm(truth, 2000, random).frames;
  frames = frames.array() - frames.mean();
  TrainingOptions options;
  options.numStates = 1;
  options.maxIterations = 2;
  const double ml = trainHmm({frames}, options).model.states[0].components()[0].covariance()(0, 0);
  const double map = trainHmm({frames}, options, entropicHooks({.multinomialWeight = 0.0, .covarianceWeight = 500.0}))
                         .model.states[0]
                         .components()[0]
                         .covariance()(0, 0);
  EXPECT_NEAR(map, ml * 2000.0 / 2500.0, 1e-9 * ml);
}

TEST(EntropicTraining, DeletingAStateRenormalisesTheRowsThatLedToIt) {
  HmmModel model = test::randomModel(4, 1, 2, CovarianceType::kFull, 3);
  const Eigen::MatrixXd before = model.transition;
  deleteState(model, 1);
  ASSERT_EQ(model.numStates(), 3);
  EXPECT_NO_THROW(model.check());
  // Row 0 keeps its proportions among the states that remain.
  EXPECT_NEAR(model.transition(0, 1) / model.transition(0, 0), before(0, 2) / before(0, 0), 1e-12);
  EXPECT_NEAR(model.transition.row(0).sum(), 1.0, 1e-12);
  EXPECT_EQ(countTransitions(model), 9);
}

}  // namespace
}  // namespace th::hmm
