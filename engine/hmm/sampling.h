// Drawing observation sequences from a known HMM: test data whose truth we control.
//
//   std::mt19937 random(7);
//   th::hmm::Sample sample = th::hmm::sampleHmm(model, 20000, random);   // sample.frames: d x T
//
// Thread contract: pure function (the random engine is the caller's).
#pragma once

#include <Eigen/Core>
#include <random>
#include <vector>

#include "hmm/hmm_model.h"

namespace th::hmm {

struct Sample {
  Eigen::MatrixXd frames;       // d x T
  std::vector<int> states;      // the hidden state of every frame
  std::vector<int> components;  // the mixture component that produced every frame
};

Sample sampleHmm(const HmmModel& model, int numFrames, std::mt19937& random);

}  // namespace th::hmm
