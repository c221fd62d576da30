#include "pipeline/live_session.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <utility>

#include "core/error.h"

namespace th::pipeline {

std::int64_t steadyNanoseconds() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

LiveSession::LiveSession(std::unique_ptr<FrameDecoder> decoder, const LiveSessionOptions& options)
    : options_(options),
      decoder_(std::move(decoder)),
      ring_(options.ringSamples),
      frames_(options.frameQueue),
      block_(options.readBlock),
      history_(static_cast<std::size_t>(std::lround(options.historySeconds * options.sampleRateHz))),
      monitor_(std::max<std::size_t>(options.monitorSamples, 1)) {
  if (!decoder_) throw Error("live session: no decoder");
  if (options.ringSamples == 0 || options.frameQueue == 0 || options.readBlock == 0)
    throw Error("live session: the ring, the frame queue and the read block need room");
  const double alignSamples = options.alignSeconds * options.sampleRateHz;
  const double alignFrames = options.alignSeconds * options.framesPerSecond;
  if (!(alignSamples >= 1.0) || std::abs(alignSamples - std::round(alignSamples)) > 1e-6 || !(alignFrames >= 1.0) ||
      std::abs(alignFrames - std::round(alignFrames)) > 1e-6 ||
      history_.size() < static_cast<std::size_t>(2 * alignSamples))
    throw Error(
        "live session: the alignment step must be a whole number of samples and of frames, and the history "
        "at least two steps");
  alignSamples_ = static_cast<std::size_t>(std::lround(alignSamples));
  alignFrames_ = static_cast<int>(std::lround(alignFrames));
}

LiveSession::~LiveSession() {
  stop();
  delete pending_.exchange(nullptr, std::memory_order_acq_rel);
}

void LiveSession::replaceDecoder(std::unique_ptr<FrameDecoder> decoder) {
  if (!decoder) throw Error("live session: no decoder");
  delete pending_.exchange(decoder.release(), std::memory_order_acq_rel);  // one the worker had not taken
}

void LiveSession::remember(std::span<const float> samples) {
  for (const float sample : samples) history_[samplesRead_++ % history_.size()] = sample;
  monitor_.push(samples.data(), samples.size());  // what does not fit is dropped: it is only a plot
}

void LiveSession::swapIn(std::unique_ptr<FrameDecoder> decoder) {
  // Warm the new decoder up on the kept speech, from an aligned sample so that its frames fall on the stream's.
  const std::uint64_t kept = std::min<std::uint64_t>(samplesRead_, history_.size());
  const std::uint64_t start = (samplesRead_ - kept + alignSamples_ - 1) / alignSamples_ * alignSamples_;
  for (std::uint64_t at = start; at < samplesRead_;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(block_.size(), samplesRead_ - at));
    for (std::size_t i = 0; i < n; ++i) block_[i] = history_[(at + i) % history_.size()];
    decoder->acceptWaveform(std::span<const float>(block_.data(), n));
    at += n;
  }
  decoder_ = std::move(decoder);
  frameOffset_ = static_cast<int>(start / alignSamples_) * alignFrames_;
  replaced_.fetch_add(1, std::memory_order_acq_rel);
}

void LiveSession::start() {
  if (worker_.joinable()) throw Error("live session: already started");
  worker_ = std::thread([this] { run(); });
}

void LiveSession::endOfInput() {
  inputEnded_.store(true, std::memory_order_release);
}

void LiveSession::stop() {
  stopping_.store(true, std::memory_order_release);
  if (worker_.joinable()) worker_.join();
}

void LiveSession::run() {
  try {
    while (!stopping_.load(std::memory_order_acquire)) {
      if (FrameDecoder* replacement = pending_.exchange(nullptr, std::memory_order_acq_rel)) {
        swapIn(std::unique_ptr<FrameDecoder>(replacement));
        deliver(steadyNanoseconds());
      }
      // Read the end flag before draining: samples written before endOfInput() are then all in the ring.
      const bool ended = inputEnded_.load(std::memory_order_acquire);
      const std::size_t n = ring_.read(block_.data(), block_.size());
      if (n > 0) {
        const std::int64_t readNs = steadyNanoseconds();
        remember(std::span<const float>(block_.data(), n));
        decoder_->acceptWaveform(std::span<const float>(block_.data(), n));
        deliver(readNs);
        continue;
      }
      if (ended) {
        const std::int64_t readNs = steadyNanoseconds();
        decoder_->inputFinished();
        deliver(readNs);
        break;
      }
      std::this_thread::sleep_for(options_.poll);
    }
  } catch (...) {
    error_ = std::current_exception();
  }
  workerDone_.store(true, std::memory_order_release);
}

