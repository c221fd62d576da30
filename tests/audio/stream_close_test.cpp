// Closing sound streams on a thread of their own (audio::closeInBackground), the gate that keeps a callback
// off a ring that is about to go (audio::CallbackGate), and the pair the playback's callback shares without a
// lock (audio::SequencedPair). Labelled `threads`: the ThreadSanitizer part of
// scripts/test.sh runs these; under ASan a callback that touched the freed buffer would be caught.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "audio/capture.h"

// LeakSanitizer: PortAudio's host APIs load plugins when PortAudio starts (ALSA's pulse and JACK modules) and
// unload them when it shuts down; what their constructors allocated is left behind, in code no longer mapped
// (the reports name no module). Allocations made while a library is being loaded (_dl_init) are never ours;
// the plugins have no frame pointers, so only the slow unwinder reaches _dl_init in their stacks.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:_dl_init\n";
}
extern "C" const char* __asan_default_options() {
  return "fast_unwind_on_malloc=0";
}
extern "C" const char* __lsan_default_options() {
  return "print_suppressions=0";
}

namespace {

using namespace std::chrono_literals;

// A stand-in for PortAudio's thread: it calls the "callback" (enter, write into the buffer, leave) until told
// to stop. Once the gate is detached the buffer is freed at once, while the thread goes on calling.
TEST(CallbackGate, NoCallbackTouchesTheBufferOnceDetachReturns) {
  th::audio::CallbackGate gate;
  auto buffer = std::make_unique<std::vector<float>>(256, 0.0f);
  std::vector<float>* shared = buffer.get();
  std::atomic<bool> stop{false};
  std::atomic<long> entered{0}, refused{0};
  std::thread callback([&] {
    while (!stop.load()) {
      if (!gate.enter()) {
        refused.fetch_add(1);
        continue;
      }
      for (float& x : *shared) x += 1.0f;
      entered.fetch_add(1);
      gate.leave();
    }
  });
  while (entered.load() < 1000) std::this_thread::yield();
  gate.detach();
  const long enteredAtDetach = entered.load();
  buffer.reset();  // the ring goes
  while (refused.load() < 1000) std::this_thread::yield();
  stop.store(true);
  callback.join();
  EXPECT_EQ(entered.load(), enteredAtDetach) << "a callback entered after detach()";
  EXPECT_FALSE(gate.enter());
}

// PortAudio started and shut down on other threads while the owner starts it again: serialised, and every
// close finishes (no device is needed to start PortAudio).
TEST(CloseInBackground, ShutsPortAudioDownOnAnotherThreadWhileTheOwnerStartsItAgain) {
  std::vector<bool> inTime;
  for (int i = 0; i < 10; ++i) {
    auto system = std::make_unique<th::audio::PortAudioSystem>();
    EXPECT_FALSE(system->devices().size() > 10000U);  // touched while others close
    inTime.push_back(th::audio::closeInBackground(std::unique_ptr<th::audio::Capture>(), std::move(system), 0ms));
  }
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (th::audio::closesUnfinished() > 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(5ms);
  EXPECT_EQ(th::audio::closesUnfinished(), 0);
  // Given time, a close that does not block says so.
  EXPECT_TRUE(th::audio::closeInBackground(std::unique_ptr<th::audio::Playback>(),
                                           std::make_unique<th::audio::PortAudioSystem>(), 10s));
}

// The playback's schedule and clock: a pair written by one thread and read by another without waiting. A read
// that succeeds never mixes two writes.
TEST(SequencedPair, AReadNeverMixesTwoWrites) {
  th::audio::SequencedPair pair;
  std::uint64_t first = 0;
  std::int64_t second = 0;
  EXPECT_FALSE(pair.read(first, second));  // nothing written yet
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (std::uint64_t i = 1; !stop.load(); ++i) pair.write(i, 2 * static_cast<std::int64_t>(i));
  });
  long reads = 0, mixed = 0;
  while (reads < 200000) {
    if (!pair.read(first, second)) continue;
    ++reads;
    if (second != 2 * static_cast<std::int64_t>(first)) ++mixed;
  }
  stop.store(true);
  writer.join();
  EXPECT_EQ(mixed, 0);
}

}  // namespace
