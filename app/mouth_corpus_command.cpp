// The default mouth models, trained and judged on tracked talking video of several speakers:
//   `talkinghead train mouth -o models/mouth.json`  the shared corpora's training clips -> a model file
//   `talkinghead eval mouth`                         the recipe on held-out GRID clips, on each StyleTalk speaker
//                                                    left out, on GRID's other speakers, on BEAT2's held-out
//                                                    quarter and on speech in other languages, beside the
//                                                    baselines and any other model files
// The protocol and its measures are engine/eval's (mouth_protocol.h, talking_corpus.h, mouth_scores.h); here they
// are run in order and printed.
#include "mouth_corpus_command.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <utility>

#include "animation/fap_mapping.h"
#include "animation/mouth_model.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/subprocess.h"
#include "eval/mouth_protocol.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"
#include "face/feature_points.h"

namespace th::app {
namespace {

using eval::MouthEstimator;
using eval::PhoneClass;
using eval::TalkingClip;
using Clips = eval::TalkingClips;

std::filesystem::path cacheFolder() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0')
    return std::filesystem::path(cache) / "talkinghead";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "talkinghead";
  return std::filesystem::temp_directory_path() / "talkinghead-cache";
}

eval::MouthRecipe recipeOf(const MouthCorpusArguments& a) {
  return {
      .model = a.model, .synthesis = a.synthesis, .stageTwo = a.stageTwo, .otherSpeakerWeight = a.otherSpeakerWeight};
}

animation::MouthModel trainRecipe(const Clips& clips, const std::vector<int>& faps,
                                  const MouthCorpusArguments& arguments,
                                  const std::vector<animation::SpeechFrames>& speechOnly) {
  eval::TrainedMouthRecipe trained = eval::trainMouthRecipe(clips, faps, recipeOf(arguments), speechOnly);
  std::fprintf(stderr, "trained on %zu clips in %.1f s (%d Baum-Welch iterations)\n", clips.size(), trained.seconds,
               trained.model.iterations);
  return std::move(trained.model);
}

std::string millimetresText(const std::array<double, 3>& drop) {
  char text[80];
  std::snprintf(text, sizeof text, "%.1f / %.1f / %.1f mm", drop[0], drop[1], drop[2]);
  return text;
}

void printScores(const std::string& name, const eval::MouthScores& s) {
  std::printf("  %-50s %6.3f %6.3f %6.3f  %6.2f %6.2f  %6.3f %6.3f\n", name.c_str(), s.jaw.rho, s.opening.rho,
              s.width.rho, s.jaw.spread, s.opening.spread, s.jaw.epsilon, s.fapsEpsilon);
}

void judge(const std::string& title, const Clips& clips, const std::vector<const MouthEstimator*>& estimators,
           const MouthEstimator* shuffled, const std::vector<int>& faps, const eval::MouthShapes& shapes) {
  const eval::MouthSetJudgement set =
      eval::judgeMouthSet(clips, estimators, shuffled, faps, shapes, eval::referenceJawMillimetresPerUnit());
  std::printf("\n%s (%zu clips, %d frames, %.0f s)\n  %-50s %6s %6s %6s  %6s %6s  %6s %6s\n", title.c_str(), set.clips,
              set.frames, set.frames / animation::kMouthFramesPerSecond, "", "jaw ρ", "lip ρ", "wid ρ", "spr J",
              "spr L", "jaw ε", "FAPs ε");
  std::printf("  the truth's chin drop (5th / 50th / 95th percentile): %s\n",
              millimetresText(set.truthChinDrop).c_str());
  for (const auto& [name, scores] : set.rows) printScores(name, scores);
}

void printClassRow(const std::string& name, const eval::PhoneClassShapes& shapes) {
  std::printf("  %-50s %7.3f %7.3f %7.3f   %7.3f %7.3f\n", name.c_str(), shapes.mean(PhoneClass::kBilabial)[0],
              shapes.mean(PhoneClass::kOpenVowel)[0],
              shapes.mean(PhoneClass::kOpenVowel)[0] - shapes.mean(PhoneClass::kBilabial)[0],
              shapes.mean(PhoneClass::kRoundedVowel)[1], shapes.mean(PhoneClass::kSpreadVowel)[1]);
}

void reportPhoneClasses(const std::string& title, const Clips& clips,
                        const std::vector<const MouthEstimator*>& estimators, const eval::MouthShapes& shapes) {
  const eval::PhoneClassJudgement classes = eval::judgePhoneClasses(clips, estimators, shapes);
  const eval::PhoneClassShapes& truth = classes.truth;
  std::printf(
      "\n%s: lip opening at bilabials (%d frames) and open vowels (%d), and their difference; mouth width at "
      "rounded (%d) and spread vowels (%d); shares of the eye corners' distance\n  %-50s %7s %7s %7s   %7s %7s\n",
      title.c_str(), truth.count(PhoneClass::kBilabial), truth.count(PhoneClass::kOpenVowel),
      truth.count(PhoneClass::kRoundedVowel), truth.count(PhoneClass::kSpreadVowel), "", "/p b m/", "open V", "diff",
      "rounded", "spread");
  printClassRow("truth (the tracked landmarks)", truth);
  for (const auto& [name, shapesOfEstimator] : classes.estimated) printClassRow(name, shapesOfEstimator);
}

void judgeBeat2(const std::vector<const MouthEstimator*>& estimators, const animation::MouthFapMap& map) {
  const eval::Beat2JawJudgement beat2 = eval::judgeBeat2Jaw(estimators, map);
  std::printf(
      "\nBEAT2's held-out quarter (%.1f s) against the motion capture's jaw (FAP 3 through the jaw's geometry; "
      "speech from the whole take, scored on the last quarter)\n  %-50s %6s %6s %6s\n",
      beat2.seconds, "", "jaw ρ", "spr J", "jaw ε");
  for (const auto& [name, score] : beat2.rows)
    std::printf("  %-50s %6.3f %6.2f %6.3f\n", name.c_str(), score.rho, score.spread, score.epsilon);
}

void reportLanguages(const std::filesystem::path& folder, const std::vector<const MouthEstimator*>& estimators,
                     const eval::PhoneClassShapes& typical, const eval::MouthShapes& shapes) {
  (void)eval::readMultilingualIndex(folder);  // a missing index fails before the heading
  std::printf(
      "\nOther languages (%s: espeak-ng, phone-aligned): per language, the correlation of the lip opening "
      "with each phone class's typical opening on tracked speakers, and (open vowels - /p b m/) / spread\n"
      "  %-8s",
      folder.c_str(), "");
  for (const MouthEstimator* e : estimators) std::printf(" %24.24s", e->name.c_str());
  std::printf("\n");
  const eval::LanguageJudgement languages = eval::judgeLanguages(folder, estimators, typical, shapes);
  for (const auto& [language, scores] : languages.languages) {
    std::printf("  %-8s", language.c_str());
    for (const auto& score : scores) std::printf("       ρ %6.3f  gap %5.2f", score.rho, score.gap);
    std::printf("\n");
  }
  std::printf("  %-8s", "mean");
  for (const auto& mean : languages.meanOverOthers) std::printf("       ρ %6.3f  gap %5.2f", mean.rho, mean.gap);
  std::printf("   (the %.0f languages other than English)\n", languages.others);
  if (!languages.beatsLevel.empty()) {
    std::printf("  %-8s", "> level");
    for (const int wins : languages.beatsLevel) std::printf(" %15d of %.0f    ", wins, languages.others);
    std::printf("   (languages where ρ beats the sound's level)\n");
  }
}

// The multilingual folder: made by the tool on first use.
std::filesystem::path multilingualFolder(const std::string& given) {
  if (!given.empty()) return given;
  const std::filesystem::path folder = cacheFolder() / "multilingual";
  std::error_code missing;
  if (!std::filesystem::is_regular_file(folder / "index.csv", missing)) {
    const std::string tool = std::string(TALKINGHEAD_SOURCE_DIR) + "/tools/multilingual_speech.py";
    std::fprintf(stderr, "making the multilingual test speech: %s -o %s\n", tool.c_str(), folder.c_str());
    runProgram({"/usr/bin/python3", tool, "-o", folder.string()});
  }
  return folder;
}

// The demo's speech (setup.sh's build/demo.mp4): how far the chin drops, in mm on the reference face.
void reportChinDrop(const std::vector<const MouthEstimator*>& estimators) {
  const double millimetresPerUnit = eval::referenceJawMillimetresPerUnit();
  std::printf(
      "\nThe demo's speech (BEAT2, 64 s): the chin's drop (FAP 3 on the reference face, MNS0 = %.1f mm), "
      "5th / 50th / 95th percentile in mm\n",
      millimetresPerUnit * 1024.0);
  for (const auto& [name, drop] : eval::demoChinDrops(estimators, millimetresPerUnit))
    std::printf("  %-50s %5.1f / %5.1f / %5.1f\n", name.c_str(), drop[0], drop[1], drop[2]);
}

}  // namespace

