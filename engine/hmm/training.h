// Training an HMM with Gaussian-mixture emissions from several observation sequences: k-means++ initialisation,
// then Baum-Welch (EM) until the log posterior stops improving.
//
//   th::hmm::TrainingOptions options;
//   options.numStates = 12;
//   th::hmm::TrainingResult result = th::hmm::trainHmm(sequences /* each d x T */, options);
//   result.model;  result.history;   // log-likelihood and log posterior of every iteration
//
// The multinomial M-steps (π, transition rows, mixture weights) go through `EstimationHooks::multinomial`, so
// Brand's entropic MAP estimator can replace the ordinary normalisation; with it unset, training is maximum
// likelihood. An M-step that changes the model's structure (trims parameters or states) is kept only if the next
// E-step confirms that the log posterior, under the prior the step was taken with, did not fall; otherwise it is
// taken again trimming more cautiously, and finally without trimming. So every step of the history is an improvement
// under its own prior. Thread contract: pure function of its arguments (deterministic for a given seed).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "hmm/hmm_model.h"

namespace th::hmm {

struct TrainingOptions {
  int numStates = 8;
  int numMixtures = 1;
  CovarianceType covariance = CovarianceType::kFull;
  int maxIterations = 100;
  double tolerance = 1e-6;  // stop when the log posterior per frame improves by less than this
  unsigned seed = 1;
  double varianceFloorFraction = 1e-3;  // variance floor: this fraction of the data's variance, per dimension
  int kmeansIterations = 20;
};

struct IterationRecord {
  double logLikelihood = 0.0;  // Σ over sequences of log P(X | model), before this iteration's M-step
  double logPrior = 0.0;       // of the model that produced it, under this iteration's prior (0 for ML)
  int liveStates = 0;
  // Log posterior after this iteration's M-step minus before, both under this iteration's prior (with an
  // annealed prior the records' own log posteriors are under different priors and not comparable).
  double stepGain = 0.0;
  // M-steps redone because their trimming lowered the log posterior (each retry trims more cautiously, the
  // last not at all).
  int trimRetries = 0;
  int statesMerged = 0;  // merges kept after this iteration's M-step (their gain is in stepGain)
  double logPosterior() const { return logLikelihood + logPrior; }
};

struct TrainingResult {
  HmmModel model;
  std::vector<IterationRecord> history;
  bool converged = false;
};

// Which multinomial an estimator is asked for.
enum class Multinomial { kInitial, kTransitionRow, kMixtureWeights };

// Which M-step is being taken: the iteration (an annealed prior depends on it) and whether the step may trim.
struct MStepContext {
  int iteration = 0;
  bool mayTrim = true;
  double trimMargin = 1.0;  // trim only when the prior's gain exceeds the likelihood's loss this many times
};

// Statistics the M-step hands to a multinomial estimator: expected counts ω (computed at `previous`, the θ the
// E-step used), returns the new θ on the simplex.
using MultinomialEstimator = std::function<Eigen::VectorXd(
    Multinomial which, const Eigen::VectorXd& counts, const Eigen::VectorXd& previous, const MStepContext& context)>;

struct EstimationHooks {
  MultinomialEstimator multinomial;  // unset: θ = ω / Σω
  // Log prior of a multinomial θ at an iteration (added to the log likelihood to form the log posterior);
  // unset: 0.
  std::function<double(const Eigen::VectorXd& theta, int iteration)> multinomialLogPrior;
  // Entropic prior on each Gaussian, P(Σ) ∝ exp(−Z_Σ·H(N(μ, Σ))) ∝ |Σ|^(−Z_Σ/2): Σ = S / (Γ + Z_Σ).
  double covariancePriorWeight = 0.0;
  // Called after each M-step with the E-step's expected frames per state (e.g. to delete dead states); may
  // change the model's size.
  std::function<void(HmmModel& model, const Eigen::VectorXd& stateOccupancy, const MStepContext& context)> afterMStep;
  // The first iteration from which the prior no longer changes (an annealed prior rises before it). Training
  // neither declares convergence nor merges states before it.
  int priorFinalFrom = 0;
  // Once the prior has settled, after each iteration try merging this many of the most similar state pairs
  // (state_merging.h), keeping the first merge that raises the log posterior. 0: never.
  int stateMergeCandidates = 0;
};

// Expected sufficient statistics of one E-step over all sequences.
struct SufficientStatistics {
  double logLikelihood = 0.0;
  Eigen::VectorXd initialCounts;                            // N
  Eigen::MatrixXd transitionCounts;                         // N x N
  Eigen::VectorXd stateOccupancy;                           // N
  std::vector<Eigen::VectorXd> componentCounts;             // per state: M
  std::vector<Eigen::MatrixXd> firstMoments;                // per state: d x M
  std::vector<std::vector<Eigen::MatrixXd>> secondMoments;  // per state, component: d x d (lower) or d x 1 (diag)
};

SufficientStatistics expectationStep(const HmmModel& model, const std::vector<Eigen::MatrixXd>& sequences);

// Re-estimates `model` in place from statistics computed at it.
void maximisationStep(HmmModel& model, const SufficientStatistics& statistics, const Eigen::VectorXd& varianceFloor,
                      const EstimationHooks& hooks, const MStepContext& context);

HmmModel initialiseWithKMeans(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options);

TrainingResult trainHmm(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options,
                        const EstimationHooks& hooks = {});

// One EM iteration on `model` in place (no check of its effect); returns the record of the model it started from.
IterationRecord baumWelchIteration(HmmModel& model, const std::vector<Eigen::MatrixXd>& sequences,
                                   const Eigen::VectorXd& varianceFloor, const EstimationHooks& hooks,
                                   const MStepContext& context = {});

// The log prior of a whole model under `hooks` at an iteration (π, transition rows, mixture weights, covariances).
double modelLogPrior(const HmmModel& model, const EstimationHooks& hooks, int iteration);

// Per-dimension variance floor for a data set.
Eigen::VectorXd varianceFloorFor(const std::vector<Eigen::MatrixXd>& sequences, double fraction);

}  // namespace th::hmm
