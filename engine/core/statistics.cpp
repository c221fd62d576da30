#include "core/statistics.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace th {

double mean(const Eigen::Ref<const Eigen::RowVectorXd>& values) {
  if (values.size() == 0) return 0.0;
  double sum = 0.0;
  for (Eigen::Index t = 0; t < values.size(); ++t) sum += values[t];
  return sum / static_cast<double>(values.size());
}

double standardDeviation(const Eigen::RowVectorXd& values) {
  if (values.size() == 0) return 0.0;
  const double average = mean(values);
  double sum = 0.0;
  for (Eigen::Index t = 0; t < values.size(); ++t) sum += (values[t] - average) * (values[t] - average);
  return std::sqrt(sum / static_cast<double>(values.size()));
}

double pearsonCorrelation(const Eigen::Ref<const Eigen::RowVectorXd>& a,
                          const Eigen::Ref<const Eigen::RowVectorXd>& b) {
  if (a.size() != b.size()) throw Error("correlation of sequences of different lengths");
  const double meanA = mean(a);
  const double meanB = mean(b);
  double xy = 0.0;
  double xx = 0.0;
  double yy = 0.0;
  for (Eigen::Index t = 0; t < a.size(); ++t) {
    const double x = a[t] - meanA;
    const double y = b[t] - meanB;
    xy += x * y;
    xx += x * x;
    yy += y * y;
  }
  const double denominator = std::sqrt(xx * yy);
  return denominator > 0.0 ? xy / denominator : 0.0;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
}

double quantile(const Eigen::RowVectorXd& values, double q) {
  return quantile(std::vector<double>(values.begin(), values.end()), q);
}

void MillisecondHistogram::add(double ms) {
  const auto bin = static_cast<std::size_t>(std::clamp(ms, 0.0, 99.99) * 100.0);
  ++counts_[bin];
  ++total_;
  largest_ = std::max(largest_, ms);
}

double MillisecondHistogram::percentile(double p) const {
  if (total_ == 0) return 0.0;
  const auto rank = static_cast<std::uint64_t>(p / 100.0 * static_cast<double>(total_ - 1));
  std::uint64_t seen = 0;
  for (std::size_t bin = 0; bin < counts_.size(); ++bin) {
    seen += counts_[bin];
    if (seen > rank) return (static_cast<double>(bin) + 0.5) / 100.0;
  }
  return largest_;
}

}  // namespace th
