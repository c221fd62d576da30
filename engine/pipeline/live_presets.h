// The live pipeline's presets: which mouth model (a file in models/), inversion window and display mode trade
// latency for accuracy. Measured by bench/latency_bench (onset → rendered mouth) and `talkinghead eval mouth
// --recipe-context C --recipe-window W --recipe-inversion` (on held-out GRID clips and speakers left out); the
// README lists the figures.
//
// Thread contract: constants.
#pragma once

#include <array>
#include <string_view>

namespace th::pipeline {

struct LivePreset {
  std::string_view name;
  std::string_view mouthModelFile;  // in models/: made by `talkinghead train mouth --context tc`
  int windowFrames;                 // inversion window: windowFrames - 1 frames of look-ahead
  bool interpolate;                 // display: smooth 60 Hz motion (+ a frame and the jitter margin)
  std::string_view summary;
};

inline constexpr std::array<LivePreset, 3> kLivePresets{{
    {"default", "mouth_live.json", 1, false, "MFCC context +-1 frame, window 1, newest frame shown"},
    {"low-latency", "mouth_instant.json", 1, false, "no MFCC context (the mouth waits only for its MFCC window)"},
    {"accurate", "mouth.json", 2, true, "the offline model (context +-2), window 2, interpolated 60 Hz motion"},
}};

// The preset called `name`, or nullptr.
inline const LivePreset* findLivePreset(std::string_view name) {
  for (const LivePreset& preset : kLivePresets)
    if (preset.name == name) return &preset;
  return nullptr;
}

}  // namespace th::pipeline
