// The viseme model (animation/viseme_model.h) as `talkinghead train visemes` and `eval visemes` run it: trained
// on the shared data's phone-aligned speech (viseme_corpus.h), and judged leave one speaker out: accuracy against
// the phones' visemes (Oculus, Rhubarb, the mouth classes), the confusion matrices and how long each viseme is
// held.
//
//   th::eval::reportVisemes({.lagFrames = 2, .sweep = true}, std::cout);
//   th::eval::trainVisemesOnCorpus("models/visemes.json", {}, std::cout);
//
// Thread contract: one call at a time per stream.
#pragma once

#include <filesystem>
#include <ostream>

#include "animation/viseme_model.h"

namespace th::eval {

struct VisemeReportOptions {
  animation::VisemeModelOptions model;  // the recipe each fold trains
  int lagFrames = 2;                    // the streamed decoder's decision lag
  bool sweep = false;                   // also the minimum hold and the emission scale, one at a time
};

void reportVisemes(const VisemeReportOptions& options, std::ostream& out);

// The model trained on every recording of the corpus and saved; one line on `out`.
void trainVisemesOnCorpus(const std::filesystem::path& output, const animation::VisemeModelOptions& model,
                          std::ostream& out);

}  // namespace th::eval
