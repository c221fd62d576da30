// The live pipeline's threads (docs/live.md, "Threads"): a source writes samples into the session's AudioRing (an
// audio callback, or a FileFeeder); a worker thread reads them, runs the FrameDecoder, and pushes timestamped
// AnimationFrames into a wait-free SPSC queue; the display (render thread, or a headless dump) takes them.
//
//   th::pipeline::LiveSession session(std::make_unique<LiveDecoder>(&head, &mouth, LiveDecoderOptions{}));
//   session.start();
//   ... the source calls session.ring().write(samples, n), then session.endOfInput() when it ends ...
//   AnimationFrame frame;
//   while (!session.done()) { while (session.nextFrame(frame)) show(frame); wait a display frame; }
//
// Nothing blocks the source: samples that do not fit in the ring are dropped and counted (overruns). When the
// display falls behind and the frame queue is full, the newest frames are dropped and counted (samples are
// never dropped for the display's sake). An exception in the worker stops it; error() rethrows it.
//
// Thread contract: one source thread (ring().write, endOfInput), one display thread (nextFrame, done); start,
// stop and the counters from the owner's thread. The decoder belongs to the worker once started.
#pragma once

#include <atomic>
#include <boost/lockfree/spsc_queue.hpp>
#include <chrono>
#include <cstdint>
#include <exception>
#include <memory>
#include <thread>
#include <vector>

#include "core/audio_ring.h"
#include "pipeline/animation_frame.h"

namespace th::pipeline {

struct LiveSessionOptions {
  std::size_t ringSamples = 4 * 16000;   // four seconds at 16 kHz
  std::size_t frameQueue = 64;           // frames waiting for the display: two seconds at 30 fps
  std::size_t readBlock = 512;           // samples the worker takes at a time (32 ms at 16 kHz)
  std::chrono::microseconds poll{2000};  // the worker's sleep when the ring is empty
  // For replaceDecoder(): the ring's sample rate and the decoder's frame rate, the speech kept to warm a new
  // decoder up, and the step its start is aligned to (a whole number of samples and of frames).
  double sampleRateHz = 16000.0;
  double framesPerSecond = 30.0;
  double historySeconds = 3.0;
  double alignSeconds = 0.1;
  std::size_t monitorSamples = 16000;  // samples kept for the display's waveform plot (lossy)
};

struct SessionCounters {
  std::uint64_t samplesIn = 0;       // written into the ring
  std::uint64_t overrunSamples = 0;  // dropped: the ring was full
  std::uint64_t framesDecoded = 0;
  std::uint64_t framesDropped = 0;  // dropped: the display's queue was full
  double decodeSeconds = 0.0;       // the worker's time in the decoder, in all
};

class LiveSession {
 public:
  explicit LiveSession(std::unique_ptr<FrameDecoder> decoder, const LiveSessionOptions& options = {});
  ~LiveSession();  // stops the worker
  LiveSession(const LiveSession&) = delete;
  LiveSession& operator=(const LiveSession&) = delete;

  AudioRing& ring() { return ring_; }
  void start();
  void endOfInput();  // the source has written its last sample
  void stop();        // ends the worker now (what is in the ring is left)
  // Hands the worker another decoder (other models or settings) without a gap: between two blocks it feeds the
  // new one the last historySeconds of speech, drops the frames already shown, and goes on with it; frame
  // indices continue. Any thread that owns the session; a decoder not yet taken is replaced.
  void replaceDecoder(std::unique_ptr<FrameDecoder> decoder);
  std::uint64_t decodersReplaced() const { return replaced_.load(std::memory_order_acquire); }
  // The samples the worker has read, for a waveform plot (display thread; what it does not take is dropped).
  std::size_t readMonitor(float* samples, std::size_t count) { return monitor_.pop(samples, count); }

  bool nextFrame(AnimationFrame& frame);  // display thread
  bool done() const;                      // the input ended, and every frame was decoded and taken
  bool workerFinished() const { return workerDone_.load(std::memory_order_acquire); }
  void rethrowError() const;  // the worker's exception, if it stopped on one
  SessionCounters counters() const;

 private:
  void run();
  void deliver(std::int64_t inputReadNs);
  void remember(std::span<const float> samples);  // into the history and the monitor
  void swapIn(std::unique_ptr<FrameDecoder> decoder);

  LiveSessionOptions options_;
  std::unique_ptr<FrameDecoder> decoder_;
  AudioRing ring_;
  boost::lockfree::spsc_queue<AnimationFrame> frames_;
  std::thread worker_;
  std::atomic<bool> inputEnded_{false};
  std::atomic<bool> stopping_{false};
  std::atomic<bool> workerDone_{false};
  std::exception_ptr error_;  // written by the worker before workerDone_ (release), read after (acquire)
  std::atomic<std::uint64_t> framesDecoded_{0};
  std::atomic<std::uint64_t> framesDropped_{0};
  std::atomic<std::int64_t> decodeNanoseconds_{0};
  std::vector<float> block_;
  // Replacing the decoder: the owner leaves it in pending_, the worker takes it.
  std::atomic<FrameDecoder*> pending_{nullptr};
  std::atomic<std::uint64_t> replaced_{0};
  std::vector<float> history_;     // the last samples read, circular by sample number
  std::uint64_t samplesRead_ = 0;  // worker's
  std::size_t alignSamples_ = 0;
  int alignFrames_ = 0;
  int frameOffset_ = 0;  // the decoder's frame 0 is the stream's frame frameOffset_
  int nextFrame_ = 0;    // the stream's next frame to deliver
  boost::lockfree::spsc_queue<float> monitor_;
};

// Feeds recorded samples (16 kHz mono) into a session from a thread of its own, in blocks, at `speed` times
// real time (0: as fast as the ring drains), then ends the session's input. At real-time pace a block is
// written when its last sample would have been heard, as a sound device delivers its periods. It never
// overruns the ring: it waits for room, as a file can. blockWrittenNs() gives when each block went in (for
// latency measurements), once finished(). Thread contract: owned by one thread; the session must outlive it.
class FileFeeder {
 public:
  // `totalSamples` > the recording's length plays it over and over until that many samples (a soak test's
  // hour from a short file, without the hour in memory); 0: once.
  // `alsoTo`: a second ring that gets every block too, without waiting (what does not fit is dropped and
  // counted there): the sound for a player.
  FileFeeder(LiveSession& session, std::vector<float> samples16k, double speed, std::size_t blockSamples = 256,
             std::size_t totalSamples = 0, AudioRing* alsoTo = nullptr);
  ~FileFeeder();  // stops and joins
  FileFeeder(const FileFeeder&) = delete;
  FileFeeder& operator=(const FileFeeder&) = delete;
  void stop();
  bool finished() const { return finished_.load(std::memory_order_acquire); }
  // Steady-clock time at which block k (samples k * blockSamples ...) was written; read after finished()
  // (kept for one pass of the recording only).
  const std::vector<std::int64_t>& blockWrittenNs() const { return blockWrittenNs_; }

 private:
  std::vector<std::int64_t> blockWrittenNs_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> finished_{false};
  std::thread thread_;
};

std::int64_t steadyNanoseconds();

}  // namespace th::pipeline
