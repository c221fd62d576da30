// Entropic MAP for a multinomial, solved in log space (docs/hmm.md, "The entropic prior, and what Z means"; Brand
// 1999).
//
// Write μ = λ/Z and, for each observed entry, rᵢ = ωᵢ/|Z| and uᵢ = log rᵢ + 1 + μ. Substituting θᵢ = rᵢ/yᵢ into
// the stationarity of the Lagrangian, ωᵢ/θᵢ + Z(log θᵢ + 1) + λ = 0 (Brand 1999; entropic.h), gives
//   Z > 0:  yᵢ − log yᵢ = −uᵢ,  yᵢ ≥ 1   (yᵢ = −W₋₁(−e^uᵢ); needs uᵢ ≤ −1)
//   Z < 0:  yᵢ + log yᵢ =  uᵢ,  yᵢ > 0   (yᵢ =  W₀(e^uᵢ); any uᵢ)
// so no e^(1+λ/Z) is ever formed: with thousands of counts λ ≈ −Σω and that exponential underflows to 0, which
// is what breaks the direct formula θ = −(ω/Z)/W(−(ω/Z)e^(1+λ/Z)).
// Σθ is monotonic in μ (increasing for Z > 0, decreasing for Z < 0), so one scalar root search for Σθ = 1
// finishes the job: Newton's method kept inside a bracket, bisecting whenever Newton leaves it.
//
// Z > 0 has a square-root singularity at the top of its range, μ_max = minᵢ(−2 − log rᵢ), where the largest
// entry reaches the branch point y = 1 (there dθ/dμ = ∞, and y is ill-conditioned in u). The search therefore
// runs in t = √(μ_max − μ) instead, where every entry is smooth, and each yᵢ is found from its excess over the
// branch point, −uᵢ − 1 = δᵢ + t² with δᵢ = log r_max − log rᵢ ≥ 0, which is exact to rounding in t and δᵢ.
#include "hmm/entropic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace th::hmm {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
// Below this |Z|/Σω the prior moves θ by less than a rounding error (its pull on log θ is Z·|log θ| ≤ 745·Z
// against Σω), and μ = λ/Z would overflow; such a Z is treated as 0.
constexpr double kNegligiblePriorFraction = 1e-20;
constexpr int kMaxInnerIterations = 60;
constexpr int kMaxOuterIterations = 200;

// d − log(1 + d) for d ≥ 0, without the cancellation of the direct form for small d: there the series
// Σₖ≥₂ (−1)ᵏ dᵏ/k, 16 terms (0.1¹⁸/18 < ε·0.1²/2), by Horner.
double gapAboveBranchPoint(double d) {
  if (d > 0.1) return d - std::log1p(d);
  double sum = 0.0;
  for (int k = 17; k >= 2; --k) sum = (k % 2 == 0 ? 1.0 : -1.0) / k + d * sum;
  return d * d * sum;
}

// d = y − 1 ≥ 0 where y − log y = 1 + excess (excess ≥ 0), i.e. y = −W₋₁(−e^(−1−excess)).
// Start: near the branch point the series y = 1 + p + p²/3 + p³/36 + ..., p = √(2·excess) (from
// y − 1 − log y = d²/2 − d³/3 + d⁴/4 − ...); far from it y ≈ r + log(r + log r), r = 1 + excess (iterate
// y = r + log y). Newton on g(d) = d − log(1 + d) − excess, convex and increasing for d > 0, then converges in a
// few steps. Newton's next error is about step²·g″/(2g′) = step²/(2d(1 + d)), below ε·d once |step| ≤ 1e-8·d:
// stop there, or when a step stops shrinking (rounding noise).
double solveUpperBranchOffset(double excess) {
  if (!(excess > 0.0)) return 0.0;
  double d;
  if (excess < 2.0) {
    const double p = std::sqrt(2.0 * excess);
    d = p * (1.0 + p * (1.0 / 3.0 + p / 36.0));
  } else {
    const double r = 1.0 + excess;
    d = r + std::log(r + std::log(r)) - 1.0;
  }
  double previousStep = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < kMaxInnerIterations; ++iteration) {
    const double step = (gapAboveBranchPoint(d) - excess) * (1.0 + d) / d;  // g / g', g' = d / (1 + d)
    const double next = std::max(0.5 * d, d - step);  // the root is never below half the current d from the left
    const double size = std::abs(next - d);
    d = next;
    if (size <= 1e-8 * d) break;
    if (iteration >= 2 && size >= previousStep) break;
    previousStep = size;
  }
  return d;
}

