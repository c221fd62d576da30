// The mouth network (animation/mouth_network.h) that the default mouth's visemes and closures come from
// (animation/articulation.h), trained on every shared corpus with a truth for it (`talkinghead train
// articulation`): GRID s1's training clips, StyleTalk and the Arabic news anchors (tracked lips, phones), BEAT2's
// phone-aligned takes, and folders of synthesised or aligned speech if given, with the face's inner-lip opening
// gradient for the closures. How well it does on speakers it never heard: tools/diagnostics/
// mouth_network_experiment and docs/mouth.md.
//
//   th::eval::trainArticulation({.output = "models/articulation.json"}, std::cout, std::cerr);
//
// Thread contract: one call at a time (the tracking runs on threads of its own).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "animation/mouth_network.h"

namespace th::eval {

struct ArticulationTraining {
  // Paths as the command line gives them (strings, so that --help shows the default unquoted).
  std::string output = "models/articulation.json";
  std::string tracks;                // the clips' tracks; empty: defaultMouthTrackFolder() (mouth_corpus_report.h)
  std::string festival;              // tools/festival_speech.py's folder; empty: none
  std::vector<std::string> aligned;  // tools/align_phones.py's folders of read speech (speechocean762's speakers)
  std::string gridPhones;            // tools/align_phones.py --grid's folder: GRID's phones where the sound puts them
  int futureSubframes = animation::MouthNetworkOptions{}.futureSubframes;
  int epochs = 20;  // as measured in docs/mouth.md (the best epoch was the last or the one before in every fold)
  // Two hidden layers of 512: on speechocean762's unseen speakers 1 point more Oculus-15 accuracy and 4-6 more
  // /p b m/ recall at the same precision than 256 (docs/mouth.md), still far under a millisecond a frame.
  std::vector<int> hidden{512, 512};
  std::vector<std::string> leftOut;  // speakers not to train on (to show or score the network on new voices)
};

// The corpora tracked (progress on `log`), the network trained and saved; one line on `out`.
void trainArticulation(const ArticulationTraining& training, std::ostream& out, std::ostream& log);

}  // namespace th::eval
