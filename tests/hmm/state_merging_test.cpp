// State merging: the two copies of a split state are the pair the statistics point to first, and merging them
// gives back the model they were split from; a merge never leaves a row that does not sum to 1.
#include "hmm/state_merging.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "hmm/forward_backward.h"
#include "hmm/sampling.h"
#include "hmm_test_models.h"

namespace th::hmm {
namespace {

// The same process with state `split` duplicated: the copies share its density and row, each receives half of
// every transition into it (so the likelihood of any data is unchanged).
HmmModel splitState(const HmmModel& model, int split) {
  const int n = model.numStates();
  HmmModel result = model;
  result.initial.conservativeResize(n + 1);
  result.initial[split] *= 0.5;
  result.initial[n] = result.initial[split];
  result.transition = Eigen::MatrixXd::Zero(n + 1, n + 1);
  result.transition.topLeftCorner(n, n) = model.transition;
  result.transition.col(split) *= 0.5;
  result.transition.col(n) = result.transition.col(split);
  result.transition.row(n) = result.transition.row(split);
  result.states.push_back(model.states[static_cast<size_t>(split)]);
  result.check();
  return result;
}

double logLikelihoodOf(const HmmModel& model, const Eigen::MatrixXd& frames) {
  return logLikelihood(model, model.emissionLogLikelihoods(frames));
}

TEST(StateMerging, TheCopiesOfASplitStateAreFoundAndMergedBack) {
  const HmmModel original = test::stickyModel1d(4, 0.9);
  std::mt19937 random(3);
  const Sample sample = sampleHmm(original, 5000, random);
  const HmmModel split = splitState(original, 2);
  ASSERT_NEAR(logLikelihoodOf(split, sample.frames), logLikelihoodOf(original, sample.frames), 1e-6);

  const SufficientStatistics statistics = expectationStep(split, {sample.frames});
  const auto candidates = mergeCandidates(split, statistics, 3);
  ASSERT_EQ(candidates.size(), 3u);
  EXPECT_EQ(candidates.front(), std::make_pair(2, 4)) << "the copies cost the emissions nothing to merge";

  const HmmModel merged = mergeStates(split, statistics, 2, 4, Eigen::VectorXd::Constant(1, 1e-6), 0.0);
  ASSERT_EQ(merged.numStates(), 4);
  // One EM step's worth of re-estimation of the original model: at least as likely, and close to it.
  const double before = logLikelihoodOf(original, sample.frames);
  const double after = logLikelihoodOf(merged, sample.frames);
  EXPECT_GE(after, before - 1e-6);
  EXPECT_LT(after - before, 0.01 * static_cast<double>(sample.frames.cols()));
  EXPECT_LT((merged.transition - original.transition).cwiseAbs().maxCoeff(), 0.03);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(merged.states[static_cast<size_t>(j)].components()[0].mean()[0], 3.0 * j, 0.1);
  }
}

TEST(StateMerging, MergingDistinctStatesCostsLikelihoodAndKeepsRowsStochastic) {
  const HmmModel model = test::randomModel(5, 2, 3, CovarianceType::kFull, 11);
  std::mt19937 random(5);
  const Sample sample = sampleHmm(model, 3000, random);
  const SufficientStatistics statistics = expectationStep(model, {sample.frames});
  const double before = statistics.logLikelihood;
  for (int a = 0; a < 5; ++a) {
    for (int b = a + 1; b < 5; ++b) {
      const HmmModel merged = mergeStates(model, statistics, a, b, Eigen::VectorXd::Constant(3, 1e-6), 0.0);
      ASSERT_EQ(merged.numStates(), 4);
      for (int i = 0; i < 4; ++i) EXPECT_NEAR(merged.transition.row(i).sum(), 1.0, 1e-12);
      EXPECT_NEAR(merged.initial.sum(), 1.0, 1e-12);
      EXPECT_NEAR(merged.states[static_cast<size_t>(a)].weights().sum(), 1.0, 1e-12);
      EXPECT_LT(logLikelihoodOf(merged, sample.frames), before) << "states " << a << " and " << b << " differ";
    }
  }
  EXPECT_THROW(mergeStates(model, statistics, 2, 2, Eigen::VectorXd::Constant(3, 1e-6), 0.0), Error);
}

}  // namespace
}  // namespace th::hmm
