// Brand's entropic prior discovers structure: from a generous, fully connected start it prunes states and
// transitions down to (nearly) those of the sparse HMM that generated the data, where maximum likelihood keeps
// everything. Also: the log posterior never decreases, on synthetic and on real speech features.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "audio/audio_file.h"
#include "core/data_path.h"
#include "features/online_features.h"
#include "hmm/entropic_training.h"
#include "hmm/forward_backward.h"
#include "hmm/sampling.h"
#include "hmm/viterbi.h"
#include "structure_report.h"

namespace th::hmm {
namespace {

using test::compareStructure;
using test::sparseSixStateModel;
using test::StructureReport;

// Every step, judged under the prior it was taken with, raises the log posterior (up to rounding); and with a
// fixed prior the history itself never falls.
void expectPosteriorNeverFalls(const TrainingResult& result, bool fixedPrior) {
  for (size_t i = 0; i + 1 < result.history.size(); ++i) {
    const double scale = 1e-9 * std::abs(result.history[i].logPosterior());
    EXPECT_GE(result.history[i].stepGain, -scale) << "iteration " << i;
    if (fixedPrior) {
      EXPECT_GE(result.history[i + 1].logPosterior(), result.history[i].logPosterior() - scale) << "iteration " << i;
    }
  }
}

TEST(StructureDiscovery, EntropicPriorFindsTheSparseModelThatMaximumLikelihoodMisses) {
  const HmmModel truth = sparseSixStateModel();
  std::mt19937 random(2024);
  const Sample sample = sampleHmm(truth, 20000, random);
  TrainingOptions options;
  options.numStates = 20;
  options.maxIterations = 150;
  options.seed = 5;

  // Maximum likelihood for 60 iterations (its rows stay dense however long it runs; 150 give 171 transitions).
  TrainingOptions mlOptions = options;
  mlOptions.maxIterations = 60;
  const TrainingResult ml = trainHmm({sample.frames}, mlOptions);
  const StructureReport mlReport = compareStructure(truth, ml.model, sample);
  std::printf(
      "[ INFO     ] maximum likelihood: %d live states, %d transitions, %d of 9 true edges, %d spurious, "
      "state agreement %.3f, %zu iterations\n",
      mlReport.liveStates, mlReport.transitions, mlReport.recoveredEdges, mlReport.spuriousEdges,
      mlReport.stateAgreement, ml.history.size() - 1);
  EXPECT_EQ(mlReport.liveStates, 20);
  EXPECT_GT(mlReport.transitions, 100) << "maximum likelihood keeps the rows dense (the truth has 15 edges)";

  const double z = 0.1 * static_cast<double>(sample.frames.cols());
  const TrainingResult map = trainHmm(
      {sample.frames}, options, entropicHooks({.multinomialWeight = z, .warmupIterations = 10, .rampIterations = 20}));
  const StructureReport mapReport = compareStructure(truth, map.model, sample);
  std::printf(
      "[ INFO     ] entropic Z = %.0f: %d live states, %d transitions, %d of 9 true edges, %d spurious, "
      "state agreement %.3f, %zu iterations\n",
      z, mapReport.liveStates, mapReport.transitions, mapReport.recoveredEdges, mapReport.spuriousEdges,
      mapReport.stateAgreement, map.history.size() - 1);
  int merges = 0;
  for (const auto& record : map.history) merges += record.statesMerged;
  EXPECT_LE(mapReport.liveStates, 8);
  EXPECT_GE(mapReport.liveStates, 6) << "no true state may be lost";
  EXPECT_LE(mapReport.transitions, mapReport.liveStates + 12) << "against maximum likelihood's dense rows";
  EXPECT_EQ(mapReport.recoveredEdges, 9);
  EXPECT_LE(mapReport.spuriousEdges, 1);
  EXPECT_GT(mapReport.stateAgreement, 0.99);
  EXPECT_GT(merges, 0) << "extinction alone leaves split copies of true states (see state_merging.h)";
  expectPosteriorNeverFalls(ml, true);
  expectPosteriorNeverFalls(map, false);
}

TEST(StructureDiscovery, LogPosteriorNeverFallsOnSyntheticData) {
  const HmmModel truth = sparseSixStateModel();
  std::mt19937 random(7);
  const Sample sample = sampleHmm(truth, 5000, random);
  TrainingOptions options;
  options.numStates = 10;
  options.maxIterations = 40;
  for (double z : {0.0, 1.0, 250.0}) {
    for (bool trim : {false, true}) {
      expectPosteriorNeverFalls(trainHmm({sample.frames}, options,
                                         entropicHooks({.multinomialWeight = z, .covarianceWeight = z, .trim = trim})),
                                true);
    }
  }
}

// BEAT2 prosody [F0, energy, dF0, dE] at 30 fps, in 4 sequences.
std::vector<Eigen::MatrixXd> beat2Prosody() {
  const audio::AudioClip clip = audio::readAudioFile(sharedDataPath("beat2/2_scott_0_1_1.wav"));
  features::FeatureOptions featureOptions = features::batchFeatureOptions();
  featureOptions.contextFrames = 0;
  const features::FeatureMatrix features = features::computeFeatures(clip.samples, featureOptions);
  const int perSequence = features.numFrames() / 4;
  std::vector<Eigen::MatrixXd> sequences;
  for (int s = 0; s < 4; ++s) {
    Eigen::MatrixXd frames(4, perSequence);
    for (int t = 0; t < perSequence; ++t) {
      const auto row = features.row(s * perSequence + t);
      for (int k = 0; k < 4; ++k) frames(k, t) = row[static_cast<size_t>(k)];
    }
    sequences.push_back(frames);
  }
  return sequences;
}

TEST(StructureDiscovery, LogPosteriorNeverFallsOnRealProsody) {
  const std::vector<Eigen::MatrixXd> sequences = beat2Prosody();
  double numFrames = 0.0;
  for (const auto& sequence : sequences) numFrames += static_cast<double>(sequence.cols());
  TrainingOptions options;
  options.numStates = 16;
  options.maxIterations = 40;
  // With a fixed prior, with and without trimming and merging.
  for (double z : {0.0, 1.0, 0.02 * numFrames, 0.1 * numFrames}) {
    for (bool trim : {false, true}) {
      const TrainingResult result =
          trainHmm(sequences, options,
                   entropicHooks({.multinomialWeight = z, .covarianceWeight = z > 1.0 ? 5.0 : 0.0, .trim = trim}));
      int undone = 0;
      int merges = 0;
      for (const auto& record : result.history) {
        undone += record.trimRetries;
        merges += record.statesMerged;
      }
      std::printf(
          "[ INFO     ] real prosody, Z = %.1f, trim %d: %d live states, %d transitions, log posterior per frame "
          "%.4f, %d trimming retries, %d merges\n",
          z, trim, result.model.numStates(), countTransitions(result.model, 0.0),
          result.history.back().logPosterior() / numFrames, undone, merges);
      expectPosteriorNeverFalls(result, true);
    }
  }
}

// Online Viterbi on a model trained on real speech (the prosody model's size: 12 states from 16, entropic),
// decoding the whole recording: agreement with batch Viterbi and mean actual lag for maximum lags 1-30.
TEST(StructureDiscovery, OnlineViterbiLagSweepOnATrainedProsodyModel) {
  const std::vector<Eigen::MatrixXd> sequences = beat2Prosody();
  double numFrames = 0.0;
  for (const auto& sequence : sequences) numFrames += static_cast<double>(sequence.cols());
  TrainingOptions options;
  options.numStates = 16;
  options.maxIterations = 60;
  const HmmModel model =
      trainHmm(sequences, options, entropicHooks({.multinomialWeight = 0.02 * numFrames, .covarianceWeight = 5.0}))
          .model;
  Eigen::MatrixXd all(4, static_cast<Eigen::Index>(numFrames));
  Eigen::Index column = 0;
  for (const auto& sequence : sequences) {
    all.middleCols(column, sequence.cols()) = sequence;
    column += sequence.cols();
  }
  const Eigen::MatrixXd logB = model.emissionLogLikelihoods(all);
  const ViterbiPath batch = viterbi(model, logB);
  const auto total = static_cast<int>(logB.cols());
  double previousAgreement = 0.0;
  for (int maxLag : {1, 2, 3, 5, 10, 20, 30, -1}) {
    OnlineViterbi online(model, {.maxLagFrames = maxLag});
    for (Eigen::Index t = 0; t < logB.cols(); ++t) online.acceptFrame(logB.col(t));
    online.finish();
    int agree = 0;
    double lagSum = 0.0;
    int maxActual = 0;
    for (int t = 0; t < total; ++t) {
      agree += online.state(t) == batch.states[static_cast<size_t>(t)];
      lagSum += online.decisionLag(t);
      maxActual = std::max(maxActual, online.decisionLag(t));
    }
    const double agreement = agree / static_cast<double>(total);
    std::printf(
        "[ INFO     ] prosody model (%d states), max lag %3d: agreement with batch %.4f, mean actual lag %.2f "
        "frames, longest %d\n",
        model.numStates(), maxLag, agreement, lagSum / total, maxActual);
    if (maxLag >= 0) {
      EXPECT_LE(maxActual, maxLag);
    }
    EXPECT_GE(agreement, previousAgreement - 0.01) << "lag " << maxLag;
    previousAgreement = agreement;
  }
  EXPECT_EQ(previousAgreement, 1.0) << "an unbounded lag equals batch";
}

}  // namespace
}  // namespace th::hmm
