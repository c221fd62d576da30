// `talkinghead live` with a window: the face driven by the live pipeline, drawn with OpenGL in a GLFW window,
// and a Dear ImGui panel (source, models and their settings, plots, latency, counters).
//
// Threads (DESIGN.md, "Live"): PortAudio's callback writes into the session's ring; the session's worker
// decodes; this thread (the main one: GLFW wants it) takes the frames, plays them out (pipeline/playout.h),
// renders and runs the panel. Changing a model or a decoder setting hands the worker a new decoder, warmed up
// on the last seconds of speech (LiveSession::replaceDecoder), so the face does not stop. A sound input that
// goes away is retried every two seconds, and the panel says so.
//
// Thread contract: call from the main thread.
#pragma once

#include <filesystem>
#include <string>

#include "live_settings.h"

namespace th::app {

struct LiveWindowArguments {
  std::string input;                   // a recording, played in a loop, instead of a sound input
  std::filesystem::path settingsPath;  // saved here when the window closes (empty: not saved)
  std::string screenshot;              // save the window as PNG after `frames` frames and quit
  int frames = 90;
  double duration = 0.0;               // seconds, then quit (0: until closed or Ctrl-C)
  int msaa = 0;                        // MSAA samples; 0: 4 on a GPU, none on a software renderer (llvmpipe)
  // The loop's cap where the display does not pace the swaps (no vsync: Xvfb, some drivers); 0: none, every
  // frame as soon as the last is swapped (to measure how many frames a second the machine could draw).
  double maxFps = 60.0;
};

void runLiveWindow(const LiveWindowArguments& arguments, LiveSettings settings);

}  // namespace th::app
