#include "animation/mouth_evaluation.h"

#include <cmath>

#include "core/error.h"

namespace th::animation {
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
    for (Eigen::Index t = 0; t < truth.cols(); ++t) sum += (estimate(k, t) - truth(k, t)) * (estimate(k, t) - truth(k, t));
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

}  // namespace th::animation
