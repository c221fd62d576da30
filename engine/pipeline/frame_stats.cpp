#include "pipeline/frame_stats.h"

#include <algorithm>
#include <cstdio>

#include "core/cpu_time.h"
#include "core/statistics.h"

namespace th::pipeline {
namespace {

constexpr std::size_t kStatFrames = 150;  // the rolling figures are medians over the last 5 s
constexpr double kStartUpMs = 500.0;
// Fewest frames whose sound-to-lips offsets are summed up: a third of a second at 30 frames/s, and a loaded
// machine's slow display still gives them in a few seconds.
constexpr std::size_t kFewestSoundToLipsFrames = 10;

void recordStat(std::deque<double>& values, double value) {
  values.push_back(value);
  while (values.size() > kStatFrames) values.pop_front();
}

double rollingMedian(const std::deque<double>& values) {
  return quantile(std::vector<double>(values.begin(), values.end()), 0.5);
}

}  // namespace

void FrameStats::frameTaken(const pipeline::AnimationFrame& frame, std::int64_t nowNs) {
  recordStat(processingMs_, static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
  recordStat(queueMs_, static_cast<double>(nowNs - frame.decodedNs) * 1e-6);
}

void FrameStats::playoutBehind(double ms) {
  recordStat(behindMs_, ms);
}

void FrameStats::frameDrawn(const FrameTimes& times) {
  ++framesDrawn_;
  recordStat(displayMs_, times.faceSetupMs + times.glMs + std::max(times.panelMs, 0.0) + times.swapMs);
  recordStat(stageMs_[0], times.faceSetupMs);
  recordStat(stageMs_[1], times.glMs);
  if (times.panelMs >= 0.0) recordStat(stageMs_[2], times.panelMs);  // on the frames that draw it
  recordStat(stageMs_[3], times.swapMs);
  recordStat(periodMs_, times.periodMs);
  // Start-up (the first half second: shaders compiled, buffers filled) is left out of the summary. Counted in
  // time, not frames: a loaded machine draws few frames in it, and its run should still be summed up.
  if (framesDrawn_ > 1) msSinceFirstFrame_ += times.periodMs;
  if (warm_) {
    allPeriodsMs_.push_back(times.periodMs);
    allBusyMs_.push_back(times.busyMs);
  } else if (msSinceFirstFrame_ >= kStartUpMs) {
    warm_ = true;
    cpuAtWarm_ = processCpuSeconds();
  }
}

void FrameStats::soundToLips(double lateMs) {
  if (lateMs_.size() < 100000) lateMs_.push_back(lateMs);
}

double FrameStats::processingMs() const {
  return rollingMedian(processingMs_);
}
double FrameStats::queueMs() const {
  return rollingMedian(queueMs_);
}
double FrameStats::behindMs() const {
  return rollingMedian(behindMs_);
}
double FrameStats::displayMs() const {
  return rollingMedian(displayMs_);
}
double FrameStats::periodMs() const {
  return rollingMedian(periodMs_);
}
double FrameStats::faceSetupMs() const {
  return rollingMedian(stageMs_[0]);
}
double FrameStats::glMs() const {
  return rollingMedian(stageMs_[1]);
}
double FrameStats::panelMs() const {
  return rollingMedian(stageMs_[2]);
}
double FrameStats::swapMs() const {
  return rollingMedian(stageMs_[3]);
}

void FrameStats::printSummary(double secondsOpen, std::uint64_t panelDraws) const {
  if (allPeriodsMs_.empty()) return;
  std::vector<double> periods = allPeriodsMs_;
  std::sort(periods.begin(), periods.end());
  const double medianPeriod = periods[periods.size() / 2];
  const double slow = periods[periods.size() * 95 / 100];
  // The frame's own work, from the loop's top (events, frames taken) to the swap's return (the loop's cap and
  // its sleep left out): how much of the cap's period is spare.
  std::vector<double> busy = allBusyMs_;
  std::sort(busy.begin(), busy.end());
  // The process's CPU time, llvmpipe's rasterising threads and the decoders included: less at the mercy of what
  // else the machine runs than the frame rate (two cores give 33.3 ms a frame at 60 frames/s).
  const double cpuMs = (processCpuSeconds() - cpuAtWarm_) * 1000.0 / static_cast<double>(periods.size());
  std::printf(
      "display: %zu frames, median %.1f frames/s (95th percentile frame %.1f ms), CPU %.1f ms a frame (all "
      "threads), busy %.1f ms a frame (95th percentile %.1f), the panel drawn %.1f times a second; per frame "
      "(median ms of the last 5 s): face %.1f, GL %.1f, panel %.1f (the frames that draw it), swap %.1f\n",
      periods.size(), 1000.0 / medianPeriod, slow, cpuMs, busy[busy.size() / 2], busy[busy.size() * 95 / 100],
      static_cast<double>(panelDraws) / secondsOpen, faceSetupMs(), glMs(), panelMs(), swapMs());
}

void FrameStats::printSoundToLips(double firstSoundSeconds, double firstDeviceDelayMs, double scheduledMs,
                                  std::uint64_t underruns) const {
  if (lateMs_.size() < kFewestSoundToLipsFrames) return;
  std::vector<double> late = lateMs_;
  std::sort(late.begin(), late.end());
  const auto at = [&](double q) { return late[static_cast<std::size_t>(q * static_cast<double>(late.size() - 1))]; };
  std::printf(
      "sound to lips: the face shows each instant %+.1f ms after it is heard (median of %zu frames; 10-90 %%: "
      "%+.1f to %+.1f ms); the recording's start heard at %.6f s on the steady clock, by the device's reported "
      "delay of %.1f ms; the sound scheduled %.1f ms after the input; %llu underruns\n",
      at(0.5), late.size(), at(0.1), at(0.9), firstSoundSeconds, firstDeviceDelayMs, scheduledMs,
      static_cast<unsigned long long>(underruns));
}

}  // namespace th::pipeline
