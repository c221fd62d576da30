// parallelFor: every index once, results in place, the first error rethrown and no new work after it. Runs
// under ThreadSanitizer (label threads).
#include "core/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace {

TEST(ParallelFor, RunsEveryIndexExactlyOnce) {
  for (unsigned threads : {0u, 1u, 2u, 4u, 16u}) {
    std::vector<int> visits(1000, 0);
    th::parallelFor(visits.size(), threads, [&](std::size_t i) { visits[i] += static_cast<int>(i) + 1; });
    for (std::size_t i = 0; i < visits.size(); ++i)
      ASSERT_EQ(visits[i], static_cast<int>(i) + 1) << "threads " << threads;
  }
}

TEST(ParallelFor, NothingToDoIsNoWork) {
  std::atomic<int> calls{0};
  th::parallelFor(0, 4, [&](std::size_t) { ++calls; });
  EXPECT_EQ(calls.load(), 0);
}

TEST(ParallelFor, OnOneThreadNothingStartsAfterTheFailingItem) {
  std::atomic<int> started{0};
  EXPECT_THROW(th::parallelFor(100, 1,
                               [&](std::size_t i) {
                                 ++started;
                                 if (i == 3) throw std::runtime_error("item 3 failed");
                               }),
               std::runtime_error);
  EXPECT_EQ(started.load(), 4);
}

TEST(ParallelFor, RethrowsTheFirstErrorAndStartsNothingAfterIt) {
  // Items take time, and more once item 3 is failing, so that running them all would take far longer than
  // unwinding one exception (slow under the sanitizers) even on a loaded machine. With trivial items the other
  // threads could finish every item before the failing one had been caught, and the test would fail for a
  // reason that is not a fault.
  constexpr int kItems = 4000;
  std::atomic<int> started{0};
  std::atomic<bool> failing{false};
  try {
    th::parallelFor(kItems, 4, [&](std::size_t i) {
      ++started;
      if (i == 3) {
        failing = true;
        throw std::runtime_error("item 3 failed");
      }
      std::this_thread::sleep_for(std::chrono::microseconds(failing ? 5000 : 250));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "item 3 failed");
  }
  // The threads stop taking items once one has failed: far fewer than all were started.
  EXPECT_LT(started.load(), kItems);
  EXPECT_GE(started.load(), 4);
}

}  // namespace
