// Brand's entropic MAP estimate of a multinomial (a transition row, π, a state's mixture weights) and the
// trimming of weak parameters (parameter extinction).
//
//   th::hmm::EntropicEstimate row = th::hmm::entropicMap(expectedCounts, /*priorWeight Z=*/1.0);
//   if (row.outcome == th::hmm::EntropicOutcome::kNoW1Solution) { /* too little evidence: θ is the ML row */ }
//   th::hmm::trimWeakParameters(row.probabilities, countsAtThoseProbabilities, 1.0);   // zeroes, renormalises
//   double logPrior = th::hmm::entropicLogPrior(row.probabilities, 1.0);               // −Z·H(θ)
//
// Source: M. Brand, "Structure learning in conditional probability models via an entropic prior and parameter
// extinction", Neural Computation 11(5):1155–1182, 1999. The prior is P(θ) ∝ exp(−Z·H(θ)) = Πᵢ θᵢ^(Z·θᵢ),
// H(θ) = −Σ θᵢ log θᵢ; Z > 0 favours low entropy (sparse rows), Z < 0 high entropy, Z = 0 is maximum
// likelihood. Given expected counts ωᵢ ≥ 0 the MAP estimate maximises, on the simplex,
//   F(θ) = Σ ωᵢ log θᵢ + Z Σ θᵢ log θᵢ                                  (log posterior up to a constant)
// and satisfies, for every i with ωᵢ > 0, the Lagrangian stationarity
//   ωᵢ/θᵢ + Z (log θᵢ + 1) + λ = 0,   i.e.   θᵢ = −(ωᵢ/Z) / W(−(ωᵢ/Z)·e^(1 + λ/Z)),
// W the Lambert function: branch W₋₁ for Z > 0, W₀ for Z < 0 (docs/hmm.md, "The entropic prior, and what Z means";
// Brand 1999). Entries with ωᵢ = 0 get θᵢ = 0 for every Z: the maximisation is over the face of the simplex spanned by
// the observed entries, so a trimmed (absent) parameter stays absent. (For Z < 0 the unrestricted maximum would give
// such entries the mass e^(−1−λ/Z); pass a small positive count if that smoothing is wanted.)
//
// Caveat, measured: for Z > 0 the W₋₁ point is always a local maximum (each Hessian entry −ωᵢ/θᵢ² + Z/θᵢ is
// negative there) but not always the global one. When many entries are weakly supported (every ωᵢ ≪ Z, Σω of a
// few Z) a stationary point with one entry on the W₀ branch can score higher: twenty counts of 6 with Z = 100
// give F = −659.06 at the (uniform) W₋₁ point and F = −624.44 at θ ≈ (0.709, 0.0153 × 19). Likewise, when there
// is no W₋₁ solution such a mixed point beats the ML fallback. Trimming acts in exactly this regime.
//
// Thread contract: pure functions of their arguments; safe to call from any number of threads.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace th::hmm {

enum class EntropicOutcome {
  kMaximumLikelihood,  // Z = 0, or |Z| ≤ 1e-20·Σω (the prior moves θ by less than rounding): θ = ω / Σω
  kStationary,         // Z ≠ 0: θ solves the stationarity equations (W₋₁ for Z > 0, W₀ for Z < 0)
  kNoW1Solution,       // Z > 0 with too little evidence, Σθ(λ_max) < 1 (see entropic.cpp): θ = ω / Σω
  kNoCounts,           // every ωᵢ = 0: θ is uniform over all entries (keeps a dead state's row stochastic)
};

struct EntropicEstimate {
  Eigen::VectorXd probabilities;  // θ, same length as the counts, Σθ = 1
  EntropicOutcome outcome = EntropicOutcome::kMaximumLikelihood;
  // λ of the stationarity equations above; set for kMaximumLikelihood (λ = −Σω) and kStationary only.
  std::optional<double> lagrangeMultiplier;
  double objective = 0.0;  // F(θ) with this Z (0·log 0 = 0); the quantity the estimate maximises
};

// MAP estimate of θ from expected counts ω (each ≥ 0 and finite, at least one entry) under the entropic prior
// of weight Z = priorWeight (finite, any sign). Z = 0 returns exactly ω / Σω. Throws std::invalid_argument on
// bad input. Never returns a non-finite θ (checked).
EntropicEstimate entropicMap(const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight);

// Log of the (unnormalised) entropic prior: Z Σ θᵢ log θᵢ = −Z·H(θ), with 0·log 0 = 0.
double entropicLogPrior(const Eigen::Ref<const Eigen::VectorXd>& probabilities, double priorWeight);

// F(θ) = Σ ωᵢ log θᵢ + Z Σ θᵢ log θᵢ (−∞ if some ωᵢ > 0 has θᵢ = 0).
double entropicObjective(const Eigen::Ref<const Eigen::VectorXd>& probabilities,
                         const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight);

// Parameter extinction (Brand 1999, section "Trimming"): zeroes every θᵢ > 0 whose removal raises the log
// posterior to first order, i.e. where the entropy gradient outweighs the likelihood gradient,
//   −Z (log θᵢ + 1) > ωᵢ / θᵢ      (tested as −Z θᵢ (log θᵢ + 1) > ωᵢ, which cannot overflow),
// all entries judged on the input θ, then renormalises the row. A row never loses all its mass: if every
// positive entry meets the criterion, the largest (the first of equals) is kept. Z ≤ 0 trims nothing (removing
// mass cannot raise a prior that favours high entropy). Returns how many entries were zeroed; θ is left
// bit-identical when none is. `probabilities` may be a matrix row.
//
// With `margin` > 1 an entry is trimmed only when the prior's gain exceeds the likelihood's loss that many times
// (a cautious retry when a first-order trim turned out to lower the log posterior).
// Use ω computed at this θ (the E-step's expected counts, before the M-step): ωᵢ/θᵢ is then the gradient of the
// log likelihood. At an exact stationary point of the same ω the criterion reads λ > 0 for every entry alike,
// so it would trim all entries or none.
int trimWeakParameters(Eigen::Ref<Eigen::VectorXd, 0, Eigen::InnerStride<>> probabilities,
                       const Eigen::Ref<const Eigen::VectorXd>& counts, double priorWeight, double margin = 1.0);

}  // namespace th::hmm
