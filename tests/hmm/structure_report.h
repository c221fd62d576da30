// The known sparse HMM of the structure-discovery test, and how close a trained model comes to its structure.
#pragma once

#include "hmm/hmm_model.h"
#include "hmm/sampling.h"

namespace th::test {

// Six 2-D Gaussian states on a ring, each with 2 or 3 successors (itself included): 9 edges between states.
hmm::HmmModel sparseSixStateModel();

struct StructureReport {
  int liveStates;
  int transitions;
  double stateAgreement;  // of the trained model's Viterbi path, after mapping states to the truth's
  int recoveredEdges;     // true edges (between distinct states) present in the trained model, mapped
  int spuriousEdges;      // trained edges between distinct states that the truth does not have
};

// Each trained state is mapped to the true state its Viterbi frames most often belong to.
StructureReport compareStructure(const hmm::HmmModel& truth, const hmm::HmmModel& trained, const hmm::Sample& sample);

}  // namespace th::test
