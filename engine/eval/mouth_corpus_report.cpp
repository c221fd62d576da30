#include "eval/mouth_corpus_report.h"

#include <array>
#include <cstdio>
#include <cstdlib>

#include "animation/fap_mapping.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/print_to.h"
#include "core/progress.h"
#include "face/feature_points.h"

namespace th::eval {
namespace {

animation::MouthModel trainRecipeLogged(const TalkingClips& clips, const std::vector<int>& faps,
                                        const MouthRecipe& recipe,
                                        const std::vector<animation::SpeechFrames>& speechOnly, std::ostream& log) {
  TrainedMouthRecipe trained = trainMouthRecipe(clips, faps, recipe, speechOnly);
  printTo(log, "trained on %zu clips in %.1f s (%d Baum-Welch iterations)\n", clips.size(), trained.seconds,
          trained.model.iterations);
  return std::move(trained.model);
}

std::string millimetresText(const std::array<double, 3>& drop) {
  char text[80];
  std::snprintf(text, sizeof text, "%.1f / %.1f / %.1f mm", drop[0], drop[1], drop[2]);
  return text;
}

void writeMouthScores(std::ostream& out, const std::string& name, const MouthScores& s) {
  printTo(out, "  %-50s %6.3f %6.3f %6.3f  %6.2f %6.2f  %6.3f %6.3f\n", name.c_str(), s.jaw.rho, s.opening.rho,
          s.width.rho, s.jaw.spread, s.opening.spread, s.jaw.epsilon, s.fapsEpsilon);
}

void writeSetJudgement(std::ostream& out, const std::string& title, const TalkingClips& clips,
                       const std::vector<const MouthEstimator*>& estimators, const MouthEstimator* shuffled,
                       const std::vector<int>& faps, const MouthShapes& shapes) {
  const MouthSetJudgement set =
      judgeMouthSet(clips, estimators, shuffled, faps, shapes, referenceJawMillimetresPerUnit());
  printTo(out, "\n%s (%zu clips, %d frames, %.0f s)\n  %-50s %6s %6s %6s  %6s %6s  %6s %6s\n", title.c_str(), set.clips,
          set.frames, set.frames / animation::kMouthFramesPerSecond, "", "jaw ρ", "lip ρ", "wid ρ", "spr J", "spr L",
          "jaw ε", "FAPs ε");
  printTo(out, "  the truth's chin drop (5th / 50th / 95th percentile): %s\n",
          millimetresText(set.truthChinDrop).c_str());
  for (const auto& [name, scores] : set.rows) writeMouthScores(out, name, scores);
}

void writeClassRow(std::ostream& out, const std::string& name, const PhoneClassShapes& shapes) {
  printTo(out, "  %-50s %7.3f %7.3f %7.3f   %7.3f %7.3f\n", name.c_str(), shapes.mean(PhoneClass::kBilabial)[0],
          shapes.mean(PhoneClass::kOpenVowel)[0],
          shapes.mean(PhoneClass::kOpenVowel)[0] - shapes.mean(PhoneClass::kBilabial)[0],
          shapes.mean(PhoneClass::kRoundedVowel)[1], shapes.mean(PhoneClass::kSpreadVowel)[1]);
}

void writePhoneClasses(std::ostream& out, const std::string& title, const TalkingClips& clips,
                       const std::vector<const MouthEstimator*>& estimators, const MouthShapes& shapes) {
  const PhoneClassJudgement classes = judgePhoneClasses(clips, estimators, shapes);
  const PhoneClassShapes& truth = classes.truth;
  printTo(out,
          "\n%s: lip opening at bilabials (%d frames) and open vowels (%d), and their difference; mouth width at "
          "rounded (%d) and spread vowels (%d); shares of the eye corners' distance\n  %-50s %7s %7s %7s   %7s "
          "%7s\n",
          title.c_str(), truth.count(PhoneClass::kBilabial), truth.count(PhoneClass::kOpenVowel),
          truth.count(PhoneClass::kRoundedVowel), truth.count(PhoneClass::kSpreadVowel), "", "/p b m/", "open V",
          "diff", "rounded", "spread");
  writeClassRow(out, "truth (the tracked landmarks)", truth);
  for (const auto& [name, shapesOfEstimator] : classes.estimated) writeClassRow(out, name, shapesOfEstimator);
}

void writeBeat2Jaw(std::ostream& out, const std::vector<const MouthEstimator*>& estimators,
                   const animation::MouthFapMap& map) {
  const Beat2JawJudgement beat2 = judgeBeat2Jaw(estimators, map);
  printTo(out,
          "\nBEAT2's held-out quarter (%.1f s) against the motion capture's jaw (FAP 3 through the jaw's geometry; "
          "speech from the whole take, scored on the last quarter)\n  %-50s %6s %6s %6s\n",
          beat2.seconds, "", "jaw ρ", "spr J", "jaw ε");
  for (const auto& [name, score] : beat2.rows)
    printTo(out, "  %-50s %6.3f %6.2f %6.3f\n", name.c_str(), score.rho, score.spread, score.epsilon);
}

void writeLanguages(std::ostream& out, const std::filesystem::path& folder,
                    const std::vector<const MouthEstimator*>& estimators, const PhoneClassShapes& typical,
                    const MouthShapes& shapes) {
  (void)readMultilingualIndex(folder);  // a missing index fails before the heading
  printTo(out,
          "\nOther languages (%s: espeak-ng, phone-aligned): per language, the correlation of the lip opening "
          "with each phone class's typical opening on tracked speakers, and (open vowels - /p b m/) / spread\n"
          "  %-8s",
          folder.c_str(), "");
  for (const MouthEstimator* e : estimators) printTo(out, " %24.24s", e->name.c_str());
  out << '\n';
  const LanguageJudgement languages = judgeLanguages(folder, estimators, typical, shapes);
  for (const auto& [language, scores] : languages.languages) {
    printTo(out, "  %-8s", language.c_str());
    for (const auto& score : scores) printTo(out, "       ρ %6.3f  gap %5.2f", score.rho, score.gap);
    out << '\n';
  }
  printTo(out, "  %-8s", "mean");
  for (const auto& mean : languages.meanOverOthers) printTo(out, "       ρ %6.3f  gap %5.2f", mean.rho, mean.gap);
  printTo(out, "   (the %.0f languages other than English)\n", languages.others);
  if (!languages.beatsLevel.empty()) {
    printTo(out, "  %-8s", "> level");
    for (const int wins : languages.beatsLevel) printTo(out, " %15d of %.0f    ", wins, languages.others);
    out << "   (languages where ρ beats the sound's level)\n";
  }
}

// The demo's speech (setup.sh's build/demo.mp4): how far the chin drops, in mm on the reference face.
void writeChinDrop(std::ostream& out, const std::vector<const MouthEstimator*>& estimators) {
  const double millimetresPerUnit = referenceJawMillimetresPerUnit();
  printTo(out,
          "\nThe demo's speech (BEAT2, 64 s): the chin's drop (FAP 3 on the reference face, MNS0 = %.1f mm), "
          "5th / 50th / 95th percentile in mm\n",
          millimetresPerUnit * 1024.0);
  for (const auto& [name, drop] : demoChinDrops(estimators, millimetresPerUnit))
    printTo(out, "  %-50s %5.1f / %5.1f / %5.1f\n", name.c_str(), drop[0], drop[1], drop[2]);
}

// What the recipe is, and how the sound of each clip sits against its picture.
void writeCorpusOpening(std::ostream& out, const MouthCorpusReportOptions& options, const TalkingCorpus& corpus) {
  printTo(out, "Mouth from audio, the recipe: %s\n", describeMouthRecipe(options.recipe).c_str());
  if (!options.compared.empty())
    out << "Model files given with --compare are judged as they are: on clips they were trained on (the shipped "
           "models/mouth.json on StyleTalk's speakers) they are not held out.\n";
  out << "\nSound against picture, per clip of 10 s or more (the offset is taken out before training and "
         "scoring):\n";
  for (const TalkingClip& clip : corpus.clips)
    if (clip.clip.soundOffset.measured)
      printTo(out, "  %-28s the sound lags the picture by %4.0f ms (r %.2f)\n", clip.clip.video.filename().c_str(),
              1000.0 * clip.clip.soundOffset.lateSeconds, clip.clip.soundOffset.correlation);
  // The lips' natural lead over the sound, on GRID: the same measure on each 3 s clip, the median over all.
  const LipLead lead = gridLipLead(corpus);
  printTo(out,
          "  GRID s1 (in sync): the mouth leads the sound by %.0f ms (median over %zu clips; the lead taken as "
          "natural: %.0f ms)\n",
          lead.medianMs, lead.clips, 1000.0 * tracking::SoundSyncOptions{}.naturalLeadSeconds);
}

}  // namespace

std::filesystem::path userCacheFolder() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0')
    return std::filesystem::path(cache) / "talkinghead";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "talkinghead";
  return std::filesystem::temp_directory_path() / "talkinghead-cache";
}