// w = log y where y + log y = u (y = W₀(e^u)), i.e. e^w + w = u. Works in w so that neither e^u nor y overflows.
// h(w) = e^w + w − u is convex and increasing; both starts lie at or right of the root (u ≥ 1: y ≤ u since
// log y ≥ 0; u < 1: w = u − y < u), so Newton converges monotonically; its next error is below step²/2, under
// ε once |step| ≤ 1e-8.
double solveLogLowerBranch(double u) {
  double w = u >= 1.0 ? std::log(u) : u;
  double previousStep = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < kMaxInnerIterations; ++iteration) {
    const double ew = std::exp(w);
    const double step = (ew + w - u) / (ew + 1.0);
    w -= step;
    const double size = std::abs(step);
    if (size <= 1e-8) break;
    if (iteration >= 2 && size >= previousStep) break;
    previousStep = size;
  }
  return w;
}

struct RowSum {
  double sum = 0.0;         // Σθᵢ over the observed entries
  double derivative = 0.0;  // its derivative in the search variable
};

// The observed entries of one row and Σθ over them, in the search variable of each branch.
class ObservedRow {
 public:
  ObservedRow(const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight)
      : size_((counts.array() > 0.0).count()) {
    index_.resize(size_);
    ratio_.resize(size_);
    Eigen::Index k = 0;
    for (Eigen::Index i = 0; i < counts.size(); ++i) {
      if (counts[i] > 0.0) {
        index_[k] = i;
        ratio_[k] = counts[i] / std::abs(priorWeight);
        ++k;
      }
    }
    logRatio_ = ratio_.log();
    logRatioBelowMax_ = logRatio_.maxCoeff() - logRatio_;
    theta_.resize(size_);
  }

  Eigen::Index size() const { return size_; }
  double maxRatio() const { return ratio_.maxCoeff(); }
  double maxLogRatio() const { return logRatio_.maxCoeff(); }
  double maxAbsLogRatio() const { return logRatio_.abs().maxCoeff(); }

  // Z > 0 at μ = μ_max − t²: θᵢ = rᵢ/(1 + dᵢ), dᵢ − log(1 + dᵢ) = δᵢ + t². Σθ decreases with t.
  // dθᵢ/dt = −θᵢ/(1 + dᵢ)·d′(dᵢ) = −2t θᵢ/dᵢ, whose limit at the branch point (t = δᵢ = 0, dᵢ ≈ √2 t) is −√2 θᵢ.
  RowSum evaluateUpperBranch(double t) {
    RowSum result;
    for (Eigen::Index k = 0; k < size_; ++k) {
      const double d = solveUpperBranchOffset(logRatioBelowMax_[k] + t * t);
      theta_[k] = ratio_[k] / (1.0 + d);
      result.sum += theta_[k];
      if (d > 0.0) {
        result.derivative -= 2.0 * t * theta_[k] / d;
      } else if (logRatioBelowMax_[k] == 0.0) {
        result.derivative -= std::sqrt(2.0) * theta_[k];
      }
    }
    return result;
  }

  // Z < 0 at μ: θᵢ = rᵢ e^(−wᵢ), e^wᵢ + wᵢ = log rᵢ + 1 + μ. Σθ decreases with μ: dθᵢ/dμ = −θᵢ/(1 + e^wᵢ).
  RowSum evaluateLowerBranch(double mu) {
    RowSum result;
    for (Eigen::Index k = 0; k < size_; ++k) {
      const double w = solveLogLowerBranch(logRatio_[k] + 1.0 + mu);
      theta_[k] = std::exp(logRatio_[k] - w);
      result.sum += theta_[k];
      result.derivative -= theta_[k] / (1.0 + std::exp(w));
    }
    return result;
  }

