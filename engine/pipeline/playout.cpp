#include "pipeline/playout.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace th::pipeline {

namespace {

std::int64_t streamNanoseconds(int frameIndex, double framesPerSecond) {
  return static_cast<std::int64_t>(std::llround(frameIndex * 1e9 / framesPerSecond));
}

}  // namespace

Playout::Playout(const PlayoutOptions& options) : options_(options) {
  if (!(options.framesPerSecond > 0.0) || !(options.marginMs >= 0.0) || !(options.windowSeconds > 0.0) ||
      !(options.catchUpRate > 0.0 && options.catchUpRate < 1.0))
    throw Error(
        "playout: the frame rate and window must be positive, the margin not negative, the catch-up rate in (0, 1)");
}

void Playout::reset() {
  frames_.clear();
  lateness_.clear();
  started_ = false;
  offsetNs_ = 0;
  lastNowNs_ = 0;
  lastStreamSeconds_ = 0.0;
}

void Playout::push(const AnimationFrame& frame, std::int64_t arrivalNs) {
  frames_.push_back(frame);
  const std::int64_t lateness = arrivalNs - streamNanoseconds(frame.index, options_.framesPerSecond);
  // A later frame that came later still makes the earlier ones irrelevant to the maximum.
  while (!lateness_.empty() && lateness_.back().latenessNs <= lateness) lateness_.pop_back();
  lateness_.push_back({arrivalNs, lateness});
}

std::int64_t Playout::targetOffsetNs() const {
  // Showing an instant between frames i and i+1 needs frame i+1 there: one frame interval more.
  return lateness_.front().latenessNs +
         static_cast<std::int64_t>(std::llround(options_.marginMs * 1e6 + 1e9 / options_.framesPerSecond));
}

bool Playout::sample(std::int64_t nowNs, PlayoutSample& out) {
  if (!options_.interpolate) {
    if (frames_.empty()) return false;
    while (frames_.size() > 1) frames_.pop_front();
    lateness_.clear();
    out.frame = frames_.back();
    out.streamSeconds = frames_.back().index / options_.framesPerSecond;
    out.behindNewestMs = 0.0;
    out.starved = false;
    return true;
  }
  const auto window = static_cast<std::int64_t>(std::llround(options_.windowSeconds * 1e9));
  while (lateness_.size() > 1 && lateness_.front().arrivalNs < nowNs - window) lateness_.pop_front();
  if (frames_.empty() && !started_) return false;
  if (lateness_.empty()) return false;

  const std::int64_t target = targetOffsetNs();
  const auto lastStreamNs = static_cast<std::int64_t>(std::llround(lastStreamSeconds_ * 1e9));
  if (!started_) {
    offsetNs_ = target;
    started_ = true;
  } else if (target > offsetNs_) {
    offsetNs_ = std::min(target, nowNs - lastStreamNs);  // hold the clock still rather than go back
  } else if (target < offsetNs_) {
    const double elapsed = static_cast<double>(nowNs - lastNowNs_);
    offsetNs_ = std::max(
        target, offsetNs_ - static_cast<std::int64_t>(std::llround(options_.catchUpRate * std::max(elapsed, 0.0))));
  }
  lastNowNs_ = nowNs;
  const double stream = static_cast<double>(std::max(nowNs - offsetNs_, lastStreamNs)) * 1e-9;
  lastStreamSeconds_ = stream;
  pick(stream, out);
  return true;
}

bool Playout::sampleAt(double streamSeconds, PlayoutSample& out) {
  if (frames_.empty()) return false;
  lateness_.clear();                                                  // no clock of its own meanwhile
  const double stream = std::max(streamSeconds, lastStreamSeconds_);  // never back
  lastStreamSeconds_ = stream;
  pick(stream, out);
  if (!options_.interpolate) {  // the frame nearest the instant, not a blend: 30 steps a second
    const bool next = frames_.size() > 1 && stream - frames_[0].index / options_.framesPerSecond >
                                                frames_[1].index / options_.framesPerSecond - stream;
    out.frame = frames_[next ? 1 : 0];
    out.streamSeconds = out.frame.index / options_.framesPerSecond;
  }
  return true;
}

void Playout::pick(double stream, PlayoutSample& out) {
  // Frames before the one at or just before `stream` are done with (one stays, to hold when starved).
  const auto timeOf = [this](const AnimationFrame& frame) { return frame.index / options_.framesPerSecond; };
  while (frames_.size() > 1 && timeOf(frames_[1]) <= stream) frames_.pop_front();

  out.streamSeconds = stream;
  out.behindNewestMs = (timeOf(frames_.back()) - stream) * 1000.0;
  out.starved = false;
  const AnimationFrame& before = frames_.front();
  if (frames_.size() == 1 || stream <= timeOf(before)) {
    out.starved = frames_.size() == 1 && stream > timeOf(before);
    if (out.starved) ++starved_;
    out.frame = before;
    return;
  }
  const AnimationFrame& after = frames_[1];
  const double w = std::clamp((stream - timeOf(before)) / (timeOf(after) - timeOf(before)), 0.0, 1.0);
  out.frame = w < 0.5 ? before : after;
  for (std::size_t n = 0; n < before.faps.size(); ++n)
    out.frame.faps[n] = (1.0 - w) * before.faps[n] + w * after.faps[n];
}

}  // namespace th::pipeline
