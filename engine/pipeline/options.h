// The options people set, each declared once (core/options.h): the command line, the live window's settings
// file and panel, and the presets are made from these lists, so a name, a range or a default cannot differ
// between them.
//
//   th::pipeline::ModelOptions models;              // which models speak, and how they decode
//   th::pipeline::HeadMotionOptions head;           // how the head moves
//   th::pipeline::IdleOptions idle;                 // what the face does besides speaking
//   th::pipeline::AnimateOptions options = th::pipeline::animateOptionsOf(models, head, idle);
//
// Commands offer the groups that apply to them: animate, export and sidebyside the first three (animate also
// StreamingOptions, for --online); render IdleOptions; live all of them and LiveOptions. docs/cli.md lists them.
// Thread contract: plain values.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "animation/head_style.h"
#include "core/options.h"
#include "pipeline/live_decoder.h"
#include "pipeline/live_presets.h"
#include "pipeline/offline.h"

namespace th::pipeline {

inline constexpr std::array<std::string_view, 4> kHeadVariantNames{"trajectory", "paper", "posterior", "none"};
inline constexpr std::array<std::string_view, 3> kMouthMethodNames{"inversion", "mmse", "none"};
inline constexpr std::array<std::string_view, 2> kCovarianceNames{"full", "diagonal"};
inline constexpr std::array<std::string_view, 2> kInversionStartNames{"conditional", "random"};

struct ModelOptions {
  std::string head = "trajectory";  // kHeadVariantNames
  std::string mouth = "inversion";  // kMouthMethodNames
  std::string headModel;            // a file; empty: the shipped one
  std::string mouthModel;           // a file; empty: the shipped one (live: the preset's)
  std::string visemeModel;          // a file; empty: the shipped one; "none": no visemes
  std::string articulationModel;    // a file; empty: the shipped one; "none": the mouth model's lips alone
  void visitOptions(OptionVisitor& v);
  // The files to load: the given ones, else the shipped ones (the mouth's: shippedMouth, in models/); empty for
  // a part switched off ("none").
  std::filesystem::path headModelPath() const;
  std::filesystem::path mouthModelPath(std::string_view shippedMouth = "mouth.json") const;
  std::filesystem::path visemeModelPath() const;  // empty for "none"
  // empty for "none"; shipped: the file in models/ (live: the preset's)
  std::filesystem::path articulationModelPath(std::string_view shipped = "articulation.json") const;
};

// The defaults are the head synthesis's (animation/head_model.h), stated there only.
struct HeadMotionOptions {
  double amplitude = animation::HeadSynthesisOptions{}.amplitude;  // times the model's rotations
  double smoothing = animation::HeadSynthesisOptions{}.smoothing;  // times the velocity and acceleration precisions
  double variation = animation::HeadSynthesisOptions{}.variation;  // times the motion the voice does not explain
  // A person's head style (animation/head_style.h): the file it comes from (a style file, a head-pose CSV with
  // its WAV, or a talking video), and the style itself once read or fitted (useHeadStyle); empty: none.
  std::string style;
  std::optional<animation::HeadStyle> fittedStyle;
  void visitOptions(OptionVisitor& v);
};

struct IdleOptions {
  bool idle = true;  // blinks, gaze shifts, the head at rest in silence
  double blinksPerMinute = animation::IdleMotionOptions{}.blinksPerMinute;
  unsigned seed = animation::HeadSynthesisOptions{}.seed;     // of the head's variation and of the idle behaviour
  Eigen::Vector3d headRestDegrees = Eigen::Vector3d::Zero();  // where the head rests: a head style's (not an option)
  void visitOptions(OptionVisitor& v);
  animation::IdleMotionOptions motionOptions() const;
};

// The style into both: the head's synthesis moves like the person (animateOptionsOf and decoderOptionsOf apply
// head.fittedStyle) and the idle head rests where theirs does.
void useHeadStyle(const animation::HeadStyle& style, HeadMotionOptions& head, IdleOptions& idle);
// Back to the model's own motion and rest.
void clearHeadStyle(HeadMotionOptions& head, IdleOptions& idle);
// (resolveHeadStyle, pipeline/head_style_source.h, reads or fits the style head.style names.)

// The streaming decoders' decisions (animate --online, live).
struct StreamingOptions {
  // The defaults are the live decoder's (pipeline/live_decoder.h), stated there only.
  int lag = LiveDecoderOptions{}.head.maxLagFrames;  // head: online Viterbi's decision lag, frames
  int window =
      LiveDecoderOptions{}.mouth.windowFrames;  // mouth: inversion window, frames (window - 1 of them look-ahead)
  void visitOptions(OptionVisitor& v);
};

// Live's own.
struct LiveOptions {
  std::string preset = "default";                             // live_presets.h
  std::string device = "default";                             // the sound input: "default" or a device number
  std::string covariance = "full";                            // the shipped mouth model's, or its diagonal twin
  int iterations = LiveDecoderOptions{}.mouth.maxIterations;  // mouth: the most EM iterations a window
  bool waitForHead =
      LiveDecoderOptions{}.waitForHead;  // frames wait for their own head (less head delay, ~300 ms more latency)
  double minF0 = LiveDecoderOptions{}.minF0Hz;  // the prosody tracker's F0 search range, Hz
  double maxF0 = LiveDecoderOptions{}.maxF0Hz;
  bool interpolate = false;  // smooth 60 Hz motion between frames (+33 ms and the jitter margin)
  bool blinks = true;        // with idle: the blinks ...
  bool gaze = true;          // ... and the gaze shifts
  void visitOptions(OptionVisitor& v);
  // The device's number, or nothing for "default"; throws th::Error for other text.
  std::optional<int> deviceIndex() const;
};

// Everything the live decoder and its display take, as `live`'s settings file holds it (one flat object, each
// option under its key; outputs/output_settings.h adds the outputs' to make the whole file).
struct LiveSettings {
  ModelOptions models;
  HeadMotionOptions head;
  IdleOptions idle;
  StreamingOptions streaming;
  LiveOptions live;
  void visitOptions(OptionVisitor& v);
  // Each option in its range, and min-f0-hz below max-f0-hz; throws th::Error naming the option.
  void check();
  // The mouth model file: the one given, else the preset's (its _diagonal twin with covariance diagonal).
  std::filesystem::path mouthModelPath() const;
  std::filesystem::path articulationModelPath() const;  // the one given, else the preset's; empty for "none"
  LiveDecoderOptions decoderOptions() const;
};

// The preset's values into `settings`, as if typed (and live.preset); throws th::Error for an unknown preset.
void applyLivePreset(LiveSettings& settings, std::string_view preset);

// The offline path's options from the groups; `online` (non-null) asks for the streaming forms.
AnimateOptions animateOptionsOf(const ModelOptions& models, const HeadMotionOptions& head, const IdleOptions& idle,
                                const StreamingOptions* online = nullptr, std::string_view start = "conditional");

// The offline path's options that decode as live's decoder does with `settings` (its preset's window and
// iterations), each frame with its own head: `animate --online --preset` and the web package's animate(), whose
// frames are those live shows of the same file when the head waits for its frame (LiveDecoderOptions::waitForHead).
AnimateOptions livePresetAnimateOptions(const LiveSettings& settings, std::string_view start = "conditional");

// The live decoder's, from the groups live offers.
LiveDecoderOptions decoderOptionsOf(const ModelOptions& models, const HeadMotionOptions& head, const IdleOptions& idle,
                                    const StreamingOptions& streaming, const LiveOptions& live);

// The models to load for these options (a part switched off is left out); throws th::Error naming a file.
AnimationModels loadModels(const ModelOptions& models, std::string_view shippedMouth = "mouth.json");
// Live's: the mouth model the settings name, or the preset's.
AnimationModels loadModels(const LiveSettings& settings);

}  // namespace th::pipeline
