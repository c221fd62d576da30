// The default mouth models trained and judged on tracked talking video of several speakers, as the commands run
// them:
//   `talkinghead train mouth -o models/mouth.json`  the shared corpora's training clips → a model file
//   `talkinghead eval mouth`                         the recipe on held-out GRID clips, on each StyleTalk speaker
//                                                    left out, on GRID's other speakers, on BEAT2's held-out
//                                                    quarter and on speech in other languages, beside the
//                                                    baselines and any other model files
// The protocol and its measures are mouth_protocol.h's, talking_corpus.h's and mouth_scores.h's; here they are
// run in order and written as the command's tables.
//
//   th::eval::reportMouthOnTalkingCorpora({.languages = folder}, std::cout, std::cerr);
//   th::eval::trainMouthOnTalkingCorpora({.output = "models/mouth.json"}, std::cerr);
//
// Thread contract: one call at a time per stream (the tracking runs on threads of its own).
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "animation/mouth_model.h"
#include "eval/mouth_protocol.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"

namespace th::eval {

std::filesystem::path userCacheFolder();          // $XDG_CACHE_HOME/talkinghead, or ~/.cache/talkinghead
std::filesystem::path defaultMouthTrackFolder();  // userCacheFolder()/tracks
// The same, as --help says it (the same on every machine, as docs/cli.md is).
inline constexpr const char* kMouthTrackFolderHelp =
    "$XDG_CACHE_HOME/talkinghead/tracks, or ~/.cache/talkinghead/tracks";

// The talking clips of these folders, tracked (tracks kept in `tracks`, empty: the default folder), with a
// progress bar, the count tracked now and the clips left out on `log`.
TalkingCorpus loadTrackedTalkingCorpus(const std::vector<TalkingFolder>& folders, const std::filesystem::path& tracks,
                                       const face::FaceModel& face, std::ostream& log);

struct MouthCorpusReportOptions {
  MouthRecipe recipe;
  // Other models judged on the same clips as they are, by name (on clips they were trained on they are not
  // held out).
  std::vector<std::pair<std::string, animation::MouthModel>> compared;
  std::filesystem::path languages;  // phone-aligned speech in other languages (tools/multilingual_speech.py)
  std::filesystem::path tracks;     // empty: defaultMouthTrackFolder()
};

// The shared corpora and GRID's other speakers tracked, the recipe trained and judged set by set; the tables on
// `out`, the tracking and the trainings on `log`.
void reportMouthOnTalkingCorpora(const MouthCorpusReportOptions& options, std::ostream& out, std::ostream& log);

struct MouthCorpusTraining {
  MouthRecipe recipe;
  std::vector<TalkingFolder> folders;  // empty: sharedTalkingFolders(), GRID s1's every fifth clip held out
  std::filesystem::path tracks;        // empty: defaultMouthTrackFolder()
  std::filesystem::path output = "models/mouth.json";
};

// The recipe trained on the folders' training clips and saved as JSON; what it was trained on on `log`.
void trainMouthOnTalkingCorpora(const MouthCorpusTraining& training, std::ostream& log);

}  // namespace th::eval
