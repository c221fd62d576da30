#include "structure_report.h"

#include <cmath>
#include <numbers>

#include "hmm/entropic_training.h"
#include "hmm/viterbi.h"

namespace th::test {

using namespace th::hmm;

// Six 2-D Gaussian states on a ring, each with 2 or 3 successors (itself included).
hmm::HmmModel sparseSixStateModel() {
  HmmModel model;
  const int n = 6;
  model.initial = Eigen::VectorXd::Constant(n, 1.0 / n);
  model.transition = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    model.transition(i, i) = 0.8;
    if (i % 2 == 0) {
      model.transition(i, (i + 1) % n) = 0.2;
    } else {
      model.transition(i, (i + 1) % n) = 0.12;
      model.transition(i, (i + 3) % n) = 0.08;
    }
    const double angle = 2.0 * std::numbers::pi * i / n;
    Eigen::Vector2d mean(4.0 * std::cos(angle), 4.0 * std::sin(angle));
    model.states.emplace_back(
        Eigen::VectorXd::Ones(1),
        std::vector<Gaussian>{Gaussian(mean, 0.5 * Eigen::Matrix2d::Identity(), CovarianceType::kFull)});
  }
  return model;
}

StructureReport compareStructure(const HmmModel& truth, const HmmModel& trained, const Sample& sample) {
  StructureReport report{trained.numStates(), countTransitions(trained, 1e-6), 0.0, 0, 0};
  const std::vector<int> path = viterbi(trained, trained.emissionLogLikelihoods(sample.frames)).states;
  // Map each trained state to the true state it most often coincides with.
  Eigen::MatrixXd overlap = Eigen::MatrixXd::Zero(trained.numStates(), truth.numStates());
  for (size_t t = 0; t < path.size(); ++t) overlap(path[t], sample.states[t]) += 1.0;
  std::vector<int> mapped(static_cast<size_t>(trained.numStates()));
  double agree = 0.0;
  for (int j = 0; j < trained.numStates(); ++j) {
    Eigen::Index best = 0;
    agree += overlap.row(j).maxCoeff(&best);
    mapped[static_cast<size_t>(j)] = static_cast<int>(best);
  }
  report.stateAgreement = agree / static_cast<double>(path.size());
  Eigen::MatrixXi found = Eigen::MatrixXi::Zero(truth.numStates(), truth.numStates());
  for (int i = 0; i < trained.numStates(); ++i) {
    for (int j = 0; j < trained.numStates(); ++j) {
      const int a = mapped[static_cast<size_t>(i)];
      const int b = mapped[static_cast<size_t>(j)];
      if (trained.transition(i, j) > 1e-6 && a != b) {
        found(a, b) = 1;
      }
    }
  }
  for (int a = 0; a < truth.numStates(); ++a) {
    for (int b = 0; b < truth.numStates(); ++b) {
      if (a == b || !found(a, b)) continue;
      if (truth.transition(a, b) > 0.0) {
        ++report.recoveredEdges;
      } else {
        ++report.spuriousEdges;
      }
    }
  }
  return report;
}

}  // namespace th::test
