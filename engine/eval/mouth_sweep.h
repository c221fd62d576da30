// The mouth paper's sweep (Terissi & Gómez 2008, Fig. 3): an AV-HMM trained at every point of a grid of
// covariance type, MFCC context tc, mixtures M and states N; each scored with ε and ρ on a validation part (where
// choices are made) and on the held-out part (only reported). `talkinghead eval mouth --sweep` runs it on BEAT2.
//
//   th::eval::MouthSweepGrid grid{.covariances = {kFull}, .contexts = {2, 5}, .mixtures = {2}, .states = {4, 8}};
//   std::vector<th::eval::MouthSweepPoint> points = th::eval::sweepMouthModels(grid, fit, validation, test);
//   th::eval::writeMouthSweepCsv("mouth_sweep.csv", points);
//   const th::eval::MouthSweepPoint* best = th::eval::bestOnValidation(points, hmm::CovarianceType::kFull);
//
// Thread contract: the points are trained in parallel on the machine's cores; progress is called under a lock.
#pragma once

#include <filesystem>
#include <functional>
#include <vector>

#include "animation/mouth_data.h"
#include "hmm/hmm_model.h"

namespace th::eval {

struct MouthSweepGrid {
  std::vector<hmm::CovarianceType> covariances;
  std::vector<int> contexts;  // tc, frames
  std::vector<int> mixtures;  // M
  std::vector<int> states;    // N
  int iterations = 100;       // Baum-Welch iterations at most
};

struct MouthSweepPoint {
  hmm::CovarianceType covariance;
  int contextFrames;
  int mixtures;
  int states;
  double validationEpsilon = 0.0;
  double validationRho = 0.0;
  double heldOutEpsilon = 0.0;
  double heldOutRho = 0.0;
  double seconds = 0.0;  // training and scoring, wall clock
  bool failed = false;   // the model could not be trained (e.g. more components than the data support)
};

// Every point of the grid, in grid order (covariance, then tc, M, N). progress(done, total) after each.
std::vector<MouthSweepPoint> sweepMouthModels(const MouthSweepGrid& grid, const animation::MouthRecording& fit,
                                              const animation::MouthRecording& validation,
                                              const animation::MouthRecording& heldOut,
                                              const std::function<void(std::size_t, std::size_t)>& progress = {});

// covariance_diag,tc,mixtures,states,validation_epsilon,validation_rho,seconds,heldout_epsilon,heldout_rho; a row
// per trained point (failed ones left out). Atomic.
void writeMouthSweepCsv(const std::filesystem::path& path, const std::vector<MouthSweepPoint>& points);

// The point of that covariance with the best validation ρ (nullptr if none trained); `failed` receives how many
// of that covariance could not be trained.
const MouthSweepPoint* bestOnValidation(const std::vector<MouthSweepPoint>& points, hmm::CovarianceType covariance,
                                        int* failed = nullptr);

}  // namespace th::eval