std::filesystem::path defaultMouthTrackFolder() {
  return userCacheFolder() / "tracks";
}

TalkingCorpus loadTrackedTalkingCorpus(const std::vector<TalkingFolder>& folders, const std::filesystem::path& tracks,
                                       const face::FaceModel& face, std::ostream& log) {
  tracking::VideoCorpusOptions options;
  options.trackFolder = tracks.empty() ? defaultMouthTrackFolder() : tracks;
  options.synchronise = true;
  ProgressBar bar(1.0, "track", log);
  TalkingCorpus corpus = loadTalkingCorpus(folders, face, options,
                                           [&](int done, int total) { bar.update(static_cast<double>(done) / total); });
  bar.finish();
  int trackedNow = 0;
  for (const TalkingClip& clip : corpus.clips) trackedNow += clip.clip.trackedNow ? 1 : 0;
  printTo(log, "%zu clips (%d tracked now; tracks kept in %s) in %.1f s\n", corpus.clips.size(), trackedNow,
          options.trackFolder.c_str(), corpus.trackingSeconds);
  for (const auto& skipped : corpus.skipped) printTo(log, "  left out: %s\n", skipped.reason.c_str());
  return corpus;
}

void reportMouthOnTalkingCorpora(const MouthCorpusReportOptions& options, std::ostream& out, std::ostream& log) {
  const face::FaceModel face = face::FaceModel::buildDefault();
  std::vector<TalkingFolder> folders = sharedTalkingFolders();
  folders.push_back({sharedDataPath("grid/samples"), ""});
  const TalkingCorpus corpus = loadTrackedTalkingCorpus(folders, options.tracks, face, log);
  const MouthShapes shapes(face);
  writeCorpusOpening(out, options, corpus);

  const MouthEvaluationSets sets = mouthEvaluationSets(corpus);
  const SpeechOnlyRecordings speechOnly = speechOnlyRecordings();
  if (options.recipe.stageTwo) printTo(out, "\nStage 2 speech: %.0f s of speech-only recordings\n", speechOnly.seconds);

  std::vector<MouthEstimator> compared;
  for (const auto& [name, model] : options.compared)
    compared.push_back(modelEstimator(name, model, options.recipe.synthesis));

  // The recipe trained on GRID's training clips and every StyleTalk speaker: judged on GRID's held-out clips, its
  // other speakers, BEAT2, other languages and the demo.
  const TalkingClips training = mouthTrainingClips(sets);
  const animation::MouthModel model = trainRecipeLogged(training, corpus.faps, options.recipe, speechOnly.speech, log);
  const MouthJudged judged(model, options.recipe.synthesis, training, corpus.faps, compared);
  const std::vector<const MouthEstimator*>& all = judged.all;
  printTo(out, "\nTrained on GRID s1's training clips and all StyleTalk speakers (%zu clips); variance scale:",
          training.size());
  for (Eigen::Index k = 0; k < model.varianceScale.size(); ++k) printTo(out, " %.2f", model.varianceScale[k]);
  out << '\n';
  writeSetJudgement(out, "GRID s1, held-out clips", sets.gridTest, all, &judged.recipe, corpus.faps, shapes);
  writeSetJudgement(out, "GRID, other speakers (never trained on)", sets.gridOthers, all, nullptr, corpus.faps, shapes);
  writePhoneClasses(out, "GRID s1, held-out clips (word alignments)", sets.gridTest, all, shapes);

  // Each StyleTalk speaker left out.
  PhoneClassShapes styleTalkTruth;
  for (const auto& [speaker, clips] : sets.styleTalkSpeakers) {
    const TalkingClips foldTraining = mouthTrainingClips(sets, speaker);
    const animation::MouthModel fold =
        trainRecipeLogged(foldTraining, corpus.faps, options.recipe, speechOnly.speech, log);
    const MouthJudged foldJudged(fold, options.recipe.synthesis, foldTraining, corpus.faps, compared);
    writeSetJudgement(out, "StyleTalk speaker left out: " + speaker, clips, foldJudged.all, &foldJudged.recipe,
                      corpus.faps, shapes);
    writePhoneClasses(out, "StyleTalk speaker left out: " + speaker + " (phones)", clips, foldJudged.all, shapes);
    addPhoneClassTruth(styleTalkTruth, clips);
  }

  std::vector<const MouthEstimator*> speechJudged = all;
  speechJudged.pop_back();  // the training mean says nothing of speech without video
  writeBeat2Jaw(out, speechJudged, animation::defineMouthFapMap(face::loadIctFace(face::ictFaceDirectory())));
  writeLanguages(out, options.languages, speechJudged, styleTalkTruth, shapes);
  writeChinDrop(out, speechJudged);
}

