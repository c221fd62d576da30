// The live path without a window (`talkinghead live --headless`): pipeline/live.h's LivePipeline fed from a
// recording at real-time pace (or faster) or from a sound input, and a display loop that takes the frames as the
// window's would, runs the display step (live_display.h: idle motion, the outputs) and measures the run.
//
//   auto models = std::make_shared<const th::pipeline::AnimationModels>(th::pipeline::loadModels(settings));
//   th::outputs::runHeadless({.input = "speech.wav", .speed = 8}, settings, models, {}, std::cout, std::cerr);
//
// A sound input that goes away is tried again every 2 s; if it has not come back after `reconnectSeconds`, the
// run ends with an error and no dump. The report (the session's counters, the look-ahead, the decoding delay,
// memory and each output's counts) goes to `out`, the pipeline's events to `log`.
// Thread contract: call from the main thread.
#pragma once

#include <functional>
#include <memory>
#include <ostream>
#include <string>

#include "outputs/output_settings.h"
#include "pipeline/animation_models.h"

namespace th::outputs {

struct HeadlessRun {
  std::string input;               // a recording; empty: the sound input settings.live.device
  double speed = 1.0;              // a recording: times real time (0: as fast as the worker decodes)
  double duration = 0.0;           // seconds: of the recording (0: all), of listening (0: until stopped)
  double repeatTo = 0.0;           // a recording: played over and over to this many seconds
  std::string dump;                // the frames received, as .csv, .json or .fap (checked by the caller)
  double reconnectSeconds = 10.0;  // a lost sound input is waited for this long
};

struct HeadlessHooks {
  std::function<bool()> stopRequested;                // polled by the display loop (an interrupt); ends the input
  std::function<void(const std::string&)> keepToken;  // VTube Studio's token, if it issued one, after the report
};

void runHeadless(const HeadlessRun& run, const LiveSessionSettings& settings,
                 std::shared_ptr<const pipeline::AnimationModels> models, const HeadlessHooks& hooks, std::ostream& out,
                 std::ostream& log);

}  // namespace th::outputs
