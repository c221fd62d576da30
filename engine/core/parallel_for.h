// Runs independent pieces of work on a few threads: work(i) for i = 0 .. count − 1, each index once, taken in
// order by whichever thread is free. For coarse items (a video clip each, a model each), not for inner loops.
//
//   std::vector<Result> results(clips.size());
//   th::parallelFor(clips.size(), 0, [&](std::size_t i) { results[i] = process(clips[i]); });
//
// threads 0: the machine's hardware concurrency; never more threads than items; 1 runs on the caller's
// thread alone. If work throws, no new item is started, the threads finish the items they hold, and the first
// exception is rethrown on the calling thread. `work` must be safe to call from several threads at once on
// different indices (each writes only its own results).
// Thread contract: call from any thread; work runs on the caller's thread and on threads of its own.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace th {

inline void parallelFor(std::size_t count, unsigned threads, const std::function<void(std::size_t)>& work) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  const auto workers = static_cast<unsigned>(std::min<std::size_t>(threads, count));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex errorMutex;
  std::exception_ptr firstError;
  const auto run = [&] {
    while (!failed.load(std::memory_order_acquire)) {
      const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= count) return;
      try {
        work(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(errorMutex);
        if (!firstError) firstError = std::current_exception();
        failed.store(true, std::memory_order_release);
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < workers; ++t) pool.emplace_back(run);
  run();  // the caller is the first worker
  for (std::thread& thread : pool) thread.join();
  if (firstError) std::rethrow_exception(firstError);
}

}  // namespace th
