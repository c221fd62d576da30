// The live window's figures: rolling medians over the last 5 s for the panel (processing, queueing, playout,
// drawing, each stage of a frame), and over the whole run for the summary printed when the window closes (frame
// rate, CPU a frame, the sound-to-lips offset of a recording played aloud).
//
//   th::pipeline::FrameStats stats;
//   stats.frameTaken(frame, nowNs);        // each animation frame the display takes
//   stats.frameDrawn(times);               // each display frame
//   stats.printSummary(secondsOpen);
//
// Thread contract: the display thread.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "pipeline/animation_frame.h"

namespace th::pipeline {

// Milliseconds of one display frame.
struct FrameTimes {
  double faceSetupMs = 0.0;  // the face posed (deformed, normals)
  double glMs = 0.0;         // rendered and presented
  double panelMs = -1.0;     // the panel drawn (-1: not this frame)
  double swapMs = 0.0;
  double busyMs = 0.0;    // from the loop's top to the swap's return (its sleep left out)
  double periodMs = 0.0;  // swap to swap
};

class FrameStats {
 public:
  void frameTaken(const pipeline::AnimationFrame& frame, std::int64_t nowNs);
  void playoutBehind(double ms);  // the playout's delay behind the newest frame
  void frameDrawn(const FrameTimes& times);
  void soundToLips(double lateMs);  // a recording played aloud: heard instant - shown instant, at a swap

  double processingMs() const;  // read to frame out
  double queueMs() const;       // frame out to the display
  double behindMs() const;
  double displayMs() const;  // drawing and swapping
  double periodMs() const;
  double faceSetupMs() const;
  double glMs() const;
  double panelMs() const;
  double swapMs() const;
  std::uint64_t framesDrawn() const { return framesDrawn_; }

  // "display: N frames, median F frames/s ..." on stdout (nothing if too few frames were drawn).
  void printSummary(double secondsOpen, std::uint64_t panelDraws) const;
  // "sound to lips: ..." on stdout, given the playback's figures (nothing without enough frames).
  void printSoundToLips(double firstSoundSeconds, double firstDeviceDelayMs, double scheduledMs,
                        std::uint64_t underruns) const;

 private:
  std::deque<double> processingMs_, queueMs_, behindMs_, displayMs_, periodMs_;
  std::array<std::deque<double>, 4> stageMs_;  // face set-up, GL, panel, swap
  std::vector<double> allPeriodsMs_;           // after the first half second (start-up)
  std::vector<double> allBusyMs_;
  std::vector<double> lateMs_;
  double cpuAtWarm_ = 0.0;          // the process's CPU seconds when start-up ended
  double msSinceFirstFrame_ = 0.0;  // swap to swap, summed from the first frame
  bool warm_ = false;
  std::uint64_t framesDrawn_ = 0;
};

}  // namespace th::pipeline
