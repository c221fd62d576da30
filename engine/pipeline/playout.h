// The display side of the live pipeline: frames arrive at 30 per second, unevenly (the worker decodes in
// blocks, the device delivers in periods); the render thread draws at its own rate (60 Hz or whatever the
// screen does). Playout is a jitter buffer with a clock: at wall time t it shows the animation at stream time
// t - delay, interpolated between the two frames around it. The delay follows the frames' arrival: the
// latest any frame of the last few seconds arrived after its own stream time, plus one frame interval (the
// interpolation needs the next frame), plus a margin. So an instant is shown as soon as the frame after it is
// (nearly) sure to be there, and motion stays smooth at any display rate.
//
//   th::pipeline::Playout playout({});
//   while (session.nextFrame(frame)) playout.push(frame, steadyNanoseconds());
//   th::pipeline::PlayoutSample sample;
//   if (playout.sample(steadyNanoseconds(), sample)) draw(sample.frame);
//
// When the delay has to grow (frames came later than before), the clock holds still until it has; when it can
// shrink, the clock runs 5 % fast until it has, so the picture never jumps back or skips. Without
// interpolation (options.interpolate = false), the newest frame is shown as it is: lowest latency, 30 fps steps.
//
// Thread contract: one thread (the render thread).
#pragma once

#include <cstdint>
#include <deque>

#include "pipeline/animation_frame.h"

namespace th::pipeline {

struct PlayoutOptions {
  double framesPerSecond = 30.0;
  double marginMs = 4.0;       // over the latest arrival: scheduling noise of the display thread
  double windowSeconds = 3.0;  // how long a late frame keeps the delay up
  double catchUpRate = 0.05;   // how much faster than real time the clock runs while the delay shrinks
  // false: no clock and no interpolation, the newest frame is shown as soon as it is there (30 steps a second,
  // as a 30 fps video plays; the lowest latency: no interpolation frame, no jitter margin).
  bool interpolate = true;
};

struct PlayoutSample {
  AnimationFrame frame;       // FAPs, head and jaw interpolated at streamSeconds; the rest from the nearer frame
  double streamSeconds = 0;   // the instant of speech shown
  double behindNewestMs = 0;  // how far the instant shown lags the newest frame received: the buffer's delay
  bool starved = false;       // the clock ran past the newest frame, which is held
};

class Playout {
 public:
  explicit Playout(const PlayoutOptions& options = {});

  void push(const AnimationFrame& frame, std::int64_t arrivalNs);  // frames in index order
  bool sample(std::int64_t nowNs, PlayoutSample& out);             // false until the first frame
  // The animation at an instant another clock gives (the sound being heard): interpolated, or without
  // interpolation the frame nearest that instant; the newest frame if it has not come yet (counted as starved).
  // The instant never goes back. False until the first frame.
  bool sampleAt(double streamSeconds, PlayoutSample& out);
  void reset();  // a new stream (frame 0 again)

  int framesBuffered() const { return static_cast<int>(frames_.size()); }
  std::uint64_t starvedSamples() const { return starved_; }

 private:
  std::int64_t targetOffsetNs() const;
  void pick(double streamSeconds, PlayoutSample& out);  // drops frames done with; fills out

  PlayoutOptions options_;
  std::deque<AnimationFrame> frames_;
  // Arrival lateness (arrival - stream time) over the window, as a monotonic deque: front is the largest.
  struct Lateness {
    std::int64_t arrivalNs;
    std::int64_t latenessNs;
  };
  std::deque<Lateness> lateness_;
  bool started_ = false;
  std::int64_t offsetNs_ = 0;  // wall = stream + offset, as the clock runs now
  std::int64_t lastNowNs_ = 0;
  double lastStreamSeconds_ = 0.0;
  std::uint64_t starved_ = 0;
};

}  // namespace th::pipeline
