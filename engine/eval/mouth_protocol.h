// The default mouth models trained and judged on tracked talking video of several speakers (`train mouth`,
// `eval mouth`): how the corpora are split, the recipe trained, the estimators and baselines, and what each set
// is judged by (mouth_scores.h), per corpus, per phone class, on BEAT2's motion-captured jaw, on speech in other
// languages and by the chin's drop on the demo's speech.
//
//   th::eval::GridSplit split = th::eval::splitGrid(corpus);            // GRID s1's every fifth clip held out
//   th::eval::TrainedMouthRecipe trained = th::eval::trainMouthRecipe(split.train, corpus.faps, recipe, {});
//   th::eval::MouthJudged judged(trained.model, recipe.synthesis, split.train, corpus.faps, {});
//   th::eval::MouthSetJudgement set = th::eval::judgeMouthSet(split.heldOut, judged.all, &judged.recipe,
//                                                             corpus.faps, shapes, millimetresPerUnit);
//
// Thread contract: pure functions of their arguments and the files they name; an estimator may be called from
// one thread at a time.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "animation/fap_mapping.h"
#include "animation/mouth_data.h"
#include "animation/mouth_model.h"
#include "eval/mouth_scores.h"
#include "eval/talking_corpus.h"

namespace th::eval {

using TalkingClips = std::vector<const TalkingClip*>;

// The recipe: the mouth model's options, how it is synthesised, and what it is trained on besides the video.
struct MouthRecipe {
  animation::MouthModelOptions model = animation::videoMouthRecipe();
  animation::MouthSynthesisOptions synthesis{.method = animation::MouthMethod::kMmse};
  bool stageTwo = false;  // re-train the audio side on speech-only recordings of other voices
  // How many times each clip of a speaker other than GRID's s1 counts in training (GRID's one speaker has 16
  // minutes, the others 18-70 s each).
  int otherSpeakerWeight = 1;
};
// "16 states x 2 Gaussians (full covariance), MFCC context +-3, ..."
std::string describeMouthRecipe(const MouthRecipe& recipe);

inline constexpr const char* kGridSpeaker = "grid-s1";

// GRID s1's clips split by name (every fifth of each of its folders held out) and every other speaker's clips.
struct GridSplit {
  TalkingClips train;
  TalkingClips heldOut;
  std::map<std::string, TalkingClips> otherSpeakers;
};
GridSplit splitGrid(const TalkingCorpus& corpus);

// The sets `eval mouth` judges on, from a corpus of the shared folders and GRID's samples: GRID s1's split, GRID's
// other speakers (grid/samples, never trained on; its bbaf2n is s1 himself and left out) and StyleTalk's
// clips, also by speaker.
struct MouthEvaluationSets {
  TalkingClips gridTrain;
  TalkingClips gridTest;
  TalkingClips gridOthers;
  TalkingClips styleTalk;
  std::map<std::string, TalkingClips> styleTalkSpeakers;
};
MouthEvaluationSets mouthEvaluationSets(const TalkingCorpus& corpus);
// The recipe's training clips: GRID s1's training clips and every StyleTalk clip except `leftOut`'s ("" keeps
// every speaker).
TalkingClips mouthTrainingClips(const MouthEvaluationSets& sets, const std::string& leftOut = "");
// What `train mouth` trains on: GRID s1's training clips and every other speaker's.
TalkingClips mouthModelTrainingClips(const GridSplit& split);

// The recordings to train on: GRID s1's clips once, the others' otherSpeakerWeight times.
std::vector<animation::MouthRecording> mouthRecordingsOf(const TalkingClips& clips, int otherSpeakerWeight = 1);

// Speech without video for the audio side (stage 2): voices other than the videos', none of them judged.
struct SpeechOnlyRecordings {
  std::vector<animation::SpeechFrames> speech;
  double seconds = 0.0;
};
SpeechOnlyRecordings speechOnlyRecordings();

struct TrainedMouthRecipe {
  animation::MouthModel model;
  double seconds = 0.0;  // the training's wall-clock time
};
// The recipe's model on these clips (and, with stage 2, the speech-only recordings), driving `faps`.
TrainedMouthRecipe trainMouthRecipe(const TalkingClips& clips, const std::vector<int>& faps, const MouthRecipe& recipe,
                                    const std::vector<animation::SpeechFrames>& speechOnly);

// A model's FAP curves for speech, and the FAP numbers of their rows.
struct MouthEstimator {
  std::string name;
  std::function<Eigen::MatrixXd(const animation::SpeechFrames&)> estimate;
  std::vector<int> faps;
};
// The model is referred to, not copied: it must outlive the estimator.
MouthEstimator modelEstimator(const std::string& name, const animation::MouthModel& model,
                              const animation::MouthSynthesisOptions& synthesis);

// The clips' estimates: each clip's own speech, or (shift 1) the next clip's.
std::vector<Eigen::MatrixXd> estimatesFor(const MouthEstimator& estimator, const TalkingClips& clips, int shift = 0);

// The baselines fitted on training clips: the sound's level (linear, ±2 frames) and the training mean.
struct MouthBaselines {
  MouthEstimator level;
  MouthEstimator mean;
};
MouthBaselines mouthBaselinesFor(const TalkingClips& training, const std::vector<int>& faps);
inline constexpr const char* kLevelBaselineName = "baseline: the sound's level alone (linear, +-2 frames)";

// What a set is judged with: the recipe's model with and without its variance compensation, the other model
// files, and the baselines fitted on the model's training clips (in that order; the training mean last).
struct MouthJudged {
  MouthEstimator recipe;
  MouthEstimator plain;
  MouthBaselines baselines;
  std::vector<const MouthEstimator*> all;
  MouthJudged(const animation::MouthModel& model, const animation::MouthSynthesisOptions& synthesis,
              const TalkingClips& training, const std::vector<int>& faps, const std::vector<MouthEstimator>& compared);
  MouthJudged(const MouthJudged&) = delete;
  MouthJudged& operator=(const MouthJudged&) = delete;
};

// The 5th, 50th and 95th percentile of drops (each the nearest rank below); zeros when there are none.
std::array<double, 3> chinDropPercentiles(std::vector<double> dropMillimetres);
// The truth's chin drop over the clips (FAP 3 of the recordings' visual rows `faps`, negative values taken as 0),
// in mm at millimetresPerUnit.
std::array<double, 3> truthChinDrop(const TalkingClips& clips, const std::vector<int>& faps, double millimetresPerUnit);
// The millimetres of one unit of FAP 3 (MNS, the mouth-nose separation over 1024) on the reference face.
double referenceJawMillimetresPerUnit();

// A set of clips judged: the truth's chin drop and each estimator's scores (and, when asked, the recipe on
// another clip's sound).
struct MouthSetJudgement {
  std::size_t clips = 0;
  int frames = 0;
  std::array<double, 3> truthChinDrop{};  // mm
  std::vector<std::pair<std::string, MouthScores>> rows;
};
MouthSetJudgement judgeMouthSet(const TalkingClips& clips, const std::vector<const MouthEstimator*>& estimators,
                                const MouthEstimator* shuffled, const std::vector<int>& faps, const MouthShapes& shapes,
                                double millimetresPerUnit);

// Lip opening and width per phone class: the truth's (the tracked landmarks) and each estimator's, over the
// clips with labels.
struct PhoneClassJudgement {
  PhoneClassShapes truth;
  std::vector<std::pair<std::string, PhoneClassShapes>> estimated;
};
PhoneClassJudgement judgePhoneClasses(const TalkingClips& clips, const std::vector<const MouthEstimator*>& estimators,
                                      const MouthShapes& shapes);
// The clips' tracked lip shapes added to `truth` by their labels' classes (the typical opening per class that
// judgeLanguages reads).
void addPhoneClassTruth(PhoneClassShapes& truth, const TalkingClips& clips);

// BEAT2's held-out quarter against its motion capture's jaw, through the jaw's geometry (fap_mapping.h): FAP 3
// of the true jaw opening against the estimates' FAP 3, speech from the whole take.
struct Beat2JawJudgement {
  double seconds = 0.0;  // scored
  std::vector<std::pair<std::string, CurveScore>> rows;
};
Beat2JawJudgement judgeBeat2Jaw(const std::vector<const MouthEstimator*>& estimators,
                                const animation::MouthFapMap& map);

// Speech in other languages (tools/multilingual_speech.py: espeak-ng, every phone's time known): the lips'
// opening an estimate gives against the opening each phone class has on tracked speakers (`typical`), and the
// gap between open vowels and /p b m/ in units of the estimate's spread.
struct LanguageScore {
  double rho = 0.0;
  double gap = 0.0;
};
struct LanguageJudgement {
  std::vector<std::pair<std::string, std::vector<LanguageScore>>> languages;  // by code; per estimator
  std::vector<LanguageScore> meanOverOthers;  // per estimator, over the languages other than English
  double others = 0.0;                        // how many those are
  // Per estimator, the other languages where its ρ beats the sound's level (empty if no estimator is named
  // kLevelBaselineName).
  std::vector<int> beatsLevel;
};
// The folder's index.csv: each language's files (the first column, by the second).
std::map<std::string, std::vector<std::string>> readMultilingualIndex(const std::filesystem::path& folder);
// A NAME.phones.csv: start,end,phone,class rows after a header; unknown classes are consonants.
std::vector<std::pair<LabelInterval, PhoneClass>> readClassedPhones(const std::filesystem::path& phonesFile);
LanguageJudgement judgeLanguages(const std::filesystem::path& folder,
                                 const std::vector<const MouthEstimator*>& estimators, const PhoneClassShapes& typical,
                                 const MouthShapes& shapes);

// The demo's speech (BEAT2's take): how far the chin drops under each estimator, in mm on the reference face.
std::vector<std::pair<std::string, std::array<double, 3>>> demoChinDrops(
    const std::vector<const MouthEstimator*>& estimators, double millimetresPerUnit);

// The lips' natural lead over the sound on GRID s1 (whose word alignments, from the sound, put the lips' closure
// where /b p/ words start): the offset measured on each clip with no lead assumed, the median over the clips, ms.
struct LipLead {
  double medianMs = 0.0;
  std::size_t clips = 0;
};
LipLead gridLipLead(const TalkingCorpus& corpus);

}  // namespace th::eval
