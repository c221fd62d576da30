// The mouth paper's evaluation on BEAT2 (`talkinghead eval mouth --beat2`, `train mouth --beat2`): the audio →
// mouth AV-HMM trained on the first part of the take and measured by the paper's ε and ρ on both parts, per
// synthesis method, beside baselines; its stage 2 (the audio side re-trained on speech alone); and its sweep
// (Fig. 3, mouth_sweep.h) drawn as the paper draws it.
//
//   th::eval::reportBeat2Mouth({.trainingFraction = 0.75}, std::cout);         // the two configurations
//   th::eval::reportBeat2Mouth({.model = "models/mouth.json"}, std::cout);    // a model file instead
//   th::eval::sweepBeat2Mouth({.grid = grid, .output = "docs/mouth_sweep"}, std::cout);
//
// The reports are the text the command prints, written to `out`. Thread contract: one call at a time per stream.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <ostream>

#include "animation/mouth_model.h"
#include "eval/mouth_sweep.h"

namespace th::eval {

struct Beat2MouthReportOptions {
  std::filesystem::path model;     // judge this model file instead of training the paper's two configurations
  double trainingFraction = 0.75;  // the first this fraction of the take trains, the rest is held out
  int windowFrames = 30;           // frames per window of the streaming inversion
};

// The method rows on the training and the held-out part; for the two configurations also stage 2 on GRID's and
// BEAT2's speech-only recordings; for a model file with a FAP map, the jaw as FAP 3. A bad model file fails
// before anything is written.
void reportBeat2Mouth(const Beat2MouthReportOptions& options, std::ostream& out);

struct Beat2MouthSweepOptions {
  MouthSweepGrid grid;
  std::filesystem::path output = "docs/mouth_sweep";  // the CSV and one PNG per covariance type
  double trainingFraction = 0.75;
};

// The grid fitted on the first 80 % of the training part, chosen on the rest, reported on the held-out part;
// writes the CSV and the plots (gnuplot, which the caller checks is installed). progress(done, total) after each
// model.
void sweepBeat2Mouth(const Beat2MouthSweepOptions& options, std::ostream& out,
                     const std::function<void(std::size_t, std::size_t)>& progress = {});

// The paper's model trained on the first `trainingFraction` of the take, with the reference face's FAP map, saved
// to `output`; one line on `log`.
void trainBeat2MouthModel(const std::filesystem::path& output, const animation::MouthModelOptions& options,
                          double trainingFraction, std::ostream& log);

}  // namespace th::eval
