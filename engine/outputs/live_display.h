// What every live path does to a frame before it is seen or sent, so that the window, `live --headless` and
// the library's stream show and send the same motion: the idle behaviour laid over it (blinks, gaze shifts,
// the head coming to rest in pauses: animation/idle_motion.h, with the settings' --no-idle, --no-blinks,
// --no-gaze and --blinks-per-minute), then the avatar frame made of it once (outputs/avatar_frame.h: what a
// character drawn here is posed with, and what the library hands on), and each frame not sent before handed to
// the outputs (VMC, OSC, VTube Studio) as that avatar frame.
//
//   th::outputs::LiveDisplay display(settings.idle, settings.live.blinks, settings.live.gaze);
//   display.setOutputs(settings.outputs.open({.faps = faps, .tokenIssued = tokenSaver}));   // output_settings.h
//   const th::outputs::AvatarFrame& shown = display.present(frame, clockSeconds);   // the window's wall clock, else
//                                                                                  // the stream's time
//
// Thread contract: one thread (the display's).
#pragma once

#include <memory>
#include <vector>

#include "animation/idle_motion.h"
#include "outputs/live_output.h"
#include "pipeline/animation_frame.h"
#include "pipeline/options.h"

namespace th::outputs {

class LiveDisplay {
 public:
  LiveDisplay(const pipeline::IdleOptions& idle, bool blinks, bool gaze);

  // The idle motion over `frame` at `clockSeconds` (a clock that goes back continues from its last value),
  // head FAPs included. If `send`, a frame whose index was not sent before (since the last newStream) goes
  // to the outputs (false: a pose held while no stream comes). Returns the avatar frame made of it (valid until
  // the next call).
  const AvatarFrame& present(pipeline::AnimationFrame& frame, double clockSeconds, bool send = true);
  void newStream() { lastSent_ = -1; }              // frame 0 again
  void setIdle(const pipeline::IdleOptions& idle);  // anew, from now
  void setSwitches(bool blinks, bool gaze) { switches_ = {.blinks = blinks, .gaze = gaze}; }

  void setOutputs(std::vector<std::unique_ptr<LiveOutput>> outputs) { outputs_ = std::move(outputs); }
  const std::vector<std::unique_ptr<LiveOutput>>& outputs() const { return outputs_; }
  std::vector<OutputStatus> statuses() const;
  void closeOutputs() { outputs_.clear(); }

  bool speaking() const { return idle_.speaking(); }
  // The FAPs a presented frame carries: the decoder's, and the idle behaviour's while it is on (in order).
  std::vector<int> fapNumbers(const std::vector<int>& decoded) const;

 private:
  bool on_;
  animation::IdleSwitches switches_;
  animation::IdleMotion idle_;
  std::vector<std::unique_ptr<LiveOutput>> outputs_;
  AvatarFrame shown_;
  int lastSent_ = -1;
  double lastClock_ = 0.0;
  double clockOffset_ = 0.0;
};

}  // namespace th::outputs
