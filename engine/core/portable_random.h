// Random draws that are the same in every build. GCC's standard library (the native build) and LLVM's (the
// WebAssembly build) draw std::uniform_real_distribution, normal_distribution and gamma_distribution by
// different algorithms, so one seed gave other blinks, gaze and head motion in a browser. These draw by the
// algorithms GCC's library uses — 53 bits from two 32-bit words, Marsaglia's polar method, Marsaglia and
// Tsang's gamma (ACM TOMS 26(3), 2000) — so the native outputs are what they were, draw for draw.
//
//   std::mt19937 random(seed);
//   th::NormalDraws normal;
//   double x = normal(random);                       // N(0, 1)
//   double wait = th::gammaDraw(random, 3.0, 1.0);   // shape 3, scale 1
//
// Thread contract: as the engine they draw from; a NormalDraws keeps its second value for the next call.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace th {

// Uniform in [0, 1): the first word the low 32 bits, the second the high ones.
inline double canonicalDraw(std::mt19937& random) {
  constexpr double kWord = 4294967296.0;  // 2^32
  double sum = static_cast<double>(random());
  sum += static_cast<double>(random()) * kWord;
  const double draw = sum / (kWord * kWord);
  return draw >= 1.0 ? std::nextafter(1.0, 0.0) : draw;
}

// Uniform in [low, high).
inline double uniformDraw(std::mt19937& random, double low, double high) {
  return canonicalDraw(random) * (high - low) + low;
}

// Normal draws by the polar method, two at a time: the second is kept for the next call.
class NormalDraws {
 public:
  explicit NormalDraws(double mean = 0.0, double deviation = 1.0) : mean_(mean), deviation_(deviation) {}
  double operator()(std::mt19937& random) {
    double draw = 0.0;
    if (saved_) {
      saved_ = false;
      draw = next_;
    } else {
      double x = 0.0, y = 0.0, r2 = 0.0;
      do {
        x = 2.0 * canonicalDraw(random) - 1.0;
        y = 2.0 * canonicalDraw(random) - 1.0;
        r2 = x * x + y * y;
      } while (r2 > 1.0 || r2 == 0.0);
      const double scale = std::sqrt(-2 * std::log(r2) / r2);
      next_ = x * scale;
      saved_ = true;
      draw = y * scale;
    }
    return draw * deviation_ + mean_;
  }

 private:
  double mean_, deviation_;
  double next_ = 0.0;
  bool saved_ = false;
};

// Gamma(shape, scale) by Marsaglia and Tsang's squeeze; a shape under 1 from shape + 1 and a uniform's power.
inline double gammaDraw(std::mt19937& random, double shape, double scale) {
  const double boosted = shape < 1.0 ? shape + 1.0 : shape;
  const double d = boosted - 1.0 / 3.0;
  const double c = 1.0 / std::sqrt(9.0 * d);
  NormalDraws normal;
  double u = 0.0, v = 0.0, n = 0.0;
  do {
    do {
      n = normal(random);
      v = 1.0 + c * n;
    } while (v <= 0.0);
    v = v * v * v;
    u = canonicalDraw(random);
  } while (u > 1.0 - 0.0331 * n * n * n * n && std::log(u) > 0.5 * n * n + d * (1.0 - v + std::log(v)));
  if (shape == boosted) return d * v * scale;
  do u = canonicalDraw(random);
  while (u == 0.0);
  return std::pow(u, 1.0 / shape) * d * v * scale;
}

}  // namespace th