eval::TalkingCorpus loadMouthCorpus(const std::vector<eval::TalkingFolder>& folders, const std::string& tracks,
                                    const face::FaceModel& face) {
  tracking::VideoCorpusOptions options;
  options.trackFolder = tracks.empty() ? defaultMouthTrackFolder() : std::filesystem::path(tracks);
  options.synchronise = true;
  ProgressBar bar(1.0, "track", std::cerr);
  eval::TalkingCorpus corpus = eval::loadTalkingCorpus(
      folders, face, options, [&](int done, int total) { bar.update(static_cast<double>(done) / total); });
  bar.finish();
  int trackedNow = 0;
  for (const TalkingClip& clip : corpus.clips) trackedNow += clip.clip.trackedNow ? 1 : 0;
  std::fprintf(stderr, "%zu clips (%d tracked now; tracks kept in %s) in %.1f s\n", corpus.clips.size(), trackedNow,
               options.trackFolder.c_str(), corpus.trackingSeconds);
  for (const auto& skipped : corpus.skipped) std::fprintf(stderr, "  left out: %s\n", skipped.reason.c_str());
  return corpus;
}

std::filesystem::path defaultMouthTrackFolder() {
  return cacheFolder() / "tracks";
}

void runEvalMouthCorpora(const MouthCorpusArguments& arguments) {
  const face::FaceModel face = face::FaceModel::buildDefault();
  std::vector<std::pair<std::string, animation::MouthModel>> others;
  for (const std::string& file : arguments.compare) others.emplace_back(file, animation::loadMouthModel(file));
  const std::filesystem::path languages = multilingualFolder(arguments.multilingual);
  std::vector<eval::TalkingFolder> folders = eval::sharedTalkingFolders();
  folders.push_back({sharedDataPath("grid/samples"), ""});
  const eval::TalkingCorpus corpus = loadMouthCorpus(folders, arguments.tracks, face);
  const eval::MouthShapes shapes(face);

  std::printf("Mouth from audio, the recipe: %s\n", eval::describeMouthRecipe(recipeOf(arguments)).c_str());
  if (!arguments.compare.empty())
    std::printf(
        "Model files given with --compare are judged as they are: on clips they were trained on (the shipped "
        "models/mouth.json on StyleTalk's speakers) they are not held out.\n");
  std::printf(
      "\nSound against picture, per clip of 10 s or more (the offset is taken out before training and "
      "scoring):\n");
  for (const TalkingClip& clip : corpus.clips)
    if (clip.clip.soundOffset.measured)
      std::printf("  %-28s the sound lags the picture by %4.0f ms (r %.2f)\n", clip.clip.video.filename().c_str(),
                  1000.0 * clip.clip.soundOffset.lateSeconds, clip.clip.soundOffset.correlation);
  // The lips' natural lead over the sound, on GRID: the same measure on each 3 s clip, the median over all.
  const eval::LipLead lead = eval::gridLipLead(corpus);
  std::printf(
      "  GRID s1 (in sync): the mouth leads the sound by %.0f ms (median over %zu clips; the lead taken as "
      "natural: %.0f ms)\n",
      lead.medianMs, lead.clips, 1000.0 * tracking::SoundSyncOptions{}.naturalLeadSeconds);

  const eval::MouthEvaluationSets sets = eval::mouthEvaluationSets(corpus);
  const eval::SpeechOnlyRecordings speechOnly = eval::speechOnlyRecordings();
  if (arguments.stageTwo) std::printf("\nStage 2 speech: %.0f s of speech-only recordings\n", speechOnly.seconds);

  std::vector<MouthEstimator> compared;
  for (const auto& [name, model] : others) compared.push_back(eval::modelEstimator(name, model, arguments.synthesis));

  // The recipe trained on GRID's training clips and every StyleTalk speaker: judged on GRID's held-out clips, its
  // other speakers, BEAT2, other languages and the demo.
  const Clips training = eval::mouthTrainingClips(sets);
  const animation::MouthModel model = trainRecipe(training, corpus.faps, arguments, speechOnly.speech);
  const eval::MouthJudged judged(model, arguments.synthesis, training, corpus.faps, compared);
  const MouthEstimator& recipe = judged.recipe;
  const std::vector<const MouthEstimator*>& all = judged.all;
  std::printf("\nTrained on GRID s1's training clips and all StyleTalk speakers (%zu clips); variance scale:",
              training.size());
  for (Eigen::Index k = 0; k < model.varianceScale.size(); ++k) std::printf(" %.2f", model.varianceScale[k]);
  std::printf("\n");
  judge("GRID s1, held-out clips", sets.gridTest, all, &recipe, corpus.faps, shapes);
  judge("GRID, other speakers (never trained on)", sets.gridOthers, all, nullptr, corpus.faps, shapes);
  reportPhoneClasses("GRID s1, held-out clips (word alignments)", sets.gridTest, all, shapes);

  // Each StyleTalk speaker left out.
  eval::PhoneClassShapes styleTalkTruth;
  for (const auto& [speaker, clips] : sets.styleTalkSpeakers) {
    const Clips foldTraining = eval::mouthTrainingClips(sets, speaker);
    const animation::MouthModel fold = trainRecipe(foldTraining, corpus.faps, arguments, speechOnly.speech);
    const eval::MouthJudged foldJudged(fold, arguments.synthesis, foldTraining, corpus.faps, compared);
    judge("StyleTalk speaker left out: " + speaker, clips, foldJudged.all, &foldJudged.recipe, corpus.faps, shapes);
    reportPhoneClasses("StyleTalk speaker left out: " + speaker + " (phones)", clips, foldJudged.all, shapes);
    eval::addPhoneClassTruth(styleTalkTruth, clips);
  }

  std::vector<const MouthEstimator*> speechJudged = all;
  speechJudged.pop_back();  // the training mean says nothing of speech without video
  judgeBeat2(speechJudged, animation::defineMouthFapMap(face::loadIctFace(face::ictFaceDirectory())));
  reportLanguages(languages, speechJudged, styleTalkTruth, shapes);
  reportChinDrop(speechJudged);
}

