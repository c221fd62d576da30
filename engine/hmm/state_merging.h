// Merging two states of a trained HMM into one, from the E-step's sufficient statistics: the structural move
// that parameter extinction lacks. The entropic prior kills transitions, and a state dies once nothing enters
// it; but a true state that EM has split in two copies keeps both (each copy is well used). Merging them
// removes a whole row of transition entropy and often sharpens the rows that entered either copy, so
// trainHmm tries the most similar pairs and keeps a merge only if the log posterior rises.
//
//   auto pairs = th::hmm::mergeCandidates(model, statistics, 3);
//   th::hmm::HmmModel merged = th::hmm::mergeStates(model, statistics, pairs[0].first, pairs[0].second, floor, 0.0);
//
// Thread contract: pure functions.
#pragma once

#include <utility>
#include <vector>

#include "hmm/training.h"

namespace th::hmm {

// The `count` pairs of states whose merge costs the emissions least: ½[Γ log|Σ_pooled| − Γa log|Σa| − Γb log|Σb|]
// summed over paired mixture components, from the statistics alone (no pass over the data). Best first.
std::vector<std::pair<int, int>> mergeCandidates(const HmmModel& model, const SufficientStatistics& statistics,
                                                 int count);

// States a and b become one (at the lower index): π and incoming transitions add up, the outgoing row and the
// densities are re-estimated from the pooled statistics (component m of a pooled with the nearest-mean
// unpaired component of b), covariances with the prior's divisor Γ + Z_Σ and the variance floor.
HmmModel mergeStates(const HmmModel& model, const SufficientStatistics& statistics, int a, int b,
                     const Eigen::VectorXd& varianceFloor, double covariancePriorWeight);

}  // namespace th::hmm
