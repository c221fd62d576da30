// The portable random draws (engine/core/portable_random.h): from the same seed, the same numbers as the
// native build's standard library (GCC's) draws, so the native outputs did not change when the engine moved
// to them; and numbers that no library's algorithm decides, so the WebAssembly build draws them too.
#include "core/portable_random.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

#if defined(__GLIBCXX__)
TEST(PortableRandom, DrawsWhatGccsStandardLibraryDraws) {
  std::mt19937 ours(7), theirs(7);
  th::NormalDraws normal(0.5, 2.0);
  std::normal_distribution<double> stdNormal(0.5, 2.0);
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(th::uniformDraw(ours, -3.0, 5.0), std::uniform_real_distribution<double>(-3.0, 5.0)(theirs)) << i;
    ASSERT_EQ(normal(ours), stdNormal(theirs)) << i;
    for (const double shape : {0.5, 3.0}) {
      std::gamma_distribution<double> stdGamma(shape, 1.7);  // a new one each time, as the idle motion draws
      ASSERT_EQ(th::gammaDraw(ours, shape, 1.7), stdGamma(theirs)) << i << ", shape " << shape;
    }
  }
}
#endif

TEST(PortableRandom, TheDrawsHaveTheirDistributionsMoments) {
  std::mt19937 random(11);
  th::NormalDraws normal;
  constexpr int kDraws = 200000;
  double uniformSum = 0.0, normalSum = 0.0, normalSquares = 0.0, gammaSum = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double u = th::uniformDraw(random, 2.0, 4.0);
    ASSERT_GE(u, 2.0);
    ASSERT_LT(u, 4.0);
    uniformSum += u;
    const double x = normal(random);
    normalSum += x;
    normalSquares += x * x;
    gammaSum += th::gammaDraw(random, 3.0, 0.5);
  }
  EXPECT_NEAR(uniformSum / kDraws, 3.0, 0.01);
  EXPECT_NEAR(normalSum / kDraws, 0.0, 0.01);
  EXPECT_NEAR(normalSquares / kDraws, 1.0, 0.01);
  EXPECT_NEAR(gammaSum / kDraws, 1.5, 0.01);  // shape x scale
}

}  // namespace
