// Descriptive statistics the measures and reports share: mean, spread, quantiles, Pearson's correlation, and a
// histogram of milliseconds for percentiles over hours of frames in constant memory.
//
//   double r = th::pearsonCorrelation(predicted.row(0), truth.row(0));   // 0 when either is constant
//   double p95 = th::quantile(latenciesMs, 0.95);                         // linear between order statistics
//   th::MillisecondHistogram decode;  decode.add(1.3);  decode.percentile(50);
//
// Sequences are rows (Eigen::RowVectorXd, a matrix's row) or std::vectors; plain loops sum in frame order, so
// a figure does not depend on how Eigen vectorises a reduction.
// Thread contract: pure functions; a MillisecondHistogram belongs to one thread.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace th {

double mean(const Eigen::Ref<const Eigen::RowVectorXd>& values);
// Population standard deviation (divided by n).
double standardDeviation(const Eigen::RowVectorXd& values);
// Pearson's correlation of two sequences of the same length; 0 where either does not vary.
double pearsonCorrelation(const Eigen::Ref<const Eigen::RowVectorXd>& a, const Eigen::Ref<const Eigen::RowVectorXd>& b);
// The q-quantile (q in [0, 1], clamped), interpolated linearly between the order statistics (R's type 7;
// q = 0.5 of an even count is the mean of the two middle values). 0 for no values.
double quantile(std::vector<double> values, double q);
double quantile(const Eigen::RowVectorXd& values, double q);

// Milliseconds in 10 µs bins up to 100 ms (larger values count in the last bin, and as the largest).
class MillisecondHistogram {
 public:
  void add(double ms);
  double percentile(double p) const;  // p in [0, 100]; the centre of the bin holding that rank
  double largest() const { return largest_; }
  std::uint64_t count() const { return total_; }

 private:
  std::vector<std::uint64_t> counts_ = std::vector<std::uint64_t>(10000, 0);
  std::uint64_t total_ = 0;
  double largest_ = 0.0;
};

}  // namespace th