  const Eigen::ArrayXd& theta() const { return theta_; }
  Eigen::Index index(Eigen::Index k) const { return index_[k]; }

 private:
  Eigen::Index size_;
  Eigen::Array<Eigen::Index, Eigen::Dynamic, 1> index_;  // position of each observed entry in the row
  Eigen::ArrayXd ratio_;                                 // rᵢ = ωᵢ/|Z|
  Eigen::ArrayXd logRatio_;                              // log rᵢ
  Eigen::ArrayXd logRatioBelowMax_;                      // δᵢ = log r_max − log rᵢ ≥ 0
  Eigen::ArrayXd theta_;
};

// x in [lower, upper] with Σθ(x) = 1, Σθ decreasing in x: Σθ(lower) ≥ 1 ≥ Σθ(upper). `evaluate(x)` fills θ(x).
// Newton inside the bracket; bisection when Newton would leave it or has no usable derivative. Stops when
// Σθ − 1 is at the level of its own rounding (m·ε), the bracket or Newton's step reaches ε·max(|x|, scale)
// (`scale`: the resolution below which x no longer changes θ), or after kMaxOuterIterations. Returns the last
// x evaluated, so the row's θ belongs to it.
template <typename Evaluate>
double solveForUnitSum(Evaluate&& evaluate, double lower, double upper, double guess, double scale,
                       double numObserved) {
  const double sumTolerance = 2.0 * numObserved * kEpsilon;
  double x = std::clamp(guess, lower, upper);
  for (int iteration = 0; iteration < kMaxOuterIterations; ++iteration) {
    const RowSum row = evaluate(x);
    const double excess = row.sum - 1.0;
    if (std::abs(excess) <= sumTolerance) return x;
    (excess > 0.0 ? lower : upper) = x;
    if (upper - lower <= 2.0 * kEpsilon * std::max({std::abs(lower), std::abs(upper), scale})) return x;
    const double step = excess / row.derivative;
    double next = x - step;
    if (!std::isfinite(step) || step == 0.0 || !(next > lower && next < upper)) {
      next = lower + 0.5 * (upper - lower);
    } else if (std::abs(step) <= 2.0 * kEpsilon * std::max(std::abs(x), scale)) {
      evaluate(next);
      return next;
    }
    x = next;
  }
  return x;  // not reached in practice; θ belongs to the last bisection or Newton point evaluated
}

void requireValidCounts(const Eigen::Ref<const Eigen::VectorXd>& counts, const char* function) {
  if (counts.size() == 0) throw std::invalid_argument(std::string(function) + ": no counts");
  for (Eigen::Index i = 0; i < counts.size(); ++i) {
    if (!std::isfinite(counts[i]) || counts[i] < 0.0) {
      throw std::invalid_argument(std::string(function) + ": count " + std::to_string(i) + " is " +
                                  std::to_string(counts[i]) + " (counts must be finite and >= 0)");
    }
  }
  if (!std::isfinite(counts.sum())) throw std::invalid_argument(std::string(function) + ": counts sum to infinity");
}

void requireFinitePriorWeight(double priorWeight, const char* function) {
  if (!std::isfinite(priorWeight)) {
    throw std::invalid_argument(std::string(function) + ": prior weight Z is " + std::to_string(priorWeight));
  }
}

EntropicEstimate finish(Eigen::VectorXd probabilities, EntropicOutcome outcome, std::optional<double> multiplier,
                        const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight) {
  // One NaN in a transition row silently kills every state on the next pass: never hand one out.
  if (!probabilities.allFinite() || (multiplier && !std::isfinite(*multiplier))) {
    throw std::logic_error("entropicMap: non-finite estimate (internal error)");
  }
  EntropicEstimate estimate;
  estimate.objective = entropicObjective(probabilities, counts, priorWeight);
  estimate.probabilities = std::move(probabilities);
  estimate.outcome = outcome;
  estimate.lagrangeMultiplier = multiplier;
  return estimate;
}

}  // namespace