void LiveSession::deliver(std::int64_t inputReadNs) {
  AnimationFrame frame;
  while (decoder_->next(frame)) {
    // The decoder's frames on the stream's count (a replaced decoder started later); ones already shown go.
    if (frame.index + frameOffset_ < nextFrame_) continue;
    const double offsetSeconds = frameOffset_ / options_.framesPerSecond;
    frame.index += frameOffset_;
    frame.prosodyIndex += frameOffset_;
    frame.timeSeconds += offsetSeconds;
    nextFrame_ = frame.index + 1;
    const std::int64_t now = steadyNanoseconds();
    frame.inputReadNs = inputReadNs;
    frame.decodedNs = now;
    decodeNanoseconds_.fetch_add(now - inputReadNs, std::memory_order_relaxed);
    framesDecoded_.fetch_add(1, std::memory_order_relaxed);
    if (!frames_.push(frame)) framesDropped_.fetch_add(1, std::memory_order_relaxed);
  }
}

bool LiveSession::nextFrame(AnimationFrame& frame) {
  return frames_.pop(frame);
}

bool LiveSession::done() const {
  return workerDone_.load(std::memory_order_acquire) && frames_.read_available() == 0;
}

void LiveSession::rethrowError() const {
  if (workerDone_.load(std::memory_order_acquire) && error_) std::rethrow_exception(error_);
}

SessionCounters LiveSession::counters() const {
  SessionCounters c;
  c.samplesIn = ring_.samplesWritten();
  c.overrunSamples = ring_.overrunSamples();
  c.framesDecoded = framesDecoded_.load(std::memory_order_relaxed);
  c.framesDropped = framesDropped_.load(std::memory_order_relaxed);
  c.decodeSeconds = static_cast<double>(decodeNanoseconds_.load(std::memory_order_relaxed)) * 1e-9;
  return c;
}

FileFeeder::FileFeeder(LiveSession& session, std::vector<float> samples16k, double speed, std::size_t blockSamples,
                       std::size_t totalSamples, AudioRing* alsoTo) {
  if (blockSamples == 0) throw Error("file feeder: blocks of 0 samples");
  if (!(speed >= 0.0)) throw Error("file feeder: the speed must be 0 (as fast as possible) or more");
  if (samples16k.empty()) throw Error("file feeder: no samples");
  const std::size_t passLength = samples16k.size();
  const std::size_t total = std::max(totalSamples, passLength);
  blockWrittenNs_.reserve((passLength + blockSamples - 1) / blockSamples);
  thread_ = std::thread([this, &session, samples = std::move(samples16k), speed, blockSamples, total, alsoTo] {
    const auto start = std::chrono::steady_clock::now();
    std::size_t at = 0;  // samples fed, all passes
    while (at < total && !stopping_.load(std::memory_order_acquire)) {
      // A block never straddles the end of a pass.
      const std::size_t inPass = at % samples.size();
      const std::size_t n = std::min({blockSamples, samples.size() - inPass, total - at});
      if (speed > 0.0) {
        // A block is due when its last sample has been heard: (at + n) / 16000 / speed seconds after the start.
        const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(static_cast<double>(at + n) / 16000.0 / speed));
        std::this_thread::sleep_until(due);
      }
      if (alsoTo != nullptr) alsoTo->write(samples.data() + inPass, n);
      std::size_t written = 0;
      while (written < n && !stopping_.load(std::memory_order_acquire)) {
        // A file can wait for room where a microphone cannot: write what fits, then try again.
        const std::size_t take = std::min(session.ring().room(), n - written);
        if (take > 0) written += session.ring().write(samples.data() + inPass + written, take);
        if (written < n) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      if (at < samples.size()) blockWrittenNs_.push_back(steadyNanoseconds());
      at += n;
    }
    session.endOfInput();
    finished_.store(true, std::memory_order_release);
  });
}

FileFeeder::~FileFeeder() {
  stop();
}

void FileFeeder::stop() {
  stopping_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
}

}  // namespace th::pipeline
