// The second source paper's measures of a visual estimate (Terissi & Gómez): average mean squared error ε,
// normalised by the truth's variance per component, and average correlation coefficient ρ.
//
//   double epsilon = th::eval::averageMse(estimate, truth);        // K x T each
//   double rho = th::eval::averageCorrelation(estimate, truth);
//   th::eval::FapScores scores = th::eval::scoreFaps(th::eval::predictFaps(model, clips), faps, clips, faps);
//
// ε = (1/TK) Σₖ (1/σ²ₖ) Σₜ (o'ₜₖ − oₜₖ)²  (the mean prediction scores 1);
// ρ = (1/TK) Σₜ Σₖ (oₜₖ − μₖ)(o'ₜₖ − μ'ₖ) / (σₖ σ'ₖ)  (the mean over components of Pearson's r; 0 for a
// constant estimate). Means and deviations are over the T frames evaluated.
// Thread contract: pure functions.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "animation/mouth_data.h"
#include "animation/mouth_model.h"

namespace th::eval {

double averageMse(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth);
double averageCorrelation(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth);

// The paper's ε and ρ (above) of FAP estimates against tracked clips, over all their
// frames together: on the jaw (FAP 3) alone and on every FAP both the estimate and the truth hold.
struct FapScores {
  double jawEpsilon = 0.0;  // NaN if either side lacks FAP 3
  double jawRho = 0.0;
  double epsilon = 0.0;  // over `faps` FAPs
  double rho = 0.0;
  int faps = 0;
  int frames = 0;
};

// The FAPs an estimate and a truth both hold, as (estimate row, truth row) pairs in the estimate's order;
// `jawPair` receives the index of FAP 3's pair (-1 if either lacks it).
std::vector<std::pair<Eigen::Index, Eigen::Index>> commonFapRows(const std::vector<int>& estimateFaps,
                                                                 const std::vector<int>& truthFaps,
                                                                 Eigen::Index& jawPair);

// estimates[i] (rows: estimateFaps) against truth[i].visual (rows: truthFaps), each cut to the shorter.
FapScores scoreFaps(const std::vector<Eigen::MatrixXd>& estimates, const std::vector<int>& estimateFaps,
                    const std::vector<animation::MouthRecording>& truth, const std::vector<int>& truthFaps);

// A mouth model's FAPs (rows: mouthFapNumbers(model)) for each clip's audio; with audioShift k, clip i gets
// clip (i + k) mod n's audio instead (a baseline: the right kind of sound, the wrong words).
std::vector<Eigen::MatrixXd> predictFaps(const animation::MouthModel& model,
                                         const std::vector<animation::MouthRecording>& clips,
                                         const animation::MouthSynthesisOptions& options = {}, int audioShift = 0);

}  // namespace th::eval