EntropicEstimate entropicMap(const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight) {
  requireValidCounts(counts, "entropicMap");
  requireFinitePriorWeight(priorWeight, "entropicMap");
  const Eigen::Index numEntries = counts.size();
  const double total = counts.sum();

  if (total == 0.0) {
    // No evidence: for Z < 0 uniform is the maximum; for Z ≥ 0 every point (Z = 0) or every vertex (Z > 0)
    // ties, and uniform is the choice that keeps a dead state's row stochastic without inventing structure.
    return finish(Eigen::VectorXd::Constant(numEntries, 1.0 / static_cast<double>(numEntries)),
                  EntropicOutcome::kNoCounts, std::nullopt, counts, priorWeight);
  }
  // Ordinary normalisation, the same expression bit for bit as ω / Σω in the caller. λ = −Σω.
  const auto maximumLikelihood = [&] { return Eigen::VectorXd(counts / total); };
  if (priorWeight == 0.0 || std::abs(priorWeight) <= kNegligiblePriorFraction * total) {
    return finish(maximumLikelihood(), EntropicOutcome::kMaximumLikelihood, -total, counts, priorWeight);
  }

  ObservedRow row(counts, priorWeight);
  if (row.size() == 1) {
    // One observed entry: the face is a single vertex, θ = eₖ, and stationarity gives λ = −ωₖ − Z.
    Eigen::VectorXd probabilities = Eigen::VectorXd::Zero(numEntries);
    probabilities[row.index(0)] = 1.0;
    return finish(std::move(probabilities), EntropicOutcome::kStationary, -counts[row.index(0)] - priorWeight, counts,
                  priorWeight);
  }

  const double numObserved = static_cast<double>(row.size());
  const double maxRatio = row.maxRatio();
  // Start from the multiplier of the ML row, λ ≈ −Σω − Z(1 + Σ θ log θ): right to O(Z/Σω) when counts are large.
  const double guessMu = -total / priorWeight - 1.0 - entropicLogPrior(counts / total, 1.0);
  double mu;
  if (priorWeight > 0.0) {
    // W₋₁ needs every uᵢ ≤ −1: μ ≤ μ_max, where the largest count sits at the branch point (θ = r, its largest
    // value on this branch). Σθ(μ_max) < 1 means no W₋₁ solution: too little evidence for this Z.
    const double muMax = -2.0 - row.maxLogRatio();
    // (When r_max ≥ 1 that entry alone has θ ≥ 1 there, and the check is skipped.)
    if (maxRatio < 1.0 && row.evaluateUpperBranch(0.0).sum < 1.0) {
      return finish(maximumLikelihood(), EntropicOutcome::kNoW1Solution, std::nullopt, counts, priorWeight);
    }
    // At λ = −m·ω_max − Z every θᵢ ≤ 1/m (the stationarity's left side −ω/θ − Z log θ − Z increases with θ on
    // this branch and is ≥ λ at θ = 1/m), so Σθ ≤ 1 there: μ_lo = −m·r_max − 1, t_hi = √(μ_max − μ_lo).
    const double upperT = std::sqrt(std::max(0.0, muMax + numObserved * maxRatio + 1.0));
    const double guessT = std::sqrt(std::max(0.0, muMax - guessMu));
    const double t = solveForUnitSum([&](double x) { return row.evaluateUpperBranch(x); }, 0.0, upperT, guessT,
                                     kEpsilon, numObserved);
    mu = muMax - t * t;
  } else {
    // Z = −s < 0. The stationarity's left side s(log θ + 1) − ω/θ increases with θ; at θ = 1 it equals λ for the
    // largest count when λ = s − ω_max (so Σθ ≥ 1), and at θ = 1/m every entry has θ ≤ 1/m when
    // λ = s(1 − log m) − m·ω_max (so Σθ ≤ 1). In μ = λ/Z = −λ/s:
    const double lowerMu = maxRatio - 1.0;
    const double upperMu = numObserved * maxRatio - 1.0 + std::log(numObserved);
    mu = solveForUnitSum([&](double x) { return row.evaluateLowerBranch(x); }, lowerMu, upperMu, guessMu,
                         1.0 + row.maxAbsLogRatio(), numObserved);
  }

  Eigen::VectorXd probabilities = Eigen::VectorXd::Zero(numEntries);
  const double sum = row.theta().sum();
  // The root search leaves |Σθ − 1| at the rounding level; dividing it out changes each term of the
  // stationarity by the same relative amount.
  for (Eigen::Index k = 0; k < row.size(); ++k) probabilities[row.index(k)] = row.theta()[k] / sum;
  return finish(std::move(probabilities), EntropicOutcome::kStationary, priorWeight * mu, counts, priorWeight);
}

