// Training with Brand's entropic prior: MAP multinomials with parameter extinction, MAP covariances, and the
// deletion of states that nothing can reach any more.
//
//   th::hmm::EntropicPrior prior{.multinomialWeight = 0.5 * totalFrames, .covarianceWeight = 0.0};
//   auto result = th::hmm::trainHmm(sequences, options, th::hmm::entropicHooks(prior));
//
// The weight Z is absolute: it is set against the expected counts, which grow with the data. Z = 1 (Brand's
// default) barely moves rows estimated from thousands of frames; structure discovery on real amounts of data
// needs Z of the order of the counts themselves (e.g. a fraction of the number of frames). The covariance
// prior has its own weight because a large Z shrinks a small state's covariance by Γ/(Γ + Z).
// Each multinomial M-step (from the second on) first trims the entries of the current θ whose entropy gradient
// outweighs their likelihood gradient (judged with the E-step's counts at that θ), then solves the MAP row on
// what is left, keeping the current row when that scores higher (generalised EM).
// A state is deleted once it is unreachable (π and every incoming transition from another state are 0), which
// leaves the likelihood unchanged; rows that pointed to it are renormalised.
// Thread contract: the hooks are stateless (the iteration comes with each call); share them freely.
#pragma once

#include "hmm/training.h"

namespace th::hmm {

struct EntropicPrior {
  double multinomialWeight = 1.0;  // Z for π, transition rows and mixture weights
  double covarianceWeight = 0.0;   // Z_Σ
  bool trim = true;                // parameter extinction and dead-state deletion
  // Annealing: maximum likelihood for the first warmupIterations (the emissions settle first), then Z rises
  // linearly to its full value over rampIterations. With both 0 the prior is fixed from the start, and the log
  // posterior is comparable (and non-decreasing) from one iteration to the next.
  int warmupIterations = 0;
  int rampIterations = 0;
  // State merging (state_merging.h): pairs tried per iteration once Z has settled, kept only if the log
  // posterior rises (0: none). Only with trim and Z > 0.
  int mergeCandidates = 8;

  double weightAt(int iteration) const;  // Z at an iteration of the schedule
};

EstimationHooks entropicHooks(const EntropicPrior& prior);

// Removes state j: its row and column of A, its entry of π, its emission density; renormalises the rows.
void deleteState(HmmModel& model, int state);

// Non-zero transitions between distinct states, and states that can be reached (π > 0 or an incoming edge).
int countTransitions(const HmmModel& model, double threshold = 0.0);

}  // namespace th::hmm
