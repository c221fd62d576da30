// A person's head style, from a clip of them talking: how far their head spreads on each axis, how fast it
// moves, where it rests, how much it moves in pauses against speech and how often one movement follows another;
// and the head model's synthesis set to move like that.
//
//   th::animation::HeadRecording clip = ...;   // the person's head pose and the prosody of their speech
//   th::animation::HeadStyle style = th::animation::fitHeadStyle(model, clip);
//   th::animation::saveHeadStyle("scott.head-style.json", style);
//   th::animation::HeadSynthesisOptions synthesis;
//   th::animation::applyHeadStyle(style, synthesis);   // then synthesiseHead(model, prosody, voiced, synthesis)
//
// The voice does not tell a lively speaker from a still one (docs/head.md), so the model alone moves every head
// as much as people do on average. The fit plays the model on the clip's own speech and sets, on a small grid,
// the synthesis's smoothing and residual variation so that its speed and beats a second match the person's
// (each at the per-axis gain that makes its spread the person's), then the residual's gain in pauses so that
// its pause/speech speed ratio does too. Each candidate is the mean over a few seeds of the residual motion; one
// whose motion steps further in a frame than the person ever does in the clip (a jump, to a viewer) is ruled out.
// The rest pose is the clip's mean pose: the synthesis adds it, and the idle behaviour eases the head to it.
// Thread contract: pure functions (save and load read and write the file).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "animation/head_data.h"
#include "animation/head_model.h"

namespace th::animation {

// What a clip of head motion shows, about its own mean pose.
struct HeadStyleMeasures {
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();  // per-axis standard deviation, degrees
  double speedP95 = 0.0;                             // deg/s
  double speedP99 = 0.0;          // deg/s: the styled head steps no faster (0 in a style saved without it: no limit)
  double pauseSpeechRatio = 0.0;  // mean speed in pauses over speech; 0 when the clip has too few pauses
  bool pauses = false;            // at least minPauseSeconds of pauses, so pauseSpeechRatio means something
  double beatsPerSecond = 0.0;    // motion beats (head_measures.h)
  double seconds = 0.0;
};

struct HeadStyle {
  std::string source;                                  // the clip it was fitted to
  Eigen::Vector3d restPose = Eigen::Vector3d::Zero();  // the clip's mean pose, degrees
  HeadStyleMeasures person;                            // the clip's
  // The synthesis that moves like the person (HeadSynthesisOptions' fields of the same names).
  Eigen::Vector3d axisGain = Eigen::Vector3d::Ones();
  double smoothing = 1.0;
  double variation = 1.0;
  double pauseVariation = HeadSynthesisOptions{}.pauseVariation;
  HeadStyleMeasures fitted;  // the styled model's on the clip's own speech: how close the fit came
};

struct HeadStyleFitOptions {
  double minSeconds = 10.0;      // a shorter clip is refused
  double minPauseSeconds = 1.0;  // fewer seconds of pauses: the pause gain keeps its default
  double minVoicedShare = 0.2;   // a clip with less voiced speech is refused (the model follows the voice)
  unsigned seeds = 3;            // of the residual motion, per candidate
};

// The measures of 3 x T rotations (degrees) over the level of their speech (T, dB), at fps frames a second.
HeadStyleMeasures measureHeadStyle(const Eigen::MatrixXd& rotations, const Eigen::RowVectorXd& levelDb, double fps,
                                   double minPauseSeconds = HeadStyleFitOptions{}.minPauseSeconds);

// Fits the style of `clip` (its rotations, prosody, voicing and level) to `model`. Throws th::Error, naming the
// clip, when it is too short, has too little voiced speech or no head motion.
HeadStyle fitHeadStyle(const HeadModel& model, const HeadRecording& clip, const HeadStyleFitOptions& options = {});

// Sets the synthesis's per-axis gain, pause gain and rest pose to the style's, and multiplies its smoothing and
// variation by the style's (the options' own, 1 by default, are a user's adjustments on top of the person's, as
// the amplitude, left as it is, is an overall scale).
// (Inline: the web build, which neither fits nor reads styles, applies them too.)
inline void applyHeadStyle(const HeadStyle& style, HeadSynthesisOptions& options) {
  options.axisGain = style.axisGain;
  options.smoothing *= style.smoothing;
  options.variation *= style.variation;
  options.pauseVariation = style.pauseVariation;
  options.restPose = style.restPose;
  options.maxStepDegrees = style.person.speedP99 / kHeadFramesPerSecond;
}

// A small JSON file ("format": "talkinghead-head-style"). Errors name the file.
void saveHeadStyle(const std::filesystem::path& path, const HeadStyle& style);
HeadStyle loadHeadStyle(const std::filesystem::path& path);
// Whether the file is a head-style file (a JSON object whose format says so), without throwing.
bool isHeadStyleFile(const std::filesystem::path& path);

// The style a file gives: a style file as saved; else a head-pose CSV (readHeadRecording's, head_data.h) with the
// recording of the same take beside it (NAME.wav, as `talkinghead track` writes them), fitted to `model`. A
// video is tracked first, which this library does not do: the app's --head-style does. Errors are one line
// naming the file.
HeadStyle headStyleFromFile(const HeadModel& model, const std::filesystem::path& file,
                            const HeadStyleFitOptions& options = {});

}  // namespace th::animation