double entropicLogPrior(const Eigen::Ref<const Eigen::VectorXd>& probabilities, double priorWeight) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < probabilities.size(); ++i) {
    if (probabilities[i] > 0.0) sum += probabilities[i] * std::log(probabilities[i]);
  }
  return priorWeight * sum;
}

double entropicObjective(const Eigen::Ref<const Eigen::VectorXd>& probabilities,
                         const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight) {
  if (probabilities.size() != counts.size()) {
    throw std::invalid_argument("entropicObjective: probabilities and counts differ in length");
  }
  double logLikelihood = 0.0;
  for (Eigen::Index i = 0; i < counts.size(); ++i) {
    if (counts[i] > 0.0) logLikelihood += counts[i] * std::log(probabilities[i]);
  }
  return logLikelihood + entropicLogPrior(probabilities, priorWeight);
}

int trimWeakParameters(Eigen::Ref<Eigen::VectorXd, 0, Eigen::InnerStride<>> probabilities,
                       const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight, double margin) {
  requireValidCounts(counts, "trimWeakParameters");
  requireFinitePriorWeight(priorWeight, "trimWeakParameters");
  if (probabilities.size() != counts.size()) {
    throw std::invalid_argument("trimWeakParameters: probabilities and counts differ in length");
  }
  double mass = 0.0;
  for (Eigen::Index i = 0; i < probabilities.size(); ++i) {
    if (!std::isfinite(probabilities[i]) || probabilities[i] < 0.0) {
      throw std::invalid_argument("trimWeakParameters: probability " + std::to_string(i) + " is " +
                                  std::to_string(probabilities[i]));
    }
    mass += probabilities[i];
  }
  if (!(mass > 0.0)) throw std::invalid_argument("trimWeakParameters: the row has no mass to begin with");
  if (priorWeight <= 0.0) return 0;

  // Brand 1999 ("Trimming"): zeroing θᵢ changes the log prior by about −θᵢ·∂(Z Σθ log θ)/∂θᵢ = −Z θᵢ(log θᵢ + 1)
  // and the log likelihood by about −θᵢ·ωᵢ/θᵢ = −ωᵢ; trim when the first gain exceeds the second loss.
  std::vector<Eigen::Index> trimmed;
  Eigen::Index largest = 0;
  int numPositive = 0;
  for (Eigen::Index i = 0; i < probabilities.size(); ++i) {
    const double theta = probabilities[i];
    if (theta <= 0.0) continue;
    ++numPositive;
    if (theta > probabilities[largest]) largest = i;
    if (-priorWeight * theta * (std::log(theta) + 1.0) > margin * counts[i]) trimmed.push_back(i);
  }
  if (trimmed.empty()) return 0;
  if (static_cast<int>(trimmed.size()) == numPositive) {
    trimmed.erase(std::find(trimmed.begin(), trimmed.end(), largest));  // never empty the row
  }
  for (Eigen::Index i : trimmed) probabilities[i] = 0.0;
  if (!trimmed.empty()) probabilities /= probabilities.sum();
  return static_cast<int>(trimmed.size());
}

}  // namespace th::hmm
