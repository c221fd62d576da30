// `talkinghead live --headless`: the live pipeline (pipeline/live.h) without a window. The sound comes from a
// recording played in at real-time pace (or faster), or from a sound input (--device); a display loop takes the
// frames as the window's would. The session's counters and the decoding delay go to stdout; what the display
// received can be dumped as an animation file.
//
// A sound input that goes away is tried again every 2 s; if it has not come back after `reconnectSeconds`, the
// run ends with an error (exit status 1) and no dump. The live outputs (--vmc, --osc, --vts) get every frame the
// display takes; their counts and rates are printed at the end, and a token VTube Studio issued is kept in the
// settings file.
// Thread contract: call from the main thread.
#pragma once

#include <filesystem>
#include <string>

#include "outputs/output_settings.h"

namespace th::app {

struct HeadlessArguments {
  std::string input;                   // a recording; empty: the sound input settings.live.device
  double speed = 1.0;                  // a recording: times real time (0: as fast as the worker decodes)
  double duration = 0.0;               // seconds: of the recording (0: all), of listening (0: until Ctrl-C)
  double repeatTo = 0.0;               // a recording: played over and over to this many seconds
  std::string dump;                    // the frames received, as .csv, .json or .fap
  double reconnectSeconds = 10.0;      // a lost sound input is waited for this long
  std::filesystem::path settingsPath;  // where VTube Studio's token is kept (empty: not kept)
};

void runHeadless(const HeadlessArguments& arguments, const outputs::LiveSessionSettings& settings);

}  // namespace th::app
