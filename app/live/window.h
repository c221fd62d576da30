// `talkinghead live` with a window: the live pipeline's frames (pipeline/live.h) played out (pipeline/playout.h)
// on the face or the user's character (render/head.h) in a GLFW window, with the Dear ImGui panel (panel.h) beside it.
//
//   th::app::runLiveWindow({.input = "speech.wav", .settingsPath = path}, settings);
//
// Threads (docs/live.md, "Threads"): PortAudio's callback writes into the session's ring; the session's worker
// decodes; this thread (the main one: GLFW wants it) takes the frames, plays them out, renders and runs the
// panel, in the Dear ImGui example's order: poll → take frames → draw the face → draw the panel → swap.
//
// Thread contract: call from the main thread.
#pragma once

#include <filesystem>
#include <string>

#include "outputs/output_settings.h"

namespace th::app {

struct LiveWindowArguments {
  std::string avatar;                  // a character (.glb, .gltf, .vrm) drawn instead of our face
  std::string input;                   // a recording, played in a loop and aloud, instead of a sound input
  std::filesystem::path settingsPath;  // saved here when the window closes (empty: not saved)
  std::string screenshot;              // save the window as PNG after `frames` frames and quit
  int frames = 90;
  double duration = 0.0;  // seconds, then quit (0: until closed or Ctrl-C)
  int msaa = 0;           // MSAA samples; 0: 4 on a GPU, none on a software renderer (llvmpipe)
  // The loop's cap where the display does not pace the swaps (no vsync: Xvfb, some drivers); 0: none, every
  // frame as soon as the last is swapped (to measure how many frames a second the machine could draw).
  double maxFps = 60.0;
};

void runLiveWindow(const LiveWindowArguments& arguments, outputs::LiveSessionSettings settings);

}  // namespace th::app
