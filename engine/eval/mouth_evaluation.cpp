#include "eval/mouth_evaluation.h"

#include <cmath>

#include "core/error.h"

namespace th::eval {
namespace {

void requireSameShape(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth) {
  if (estimate.rows() != truth.rows() || estimate.cols() != truth.cols() || truth.cols() < 2 || truth.rows() < 1) {
    throw Error("mouth evaluation: the estimate and the truth must both be K x T with T >= 2");
  }
}

// Plain loops: GCC's -Wnull-dereference misreads Eigen's reductions over some dynamic temporaries.
struct Moments {
  double mean = 0.0;
  double deviation = 0.0;
};

Moments momentsOf(const Eigen::MatrixXd& m, Eigen::Index row) {
  Moments result;
  for (Eigen::Index t = 0; t < m.cols(); ++t) result.mean += m(row, t);
  result.mean /= static_cast<double>(m.cols());
  double sum = 0.0;
  for (Eigen::Index t = 0; t < m.cols(); ++t) sum += (m(row, t) - result.mean) * (m(row, t) - result.mean);
  result.deviation = std::sqrt(sum / static_cast<double>(m.cols()));
  return result;
}

}  // namespace

double averageMse(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth) {
  requireSameShape(estimate, truth);
  double total = 0.0;
  for (Eigen::Index k = 0; k < truth.rows(); ++k) {
    const Moments m = momentsOf(truth, k);
    if (!(m.deviation > 0.0)) throw Error("mouth evaluation: a truth component is constant (ε undefined)");
    double sum = 0.0;
    for (Eigen::Index t = 0; t < truth.cols(); ++t)
      sum += (estimate(k, t) - truth(k, t)) * (estimate(k, t) - truth(k, t));
    total += sum / (m.deviation * m.deviation);
  }
  return total / static_cast<double>(truth.rows() * truth.cols());
}

double averageCorrelation(const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth) {
  requireSameShape(estimate, truth);
  double total = 0.0;
  for (Eigen::Index k = 0; k < truth.rows(); ++k) {
    const Moments a = momentsOf(truth, k);
    const Moments b = momentsOf(estimate, k);
    if (!(a.deviation > 0.0) || !(b.deviation > 0.0)) continue;  // a constant estimate correlates 0
    double sum = 0.0;
    for (Eigen::Index t = 0; t < truth.cols(); ++t) sum += (truth(k, t) - a.mean) * (estimate(k, t) - b.mean);
    total += sum / (a.deviation * b.deviation);
  }
  return total / static_cast<double>(truth.rows() * truth.cols());
}

std::vector<std::pair<Eigen::Index, Eigen::Index>> commonFapRows(const std::vector<int>& estimateFaps,
                                                                 const std::vector<int>& truthFaps,
                                                                 Eigen::Index& jawPair) {
  std::vector<std::pair<Eigen::Index, Eigen::Index>> rows;
  jawPair = -1;
  for (std::size_t e = 0; e < estimateFaps.size(); ++e)
    for (std::size_t t = 0; t < truthFaps.size(); ++t)
      if (estimateFaps[e] == truthFaps[t]) {
        if (estimateFaps[e] == 3) jawPair = static_cast<Eigen::Index>(rows.size());
        rows.emplace_back(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(t));
      }
  return rows;
}

FapScores scoreFaps(const std::vector<Eigen::MatrixXd>& estimates, const std::vector<int>& estimateFaps,
                    const std::vector<animation::MouthRecording>& truth, const std::vector<int>& truthFaps) {
  if (estimates.size() != truth.size()) throw Error("scoreFaps: as many estimates as clips are needed");
  Eigen::Index jawRow = -1;
  const std::vector<std::pair<Eigen::Index, Eigen::Index>> rows = commonFapRows(estimateFaps, truthFaps, jawRow);
  if (rows.empty()) throw Error("scoreFaps: the estimate and the truth have no FAP in common");
  Eigen::Index frames = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) frames += std::min(estimates[i].cols(), truth[i].visual.cols());
  Eigen::MatrixXd estimate(static_cast<Eigen::Index>(rows.size()), frames);
  Eigen::MatrixXd actual(static_cast<Eigen::Index>(rows.size()), frames);
  Eigen::Index column = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Eigen::Index n = std::min(estimates[i].cols(), truth[i].visual.cols());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      estimate.row(static_cast<Eigen::Index>(r)).segment(column, n) = estimates[i].row(rows[r].first).head(n);
      actual.row(static_cast<Eigen::Index>(r)).segment(column, n) = truth[i].visual.row(rows[r].second).head(n);
    }
    column += n;
  }
  FapScores scores;
  scores.faps = static_cast<int>(rows.size());
  scores.frames = static_cast<int>(frames);
  scores.epsilon = averageMse(estimate, actual);
  scores.rho = averageCorrelation(estimate, actual);
  scores.jawEpsilon = scores.jawRho = std::numeric_limits<double>::quiet_NaN();
  if (jawRow >= 0) {
    scores.jawEpsilon = averageMse(estimate.row(jawRow), actual.row(jawRow));
    scores.jawRho = averageCorrelation(estimate.row(jawRow), actual.row(jawRow));
  }
  return scores;
}

std::vector<Eigen::MatrixXd> predictFaps(const animation::MouthModel& model,
                                         const std::vector<animation::MouthRecording>& clips,
                                         const animation::MouthSynthesisOptions& options, int audioShift) {
  std::vector<Eigen::MatrixXd> estimates;
  const auto n = static_cast<int>(clips.size());
  for (int i = 0; i < n; ++i) {
    const animation::MouthRecording& source = clips[static_cast<std::size_t>(((i + audioShift) % n + n) % n)];
    estimates.push_back(animation::mouthFapsOf(model, animation::synthesiseMouth(model, source.speech, options)));
  }
  return estimates;
}

}  // namespace th::eval
