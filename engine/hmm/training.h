// Training an HMM with Gaussian-mixture emissions from several observation sequences: k-means++ initialisation,
// then Baum-Welch (EM) until the log posterior stops improving.
//
//   th::hmm::TrainingOptions options;
//   options.numStates = 12;
//   th::hmm::TrainingResult result = th::hmm::trainHmm(sequences /* each d x T */, options);
//   result.model;  result.history;   // log-likelihood and log posterior of every iteration
//
// The multinomial M-steps (π, transition rows, mixture weights) go through `multinomialMStep`, so Brand's
// entropic MAP estimator can replace the ordinary normalisation; with it unset, training is maximum likelihood.
// Thread contract: pure function of its arguments (deterministic for a given seed).
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
  double tolerance = 1e-6;        // stop when the log posterior per frame improves by less than this
  unsigned seed = 1;
  double varianceFloorFraction = 1e-3;  // variance floor: this fraction of the data's variance, per dimension
  int kmeansIterations = 20;
};

struct IterationRecord {
  double logLikelihood = 0.0;   // Σ over sequences of log P(X | model), before this iteration's M-step
  double logPrior = 0.0;        // of the model that produced it (0 for maximum likelihood)
  int liveStates = 0;
  double logPosterior() const { return logLikelihood + logPrior; }
};

struct TrainingResult {
  HmmModel model;
  std::vector<IterationRecord> history;
  bool converged = false;
};

// Which multinomial an estimator is asked for.
enum class Multinomial { kInitial, kTransitionRow, kMixtureWeights };

// Statistics the M-step hands to a multinomial estimator: expected counts ω (computed at `previous`, the θ the
// E-step used), returns the new θ on the simplex.
using MultinomialEstimator = std::function<Eigen::VectorXd(Multinomial which, const Eigen::VectorXd& counts,
                                                           const Eigen::VectorXd& previous)>;

struct EstimationHooks {
  MultinomialEstimator multinomial;  // unset: θ = ω / Σω
  // Log prior of a multinomial θ (added to the log likelihood to form the log posterior); unset: 0.
  std::function<double(const Eigen::VectorXd& theta)> multinomialLogPrior;
  // Entropic prior on each Gaussian, P(Σ) ∝ exp(−Z_Σ·H(N(μ, Σ))) ∝ |Σ|^(−Z_Σ/2): Σ = S / (Γ + Z_Σ).
  double covariancePriorWeight = 0.0;
  // Called after each M-step (e.g. to delete dead states); may change the model's size.
  std::function<void(HmmModel& model, const Eigen::VectorXd& stateOccupancy)> afterMStep;
};

HmmModel initialiseWithKMeans(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options);

TrainingResult trainHmm(const std::vector<Eigen::MatrixXd>& sequences, const TrainingOptions& options,
                        const EstimationHooks& hooks = {});

// One EM iteration on `model` in place; returns the record of the model it started from.
IterationRecord baumWelchIteration(HmmModel& model, const std::vector<Eigen::MatrixXd>& sequences,
                                   const TrainingOptions& options, const Eigen::VectorXd& varianceFloor,
                                   const EstimationHooks& hooks);

// The log prior of a whole model under `hooks` (π, every transition row, every state's mixture weights).
double modelLogPrior(const HmmModel& model, const EstimationHooks& hooks);

// Per-dimension variance floor for a data set.
Eigen::VectorXd varianceFloorFor(const std::vector<Eigen::MatrixXd>& sequences, double fraction);

}  // namespace th::hmm
