// The live pipeline's presets: which mouth model (a file in models/), inversion window and display mode trade
// latency for accuracy. A preset is a few option values by name (pipeline/options.h), set as if typed.
// Measured by bench/latency_bench (onset → rendered mouth) and `talkinghead eval mouth --recipe-context C
// --recipe-window W --recipe-inversion` (on held-out GRID clips and speakers left out); docs/results.md lists the
// figures.
//
// Thread contract: constants.
#pragma once

#include <array>
#include <string_view>

namespace th::pipeline {

struct PresetValue {
  std::string_view option;  // an option's name (pipeline/options.h)
  std::string_view value;   // as typed on the command line
};

struct LivePreset {
  std::string_view name;
  std::string_view summary;
  std::string_view mouthModelFile;  // in models/: made by `talkinghead train mouth --context tc`
  // in models/: made by `talkinghead train articulation --future N`, its look-ahead no longer than the mouth's
  std::string_view articulationFile;
  std::array<PresetValue, 2> values;
};

inline constexpr std::array<std::string_view, 3> kLivePresetNames{"default", "low-latency", "accurate"};

inline constexpr std::array<LivePreset, 3> kLivePresets{{
    {"default",
     "MFCC context +-1 frame, window 1, newest frame shown",
     "mouth_live.json",
     "articulation_live.json",
     {{{"window-frames", "1"}, {"interpolate", "false"}}}},
    {"low-latency",
     "no MFCC context (the mouth waits only for its MFCC window)",
     "mouth_instant.json",
     "articulation_instant.json",
     {{{"window-frames", "1"}, {"interpolate", "false"}}}},
    {"accurate",
     "the offline model (context +-2), window 2, interpolated 60 Hz motion",
     "mouth.json",
     "articulation.json",
     {{{"window-frames", "2"}, {"interpolate", "true"}}}},
}};

// The preset called `name`, or nullptr.
inline const LivePreset* findLivePreset(std::string_view name) {
  for (const LivePreset& preset : kLivePresets)
    if (preset.name == name) return &preset;
  return nullptr;
}

}  // namespace th::pipeline