void runTrainMouthCorpora(const MouthCorpusArguments& arguments, const std::string& output) {
  const std::filesystem::path path = output;
  if (path.extension() != ".json") throw fileError(path, "a model is written as JSON: give a .json name");
  checkOutputTarget(path);
  std::vector<eval::TalkingFolder> folders;
  for (const std::string& corpus : arguments.corpora) {
    const std::size_t equals = corpus.find('=');
    folders.push_back(
        {corpus.substr(0, equals), equals == std::string::npos ? std::string() : corpus.substr(equals + 1)});
  }
  if (folders.empty()) folders = eval::sharedTalkingFolders();
  const face::FaceModel face = face::FaceModel::buildDefault();
  const eval::TalkingCorpus corpus = loadMouthCorpus(folders, arguments.tracks, face);
  const eval::GridSplit split = eval::splitGrid(corpus);
  const Clips training = eval::mouthModelTrainingClips(split);
  const eval::SpeechOnlyRecordings speechOnly = eval::speechOnlyRecordings();
  const animation::MouthModel model = trainRecipe(training, corpus.faps, arguments, speechOnly.speech);
  animation::saveMouthModel(path, model, arguments.model);
  double seconds = 0.0;
  for (const TalkingClip* clip : training)
    seconds += clip->clip.recording.numFrames() / animation::kMouthFramesPerSecond;
  std::fprintf(
      stderr, "mouth model: %s; trained on %zu clips (%.0f s of talking video%s)%s; wrote %s\n",
      eval::describeMouthRecipe(recipeOf(arguments)).c_str(), training.size(), seconds,
      split.heldOut.empty() ? "" : ", GRID s1's every fifth clip kept for `eval mouth`",
      arguments.stageTwo
          ? (" and " + std::to_string(static_cast<int>(speechOnly.seconds)) + " s of speech-only voices").c_str()
          : "",
      path.c_str());
}

}  // namespace th::app
