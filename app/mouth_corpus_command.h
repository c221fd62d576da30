// The default mouth models from tracked talking video (mouth_corpus_command.cpp): their arguments and runners,
// registered as `train mouth` and `eval mouth` by mouth_command.cpp.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "animation/mouth_model.h"
#include "eval/mouth_protocol.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"

namespace th::app {

struct MouthCorpusArguments {
  std::string tracks;  // where the clips' tracks are kept; empty: defaultMouthTrackFolder()
  // train: folders of talking clips, "FOLDER" or "FOLDER=SPEAKER" (eval/talking_corpus.h); empty: the
  // shared corpora (sharedTalkingFolders), GRID s1's every fifth clip held out.
  std::vector<std::string> corpora;
  std::vector<std::string> compare;  // eval: other model files judged on the same clips
  std::string multilingual;          // eval: the folder tools/multilingual_speech.py made; empty: made in the cache
  // The recipe (eval/mouth_protocol.h's MouthRecipe, whose defaults these are).
  animation::MouthModelOptions model = eval::MouthRecipe{}.model;
  animation::MouthSynthesisOptions synthesis = eval::MouthRecipe{}.synthesis;
  bool stageTwo = eval::MouthRecipe{}.stageTwo;
  int otherSpeakerWeight = eval::MouthRecipe{}.otherSpeakerWeight;
  // eval: set model.covariance and synthesis.method when parsed (`--recipe-diagonal`, `--recipe-inversion`).
  bool recipeDiagonal = false;
  bool recipeInversion = false;
};

std::filesystem::path defaultMouthTrackFolder();  // $XDG_CACHE_HOME/talkinghead/tracks, or ~/.cache/...
// The same, as --help says it (the same on every machine, as docs/cli.md is).
inline constexpr const char* kMouthTrackFolderHelp =
    "$XDG_CACHE_HOME/talkinghead/tracks, or ~/.cache/talkinghead/tracks";
// The talking clips of these folders, tracked (tracks kept in `tracks`, empty: the default folder), with the
// progress on stderr.
eval::TalkingCorpus loadMouthCorpus(const std::vector<eval::TalkingFolder>& folders, const std::string& tracks,
                                    const face::FaceModel& face);
void runEvalMouthCorpora(const MouthCorpusArguments& arguments);
void runTrainMouthCorpora(const MouthCorpusArguments& arguments, const std::string& output);

}  // namespace th::app
