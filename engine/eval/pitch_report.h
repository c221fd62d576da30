// F0 accuracy as `talkinghead eval pitch` prints it: our tracker and the Debian peers (peer_trackers.h) on the
// same files at the same hops (5 ms and the animation's 30 frames/s), scored against the references
// (pitch_corpus.h) by FFE, GPE, VDE, the voicing errors and the fine error in cents.
//
//   th::eval::reportPitchAccuracy({.subset = "held-out", .peers = false}, std::cout);
//
// Thread contract: one call at a time per stream; the peers run as other programs.
#pragma once

#include <ostream>
#include <string>

#include "features/pitch.h"

namespace th::eval {

struct PitchReportOptions {
  std::string folder;          // WAV + .f0ref pairs; empty: the shared FDA-UE
  std::string subset = "all";  // all, tuning (001-005: our defaults were tuned on them) or held-out (006-010)
  bool peers = true;           // also Praat, RAPT, SWIPE and aubio (each must be installed)
  double minF0Hz = 60.0;       // the search range of every tracker
  double maxF0Hz = 500.0;
  features::PitchOptions pitch;  // our tracker's tuning (its range is the one above)
};

void reportPitchAccuracy(const PitchReportOptions& options, std::ostream& out);

}  // namespace th::eval
