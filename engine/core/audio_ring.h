// Samples from an audio callback to the worker thread: a wait-free single-producer, single-consumer ring
// (boost::lockfree::spsc_queue, its storage allocated once, here). write() is what a PortAudio callback
// may call: it never allocates, locks, blocks or throws. What does not fit is dropped and counted as an
// overrun (the worker fell behind by more than the ring holds).
//
//   th::AudioRing ring(32000);                 // two seconds at 16 kHz
//   ring.write(input, frames);                           // the callback
//   std::size_t n = ring.read(buffer.data(), buffer.size());   // the worker
//
// Thread contract: one producer thread calls write(), one consumer thread calls read(); the counters may be
// read from any thread.
#pragma once

#include <atomic>
#include <boost/lockfree/spsc_queue.hpp>
#include <cstddef>
#include <cstdint>

namespace th {

class AudioRing {
 public:
  explicit AudioRing(std::size_t capacitySamples) : queue_(capacitySamples) {}
  AudioRing(const AudioRing&) = delete;
  AudioRing& operator=(const AudioRing&) = delete;

  // Producer. Returns the number written; the rest of `count` is dropped and counted.
  std::size_t write(const float* samples, std::size_t count) noexcept {
    const std::size_t written = queue_.push(samples, count);
    written_.fetch_add(written, std::memory_order_relaxed);
    if (written < count) overruns_.fetch_add(count - written, std::memory_order_relaxed);
    return written;
  }

  // Producer: how many samples write() would take now.
  std::size_t room() const noexcept { return queue_.write_available(); }

  // Consumer: how many samples read() would give now.
  std::size_t available() const noexcept { return queue_.read_available(); }
  // Consumer. Returns the number read (0 when empty).
  std::size_t read(float* out, std::size_t maxCount) noexcept { return queue_.pop(out, maxCount); }

  std::uint64_t samplesWritten() const noexcept { return written_.load(std::memory_order_relaxed); }
  std::uint64_t overrunSamples() const noexcept { return overruns_.load(std::memory_order_relaxed); }

 private:
  boost::lockfree::spsc_queue<float> queue_;
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> overruns_{0};
};

}  // namespace th