void trainMouthOnTalkingCorpora(const MouthCorpusTraining& training, std::ostream& log) {
  const std::filesystem::path& path = training.output;
  if (path.extension() != ".json") throw fileError(path, "a model is written as JSON: give a .json name");
  checkOutputTarget(path);
  const face::FaceModel face = face::FaceModel::buildDefault();
  const TalkingCorpus corpus = loadTrackedTalkingCorpus(
      training.folders.empty() ? sharedTalkingFolders() : training.folders, training.tracks, face, log);
  const GridSplit split = splitGrid(corpus);
  const TalkingClips clips = mouthModelTrainingClips(split);
  const SpeechOnlyRecordings speechOnly = speechOnlyRecordings();
  const animation::MouthModel model = trainRecipeLogged(clips, corpus.faps, training.recipe, speechOnly.speech, log);
  animation::saveMouthModel(path, model, training.recipe.model);
  double seconds = 0.0;
  for (const TalkingClip* clip : clips) seconds += clip->clip.recording.numFrames() / animation::kMouthFramesPerSecond;
  printTo(log, "mouth model: %s; trained on %zu clips (%.0f s of talking video%s)%s; wrote %s\n",
          describeMouthRecipe(training.recipe).c_str(), clips.size(), seconds,
          split.heldOut.empty() ? "" : ", GRID s1's every fifth clip kept for `eval mouth`",
          training.recipe.stageTwo
              ? (" and " + std::to_string(static_cast<int>(speechOnly.seconds)) + " s of speech-only voices").c_str()
              : "",
          path.c_str());
}

}  // namespace th::eval
