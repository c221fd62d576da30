// The head-motion model's commands as reports (`talkinghead train head`, `eval head`, `eval head --style-from`,
// `train head --video`): head_protocol.h's results written as the tables the command prints.
//
//   th::eval::reportHeadLeaveOneSpeakerOut({.trainingFraction = 0.75}, std::cout);
//   th::eval::reportHeadStyles({}, std::cout);
//   th::eval::trainHeadModelOnCorpora({.output = "models/head.json"}, std::cerr);
//
// The columns (E, corr, std ratio, p95 v, pause, jump%, FD, BA, beat/s, div) are explained in the report's own
// opening lines. Thread contract: one call at a time per stream.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

#include "animation/head_model.h"
#include "tracking/video_training.h"

namespace th::eval {

struct HeadReportOptions {
  animation::HeadModelOptions model;              // the recipe each fold trains
  double trainingFraction = 0.75;                 // the first this fraction of BEAT2's take trains
  int lagFrames = animation::kLiveHeadLagFrames;  // the online variant's decoding lag
  std::filesystem::path judged;                   // also judge this model file on BEAT2's held-out part
  std::filesystem::path compare;                  // judge this model file beside the recipe
};

// Each speaker left out in turn (head_protocol.h), its rows written as soon as it is judged, then the summary
// against the targets, the idle behaviour's blinks and, if given, the judged model file. The model files are
// read first: a bad one fails before the training.
void reportHeadLeaveOneSpeakerOut(const HeadReportOptions& options, std::ostream& out);

// Each held-out speaker's head style from another clip of theirs, styled beside unstyled (evaluateHeadStyles).
void reportHeadStyles(const HeadReportOptions& options, std::ostream& out);

struct HeadTraining {
  std::filesystem::path output = "models/head.json";
  animation::HeadModelOptions model;
  double trainingFraction = 0.75;  // the first this fraction of BEAT2's take trains
  bool beat2Only = false;          // BEAT2's one speaker (the paper's setting) instead of every training speaker
  int holdOutEvery = 5;            // own clips: every N-th held out (a single clip: its last quarter)
};

// The corpora's training speakers (or BEAT2's alone) → the model file; one line on `log`.
void trainHeadModelOnCorpora(const HeadTraining& training, std::ostream& log);

// One's own clips, tracked from `folder`, as one more speaker (named after the folder) beside the corpora: every
// N-th clip held out and judged as eval head judges a speaker, beside `shipped`. Clips left out (and those
// without a head) are named on `log`.
void trainHeadModelWithOwnClips(const tracking::VideoCorpus& clips, const std::filesystem::path& folder,
                                const animation::HeadModel& shipped, const HeadTraining& training, std::ostream& out,
                                std::ostream& log);

}  // namespace th::eval
