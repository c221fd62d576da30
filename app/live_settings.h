// What `talkinghead live` is told: the command line's arguments, and the settings the window's panel edits
// (saved when the window closes, restored when it opens; the command line's options win over the saved ones).
//
//   LiveSettings settings = loadLiveSettings(path);      // defaults if there is no file yet
//   pipeline::LiveDecoderOptions options = decoderOptionsOf(settings);
//   saveLiveSettings(path, settings);
//
// Thread contract: plain values and functions; one thread.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/live_decoder.h"

namespace th::app {

struct LiveSettings {
  std::string preset = "default";          // pipeline/live_presets.h: the mouth model, window and display mode
  std::string device = "default";         // sound input: "default" or a device number
  std::string headVariant = "trajectory";  // trajectory, paper (Viterbi state means), none
  std::string mouthMethod = "inversion";   // inversion, mmse, none
  std::string covariance = "full";         // the shipped mouth model's: full, or its diagonal twin
  std::string headModel;                   // model files; empty: the shipped ones (the preset's mouth)
  std::string mouthModel;
  int lagFrames = 6;         // head: online Viterbi's decision lag
  int windowFrames = 1;      // mouth: inversion window (look-ahead)
  int iterations = 20;       // mouth: most EM iterations a window
  bool waitForHead = false;  // frames wait for their own head (smaller head delay, 300 ms more latency)
  double minF0Hz = 60.0;
  double maxF0Hz = 500.0;
  double headAmplitude = 1.0;  // display: head rotations scaled by this
  bool interpolate = false;    // display: smooth 60 Hz motion between frames (+33 ms and the jitter margin)
  bool blinks = true;          // display: idle blinks
  bool gaze = true;            // display: small gaze shifts
  bool idle = true;            // display: blinks, gaze and the head at rest in silence at all (--no-idle)
  double headSmoothing = 1.0;  // head trajectory: times its velocity and acceleration precisions
  double headVariation = 1.0;  // head: times the motion the voice does not explain
  double blinksPerMinute = 17.0;
  unsigned seed = 1;           // of the head's variation and of the idle behaviour
};

pipeline::LiveDecoderOptions decoderOptionsOf(const LiveSettings& settings);
// The preset's window and display mode into `settings` (throws th::Error for an unknown preset).
void applyPreset(LiveSettings& settings, const std::string& preset);
// The model files the settings name, or the shipped ones: models/head.json, models/<the preset's mouth> (its
// _diagonal twin with covariance "diagonal").
std::string headModelOf(const LiveSettings& settings);
std::string mouthModelOf(const LiveSettings& settings);

// $XDG_CONFIG_HOME/talkinghead/live.json, else ~/.config/talkinghead/live.json; empty if neither is known.
std::filesystem::path defaultLiveSettingsPath();
// A missing file gives the defaults; a file that is not valid JSON or has a bad value throws th::Error naming
// it. Unknown keys are ignored (a newer version's file).
LiveSettings loadLiveSettings(const std::filesystem::path& path);
void saveLiveSettings(const std::filesystem::path& path, const LiveSettings& settings);  // atomic

}  // namespace th::app
