// Small HMMs with known parameters, shared by the HMM tests.
#pragma once

#include "hmm/hmm_model.h"

namespace th::test {

// N states of 1-D Gaussians at 0, 3, 6, ... (σ = 1) with a "sticky" transition matrix.
hmm::HmmModel stickyModel1d(int numStates, double stay);

// A random full-covariance model of dimension d, N states, M components, with dense random transitions.
hmm::HmmModel randomModel(int numStates, int numMixtures, int dimension, hmm::CovarianceType type, unsigned seed);

}  // namespace th::test
