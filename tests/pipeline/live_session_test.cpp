// LiveSession's threads with a stand-in decoder (so that the ThreadSanitizer part of scripts/test.sh builds
// only the session, not the engine): every sample arrives once and in order, frames come out in order,
// overruns and dropped frames are counted, a worker's error reaches the owner.
#include "pipeline/live_session.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/error.h"

namespace th::pipeline {
namespace {

// One frame per `kHop` samples: its index and the sum of its samples, so that order and completeness show.
class SummingDecoder : public FrameDecoder {
 public:
  static constexpr std::size_t kHop = 160;
  explicit SummingDecoder(int throwAtFrame = -1, double scale = 1.0) : throwAtFrame_(throwAtFrame), scale_(scale) {}
  void acceptWaveform(std::span<const float> samples) override {
    for (const float s : samples) {
      sum_ += s;
      if (++inFrame_ == kHop) emit();
    }
  }
  void inputFinished() override {
    if (inFrame_ > 0) emit();
  }
  bool next(AnimationFrame& frame) override {
    if (ready_.empty()) return false;
    frame = ready_.front();
    ready_.erase(ready_.begin());
    return true;
  }

 private:
  void emit() {
    if (count_ == throwAtFrame_) throw std::runtime_error("decoder failed");
    AnimationFrame frame;
    frame.index = count_++;
    frame.energy = scale_ * sum_;
    ready_.push_back(frame);
    sum_ = 0.0;
    inFrame_ = 0;
  }
  int throwAtFrame_;
  double scale_;
  int count_ = 0;
  std::size_t inFrame_ = 0;
  double sum_ = 0.0;
  std::vector<AnimationFrame> ready_;
};

// Sample n is n: each frame's sum is known.
std::vector<float> ramp(std::size_t n) {
  std::vector<float> samples(n);
  std::iota(samples.begin(), samples.end(), 0.0f);
  return samples;
}

double expectedSum(int frame, std::size_t total) {
  const std::size_t begin = static_cast<std::size_t>(frame) * SummingDecoder::kHop;
  const std::size_t end = std::min(total, begin + SummingDecoder::kHop);
  double sum = 0.0;
  for (std::size_t n = begin; n < end; ++n) sum += static_cast<double>(n);
  return sum;
}

// Takes frames until the session is done; `pause` slows the display down.
std::vector<AnimationFrame> drain(LiveSession& session, std::chrono::microseconds pause = {}) {
  std::vector<AnimationFrame> frames;
  AnimationFrame frame;
  while (!session.done()) {
    while (session.nextFrame(frame)) frames.push_back(frame);
    std::this_thread::sleep_for(pause.count() > 0 ? pause : std::chrono::microseconds(200));
  }
  while (session.nextFrame(frame)) frames.push_back(frame);
  return frames;
}

TEST(LiveSession, EverySampleOnceAndInOrderThroughTheThreads) {
  const std::size_t total = 16000 * 3 + 77;  // a partial last frame
  LiveSession session(std::make_unique<SummingDecoder>(), {.ringSamples = 4096, .frameQueue = 1024, .readBlock = 300});
  session.start();
  FileFeeder feeder(session, ramp(total), 0.0, 97);  // as fast as the ring drains: the ring fills up often
  const std::vector<AnimationFrame> frames = drain(session);
  session.rethrowError();
  const std::size_t expected = (total + SummingDecoder::kHop - 1) / SummingDecoder::kHop;
  ASSERT_EQ(frames.size(), expected);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(frames[f].index, static_cast<int>(f));
    EXPECT_DOUBLE_EQ(frames[f].energy, expectedSum(static_cast<int>(f), total)) << "frame " << f;
    EXPECT_GE(frames[f].decodedNs, frames[f].inputReadNs);
  }
  const SessionCounters counters = session.counters();
  EXPECT_EQ(counters.samplesIn, total);
  EXPECT_EQ(counters.overrunSamples, 0U);  // a file waits for room
  EXPECT_EQ(counters.framesDecoded, expected);
  EXPECT_EQ(counters.framesDropped, 0U);
  // The feeder marks itself finished just after it ends the input, so the worker may be done first: join it.
  feeder.stop();
  EXPECT_TRUE(feeder.finished());
}

TEST(LiveSession, AFullRingDropsSamplesAndASlowDisplayDropsFramesBothCounted) {
  // A "callback" that writes without waiting into a small ring while the worker is not yet running: the ring
  // keeps what fits and counts the rest.
  LiveSession session(std::make_unique<SummingDecoder>(), {.ringSamples = 1000, .frameQueue = 4, .readBlock = 64});
  const std::vector<float> burst = ramp(1500);
  EXPECT_EQ(session.ring().write(burst.data(), burst.size()), 1000U);
  EXPECT_EQ(session.counters().overrunSamples, 500U);
  session.start();
  // Then steady input with a display that takes nothing until the end: the frame queue (4) overflows.
  std::thread callback([&] {
    const std::vector<float> block(160, 1.0f);
    for (int i = 0; i < 50; ++i) {
      // Waits for room (as a file does), so that on a loaded machine, where the worker may be late by more
      // than the small ring holds, this part drops no samples: its point is the frames.
      while (session.ring().room() < block.size()) std::this_thread::sleep_for(std::chrono::microseconds(100));
      session.ring().write(block.data(), block.size());
      std::this_thread::sleep_for(std::chrono::microseconds(300));
    }
    session.endOfInput();
  });
  callback.join();
  while (!session.workerFinished()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const std::vector<AnimationFrame> frames = drain(session);
  const SessionCounters counters = session.counters();
  EXPECT_EQ(counters.samplesIn, 1000U + 50U * 160U);
  EXPECT_EQ(counters.framesDecoded, (1000U + 50U * 160U + SummingDecoder::kHop - 1) / SummingDecoder::kHop);
  EXPECT_EQ(frames.size(), 4U);
  EXPECT_EQ(counters.framesDropped, counters.framesDecoded - 4U);
  // What reached the display is the first frames, in order.
  for (std::size_t f = 0; f < frames.size(); ++f) EXPECT_EQ(frames[f].index, static_cast<int>(f));
}

TEST(LiveSession, AWorkersErrorStopsItAndReachesTheOwner) {
  LiveSession session(std::make_unique<SummingDecoder>(5), {});
  session.start();
  FileFeeder feeder(session, ramp(16000), 0.0);
  const std::vector<AnimationFrame> frames = drain(session);
  // The frames of the blocks decoded before the failing one arrive (how many depends on how the worker's reads
  // fell), in order; none after it.
  EXPECT_LT(frames.size(), 5U);
  for (std::size_t f = 0; f < frames.size(); ++f) EXPECT_EQ(frames[f].index, static_cast<int>(f));
  EXPECT_THROW(session.rethrowError(), std::runtime_error);
  feeder.stop();
}

TEST(LiveSession, StopsWhileTheSourceIsStillWriting) {
  LiveSession session(std::make_unique<SummingDecoder>(), {});
  session.start();
  FileFeeder feeder(session, ramp(16000 * 60), 1.0);  // a minute at real time: stopped long before
  // Stopped once it has written something (a thread may start late on a loaded machine), well before a second.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (session.counters().samplesIn == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  feeder.stop();
  session.stop();
  EXPECT_TRUE(session.workerFinished());
  EXPECT_LT(session.counters().samplesIn, 16000U);
  EXPECT_GT(session.counters().samplesIn, 0U);
}

TEST(LiveSession, FileFeederKeepsTheRealTimePace) {
  LiveSession session(std::make_unique<SummingDecoder>(), {});
  session.start();
  const auto start = std::chrono::steady_clock::now();
  FileFeeder feeder(session, ramp(16000 / 5), 1.0);  // 0.2 s of sound
  const std::vector<AnimationFrame> frames = drain(session);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(frames.size(), 20U);
  EXPECT_GE(seconds, 0.18);  // not faster than the sound (one block of slack)
  EXPECT_THROW(FileFeeder(session, {}, -1.0), th::Error);
}

// A recording played over and over (a soak test's long stream from a short file): every pass in order.
TEST(LiveSession, FileFeederRepeatsTheRecordingToTheLengthAsked) {
  const std::size_t length = 16 * SummingDecoder::kHop;
  LiveSession session(std::make_unique<SummingDecoder>(), {.frameQueue = 1024});
  session.start();
  FileFeeder feeder(session, ramp(length), 0.0, 100, length * 5 / 2);
  const std::vector<AnimationFrame> frames = drain(session);
  ASSERT_EQ(frames.size(), 40U);
  for (std::size_t f = 0; f < frames.size(); ++f)
    EXPECT_DOUBLE_EQ(frames[f].energy, expectedSum(static_cast<int>(f % 16), length)) << "frame " << f;
  EXPECT_EQ(session.counters().samplesIn, length * 5 / 2);
}

// Decoders replaced twice while the sound plays: the frames go on without a gap or a repeat, each the sum of
// its own samples (the new decoder was warmed up on an aligned stretch of the kept speech), by the decoder of
// the moment (its scale says which). The monitor gives the samples in order. The replacements are made when the
// display has had 40 and 120 of the 300 frames (not at set times, which a stalled thread would overrun), and
// the frame queue holds all of them, so a late display drops none.
TEST(LiveSession, ReplacingTheDecoderKeepsTheFramesGoing) {
  const std::size_t total = 16000 * 3;
  LiveSession session(
      std::make_unique<SummingDecoder>(),
      {.frameQueue = 1024, .readBlock = 256, .framesPerSecond = 16000.0 / SummingDecoder::kHop, .historySeconds = 0.5});
  session.start();
  FileFeeder feeder(session, ramp(total), 2.0);
  std::vector<AnimationFrame> frames;
  std::vector<float> monitored(4096);
  float lastMonitored = -1.0f;
  bool monitorInOrder = true;
  std::size_t monitoredCount = 0;
  AnimationFrame frame;
  int replaced = 0;
  while (!session.done()) {
    if ((replaced == 0 && frames.size() >= 40) || (replaced == 1 && frames.size() >= 120)) {
      ++replaced;
      session.replaceDecoder(std::make_unique<SummingDecoder>(-1, 1.0 + replaced));
    }
    while (session.nextFrame(frame)) frames.push_back(frame);
    for (std::size_t n = session.readMonitor(monitored.data(), monitored.size()); n > 0;
         n = session.readMonitor(monitored.data(), monitored.size())) {
      for (std::size_t i = 0; i < n; ++i) {
        monitorInOrder = monitorInOrder && monitored[i] > lastMonitored;
        lastMonitored = monitored[i];
      }
      monitoredCount += n;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  while (session.nextFrame(frame)) frames.push_back(frame);
  session.rethrowError();
  EXPECT_EQ(session.decodersReplaced(), 2U);
  ASSERT_EQ(frames.size(), total / SummingDecoder::kHop);
  double lastScale = 1.0;
  int byLast = 0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    ASSERT_EQ(frames[f].index, static_cast<int>(f));
    const double scale = frames[f].energy / expectedSum(static_cast<int>(f), total);
    EXPECT_TRUE(scale == 1.0 || scale == 2.0 || scale == 3.0) << "frame " << f << ": " << scale;
    EXPECT_GE(scale, lastScale) << "frame " << f;
    lastScale = scale;
    byLast += scale == 3.0 ? 1 : 0;
  }
  EXPECT_GT(byLast, 50);
  EXPECT_TRUE(monitorInOrder);
  EXPECT_GT(monitoredCount, total / 2);
  EXPECT_THROW(session.replaceDecoder(nullptr), th::Error);
}

}  // namespace
}  // namespace th::pipeline
