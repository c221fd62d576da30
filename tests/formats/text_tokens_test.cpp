// Numbers as the text formats write them: the printf form (what a standard library without floating-point
// to_chars writes with, as the WebAssembly build's) gives to_chars' text, so a file reads the same from either build.
#include "formats/text_tokens.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

using th::formats::fixedNotation;
using th::formats::printfFixed;
using th::formats::printfShortest;
using th::formats::shortest;

std::vector<double> samples() {
  std::vector<double> values = {0.0,    -0.0,     1.0,    -1.0,   0.1,     1e-7,     123456.789, 0.0333333333333,
                                1e15,   1e16,     1e-300, 5e-324, 0.03125, 203.8807, -9.7871,    1.0 / 3.0,
                                2.5e-5, 1e21 / 7, 1024.0, 0.5,    100.0,   1e-5,     9.5,        -0.00005};
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-2000.0, 2000.0);
  std::uniform_int_distribution<int> exponent(-30, 15);
  for (int i = 0; i < 4000; ++i) values.push_back(uniform(random) * std::pow(10.0, exponent(random) / 3));
  for (int i = 0; i < 2000; ++i) {  // any bits below 2^53
    double value = 0.0;
    const std::uint64_t bits = random();
    std::memcpy(&value, &bits, sizeof value);
    if (std::isfinite(value) && std::abs(value) < 9007199254740992.0) values.push_back(value);
  }
  return values;
}

TEST(TextTokens, PrintfWritesWhatToCharsWrites) {
  for (const double value : samples()) {
    ASSERT_EQ(printfShortest(value), shortest(value)) << value;
    ASSERT_EQ(printfFixed(value), fixedNotation(value)) << value;
    for (const int decimals : {0, 4, 6, 7}) ASSERT_EQ(printfFixed(value, decimals), fixedNotation(value, decimals));
  }
  EXPECT_EQ(printfShortest(std::numeric_limits<double>::infinity()), shortest(std::numeric_limits<double>::infinity()));
  EXPECT_EQ(printfFixed(-std::numeric_limits<double>::infinity(), 3),
            fixedNotation(-std::numeric_limits<double>::infinity(), 3));
}

}  // namespace
