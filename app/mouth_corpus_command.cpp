// The default mouth models, trained and judged on tracked talking video of several speakers:
//   `talkinghead train mouth -o models/mouth.json`  the shared corpora's training clips -> a model file
//   `talkinghead eval mouth`                         the recipe on held-out GRID clips, on each StyleTalk speaker
//                                                    left out, on GRID's other speakers, on BEAT2's held-out
//                                                    quarter and on speech in other languages, beside the
//                                                    baselines and any other model files
// (engine/eval/talking_corpus.h, mouth_scores.h).
#include "mouth_corpus_command.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>

#include "animation/fap_mapping.h"
#include "animation/mouth_model.h"
#include "audio/media_audio.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/subprocess.h"
#include "eval/mouth_corpus.h"
#include "eval/mouth_scores.h"
#include "eval/talking_corpus.h"
#include "face/face_model.h"
#include "face/feature_points.h"
#include "pipeline/offline.h"

namespace th::app {
namespace {

using eval::PhoneClass;
using eval::TalkingClip;
using Clips = std::vector<const TalkingClip*>;

std::filesystem::path cacheFolder() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache != nullptr && *cache != '\0')
    return std::filesystem::path(cache) / "talkinghead";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "talkinghead";
  return std::filesystem::temp_directory_path() / "talkinghead-cache";
}

// GRID's held-out clips: every fifth of each of its folders, by name.
void splitGrid(const eval::TalkingCorpus& corpus, Clips& train, Clips& heldOut,
               std::map<std::string, Clips>& otherSpeakers) {
  std::map<std::filesystem::path, int> index;
  for (const TalkingClip& clip : corpus.clips) {
    if (clip.speaker != "grid-s1") {
      otherSpeakers[clip.speaker].push_back(&clip);
      continue;
    }
    const int i = index[clip.clip.video.parent_path()]++;
    (i % 5 == 4 ? heldOut : train).push_back(&clip);
  }
}

std::vector<animation::MouthRecording> recordingsOf(const Clips& clips, int otherSpeakerWeight = 1) {
  std::vector<animation::MouthRecording> recordings;
  for (const TalkingClip* clip : clips)
    for (int copy = 0; copy < (clip->speaker == "grid-s1" ? 1 : otherSpeakerWeight); ++copy)
      recordings.push_back(clip->clip.recording);
  return recordings;
}

// Speech without video for the audio side (stage 2): voices other than the videos', none of them judged here.
// BEAT2's speaker (his audio-only takes and the first three quarters of the take with motion; the last quarter
// is judged), CMU ARCTIC's prompt and FDA-UE's male and female speaker. GRID's other speakers (grid/samples)
// are kept out: they are judged.
std::vector<animation::SpeechFrames> speechOnlyRecordings(double* seconds) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(sharedDataPath("speech/fda-ue")))
    if (entry.path().extension() == ".wav") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  files.push_back(sharedDataPath("speech/arctic/arctic_a0001.wav"));
  files.push_back(sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"));
  files.push_back(sharedDataPath("beat2/audio_only/2_scott_0_4_4.wav"));
  std::vector<animation::SpeechFrames> speech;
  for (const auto& file : files) speech.push_back(animation::speechFramesOf(file));
  const animation::SpeechFrames take = animation::speechFramesOf(sharedDataPath("beat2/2_scott_0_1_1.wav"));
  speech.push_back(take.middleFrames(0, static_cast<Eigen::Index>(0.75 * take.numFrames())));
  *seconds = 0.0;
  for (const auto& s : speech) *seconds += s.numFrames() / animation::kMouthFramesPerSecond;
  return speech;
}

const char* covarianceName(hmm::CovarianceType type) {
  return type == hmm::CovarianceType::kFull ? "full" : "diagonal";
}

std::string describeRecipe(const MouthCorpusArguments& a) {
  std::ostringstream text;
  text << a.model.states << " states x " << a.model.mixtures << " Gaussians (" << covarianceName(a.model.covariance)
       << " covariance), MFCC context "
       << (a.model.futureContextFrames < 0 || a.model.futureContextFrames == a.model.contextFrames
               ? "+-" + std::to_string(a.model.contextFrames)
               : "-" + std::to_string(a.model.contextFrames) + "..+" + std::to_string(a.model.futureContextFrames))
       << ", " << a.model.visualComponents << " visual components"
       << (a.model.visualDeltas ? " with deltas (MLPG)" : "")
       << (a.model.normaliseSpeech ? ", normalised speech" : ", raw MFCCs")
       << (a.model.varianceValidationEvery > 0 ? ", variance compensation" : "")
       << (a.stageTwo ? ", stage 2 on speech-only voices" : "")
       << (a.otherSpeakerWeight > 1
               ? ", speakers other than GRID's weighing " + std::to_string(a.otherSpeakerWeight) + "x"
               : "");
  return text.str();
}

// The recipe: the mouth model on these clips (and, with stage 2, the speech-only recordings), driving the
// corpus's FAPs.
animation::MouthModel trainRecipe(const Clips& clips, const std::vector<int>& faps,
                                  const MouthCorpusArguments& arguments,
                                  const std::vector<animation::SpeechFrames>& speechOnly) {
  const auto started = std::chrono::steady_clock::now();
  animation::MouthModel model =
      animation::trainMouthModel(recordingsOf(clips, arguments.otherSpeakerWeight), arguments.model,
                                 arguments.stageTwo ? speechOnly : std::vector<animation::SpeechFrames>{});
  model.visualFaps = faps;
  std::fprintf(stderr, "trained on %zu clips in %.1f s (%d Baum-Welch iterations)\n", clips.size(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), model.iterations);
  return model;
}

// A model's FAP curves for speech, and the FAP numbers of their rows.
struct Estimator {
  std::string name;
  std::function<Eigen::MatrixXd(const animation::SpeechFrames&)> estimate;
  std::vector<int> faps;
};

Estimator modelEstimator(const std::string& name, const animation::MouthModel& model,
                         const animation::MouthSynthesisOptions& synthesis) {
  return {name,
          [&model, synthesis](const animation::SpeechFrames& speech) {
            return animation::mouthFapsOf(model, animation::synthesiseMouth(model, speech, synthesis));
          },
          animation::mouthFapNumbers(model)};
}

void printHeader(const std::string& title, const Clips& clips) {
  int frames = 0;
  for (const TalkingClip* clip : clips) frames += clip->clip.recording.numFrames();
  std::printf("\n%s (%zu clips, %d frames, %.0f s)\n  %-50s %6s %6s %6s  %6s %6s  %6s %6s\n", title.c_str(),
              clips.size(), frames, frames / animation::kMouthFramesPerSecond, "", "jaw ρ", "lip ρ", "wid ρ", "spr J",
              "spr L", "jaw ε", "FAPs ε");
}

void printScores(const std::string& name, const eval::MouthScores& s) {
  std::printf("  %-50s %6.3f %6.3f %6.3f  %6.2f %6.2f  %6.3f %6.3f\n", name.c_str(), s.jaw.rho, s.opening.rho,
              s.width.rho, s.jaw.spread, s.opening.spread, s.jaw.epsilon, s.fapsEpsilon);
}

// The clips' estimates: each clip's own speech, or (shift 1) the next clip's, cut or held to its length.
std::vector<Eigen::MatrixXd> estimatesFor(const Estimator& estimator, const Clips& clips, int shift = 0) {
  std::vector<Eigen::MatrixXd> out;
  const auto n = static_cast<int>(clips.size());
  for (int i = 0; i < n; ++i) {
    const TalkingClip* source = clips[static_cast<std::size_t>((i + shift) % n)];
    out.push_back(estimator.estimate(source->clip.recording.speech));
  }
  return out;
}

// The mean FAPs of the training clips, and the level baseline fitted on them.
struct Baselines {
  Estimator level;
  Estimator mean;
};

Baselines baselinesFor(const Clips& training, const std::vector<int>& faps) {
  std::vector<const animation::MouthRecording*> recordings;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(faps.size()));
  double frames = 0.0;
  for (const TalkingClip* clip : training) {
    recordings.push_back(&clip->clip.recording);
    mean += clip->clip.recording.visual.rowwise().sum();
    frames += clip->clip.recording.numFrames();
  }
  mean /= frames;
  auto level = std::make_shared<eval::LevelBaseline>(recordings, 2);
  return {
      {"baseline: the sound's level alone (linear, +-2 frames)",
       [level](const animation::SpeechFrames& speech) { return level->predict(speech); }, faps},
      {"baseline: the training mean",
       [mean](const animation::SpeechFrames& speech) { return Eigen::MatrixXd(mean.replicate(1, speech.numFrames())); },
       faps}};
}

// What a set is judged with: the recipe's model with and without its variance compensation, the other model
// files, and the baselines fitted on the model's training clips (in that order; the training mean last).
struct Judged {
  Estimator recipe;
  Estimator plain;
  Baselines baselines;
  std::vector<const Estimator*> all;
  Judged(const animation::MouthModel& model, const animation::MouthSynthesisOptions& synthesis, const Clips& training,
         const std::vector<int>& faps, const std::vector<Estimator>& compared)
      : recipe(modelEstimator("this recipe", model, synthesis)),
        plain(modelEstimator("this recipe, no variance compensation", model, withoutCompensation(synthesis))),
        baselines(baselinesFor(training, faps)) {
    all = {&recipe, &plain};
    for (const Estimator& e : compared) all.push_back(&e);
    all.push_back(&baselines.level);
    all.push_back(&baselines.mean);
  }
  Judged(const Judged&) = delete;
  Judged& operator=(const Judged&) = delete;

  static animation::MouthSynthesisOptions withoutCompensation(animation::MouthSynthesisOptions options) {
    options.varianceCompensation = false;
    return options;
  }
};

void printClassRow(const std::string& name, const eval::PhoneClassShapes& shapes) {
  std::printf("  %-50s %7.3f %7.3f %7.3f   %7.3f %7.3f\n", name.c_str(), shapes.mean(PhoneClass::kBilabial)[0],
              shapes.mean(PhoneClass::kOpenVowel)[0],
              shapes.mean(PhoneClass::kOpenVowel)[0] - shapes.mean(PhoneClass::kBilabial)[0],
              shapes.mean(PhoneClass::kRoundedVowel)[1], shapes.mean(PhoneClass::kSpreadVowel)[1]);
}

void reportPhoneClasses(const std::string& title, const Clips& clips, const std::vector<const Estimator*>& estimators,
                        const eval::MouthShapes& shapes) {
  eval::PhoneClassShapes truth;
  std::vector<eval::PhoneClassShapes> estimated(estimators.size());
  for (const TalkingClip* clip : clips) {
    if (clip->labels.empty()) continue;
    const std::vector<PhoneClass> classes = eval::labelClassesAt(
        clip->labels, clip->labelsAreWords, animation::kMouthFramesPerSecond, clip->clip.recording.numFrames());
    truth.add(classes, clip->clip.lipShape);
    for (std::size_t e = 0; e < estimators.size(); ++e)
      estimated[e].add(classes, shapes.of(estimators[e]->estimate(clip->clip.recording.speech), estimators[e]->faps));
  }
  std::printf(
      "\n%s: lip opening at bilabials (%d frames) and open vowels (%d), and their difference; mouth width at "
      "rounded (%d) and spread vowels (%d); shares of the eye corners' distance\n  %-50s %7s %7s %7s   %7s %7s\n",
      title.c_str(), truth.count(PhoneClass::kBilabial), truth.count(PhoneClass::kOpenVowel),
      truth.count(PhoneClass::kRoundedVowel), truth.count(PhoneClass::kSpreadVowel), "", "/p b m/", "open V", "diff",
      "rounded", "spread");
  printClassRow("truth (the tracked landmarks)", truth);
  for (std::size_t e = 0; e < estimators.size(); ++e) printClassRow(estimators[e]->name, estimated[e]);
}

// The truth's chin drop (FAP 3, 5th / 50th / 95th percentile) in mm on the reference face.
std::string chinDropOf(const Clips& clips, const std::vector<int>& faps) {
  const face::FaceAssets assets = face::loadIctFace(face::ictFaceDirectory());
  const double millimetres = 10.0 * face::measureFapUnits(assets.points, assets.neutral.positions).mns;
  const auto jaw = std::find(faps.begin(), faps.end(), 3) - faps.begin();
  std::vector<double> drop;
  for (const TalkingClip* clip : clips)
    for (Eigen::Index t = 0; t < clip->clip.recording.numFrames(); ++t)
      drop.push_back(std::max(0.0, clip->clip.recording.visual(jaw, t)) * millimetres);
  std::sort(drop.begin(), drop.end());
  const auto at = [&](double p) { return drop[static_cast<std::size_t>(p * static_cast<double>(drop.size() - 1))]; };
  char text[80];
  std::snprintf(text, sizeof text, "%.1f / %.1f / %.1f mm", at(0.05), at(0.5), at(0.95));
  return text;
}

void judge(const std::string& title, const Clips& clips, const std::vector<const Estimator*>& estimators,
           const Estimator* shuffled, const std::vector<int>& faps, const eval::MouthShapes& shapes) {
  printHeader(title, clips);
  std::printf("  the truth's chin drop (5th / 50th / 95th percentile): %s\n", chinDropOf(clips, faps).c_str());
  for (const Estimator* estimator : estimators)
    printScores(estimator->name,
                eval::scoreMouth(estimatesFor(*estimator, clips), estimator->faps, shapes, clips, faps));
  if (shuffled != nullptr && clips.size() > 1)
    printScores("baseline: " + shuffled->name + " on another clip's sound",
                eval::scoreMouth(estimatesFor(*shuffled, clips, 1), shuffled->faps, shapes, clips, faps));
}

// BEAT2's held-out quarter against its motion capture's jaw, through the jaw's geometry (fap_mapping.h): FAP 3
// of the true jaw opening against the estimates' FAP 3.
void judgeBeat2(const std::vector<const Estimator*>& estimators, const animation::MouthFapMap& map) {
  const animation::MouthRecording take = eval::loadBeat2Mouth();
  const auto boundary = static_cast<Eigen::Index>(std::lround(0.75 * take.numFrames()));
  const Eigen::Index count = take.numFrames() - boundary;
  const Eigen::RowVectorXd truth = animation::mouthFaps(map, take.visual.row(0).tail(count)).row(0);
  std::printf(
      "\nBEAT2's held-out quarter (%.1f s) against the motion capture's jaw (FAP 3 through the jaw's geometry; "
      "speech from the whole take, scored on the last quarter)\n  %-50s %6s %6s %6s\n",
      static_cast<double>(count) / animation::kMouthFramesPerSecond, "", "jaw ρ", "spr J", "jaw ε");
  for (const Estimator* estimator : estimators) {
    const Eigen::MatrixXd faps = estimator->estimate(take.speech);
    const auto jaw = std::find(estimator->faps.begin(), estimator->faps.end(), 3) - estimator->faps.begin();
    const eval::CurveScore score = eval::scoreCurve(faps.row(jaw).tail(count), truth);
    std::printf("  %-50s %6.3f %6.2f %6.3f\n", estimator->name.c_str(), score.rho, score.spread, score.epsilon);
  }
}

// Speech in other languages (tools/multilingual_speech.py: espeak-ng, every phone's time known): the lips'
// opening an estimate gives against the opening each phone class has on tracked speakers (StyleTalk's
// phone-labelled clips), and the gap between open vowels and /p b m/ in units of the estimate's spread.
void judgeLanguages(const std::filesystem::path& folder, const std::vector<const Estimator*>& estimators,
                    const eval::PhoneClassShapes& typical, const eval::MouthShapes& shapes) {
  std::ifstream index(folder / "index.csv");
  if (!index)
    throw fileError(folder / "index.csv", "cannot be read (make the folder with tools/multilingual_speech.py)");
  std::string line;
  std::getline(index, line);
  std::map<std::string, std::vector<std::string>> byLanguage;
  while (std::getline(index, line)) {
    const std::size_t comma = line.find(',');
    const std::size_t second = line.find(',', comma + 1);
    if (comma == std::string::npos || second == std::string::npos) continue;
    byLanguage[line.substr(comma + 1, second - comma - 1)].push_back(line.substr(0, comma));
  }
  std::printf(
      "\nOther languages (%s: espeak-ng, phone-aligned): per language, the correlation of the lip opening "
      "with each phone class's typical opening on tracked speakers, and (open vowels - /p b m/) / spread\n"
      "  %-8s",
      folder.c_str(), "");
  for (const Estimator* e : estimators) std::printf(" %24.24s", e->name.c_str());
  std::printf("\n");
  // Means over the languages other than English (en is there to compare with), and per estimator the languages
  // where its correlation beats the sound's level (the estimator so named, if judged).
  std::vector<std::pair<double, double>> sums(estimators.size(), {0.0, 0.0});
  std::vector<int> beatsLevel(estimators.size(), 0);
  const auto level = std::find_if(estimators.begin(), estimators.end(), [](const Estimator* e) {
    return e->name.rfind("baseline: the sound's level", 0) == 0;
  });
  const double others = static_cast<double>(byLanguage.size() - byLanguage.count("en"));
  for (const auto& [language, files] : byLanguage) {
    std::vector<double> rhos;
    std::printf("  %-8s", language.c_str());
    for (std::size_t e = 0; e < estimators.size(); ++e) {
      std::vector<double> opening, target;
      double open = 0.0, closed = 0.0;
      int openCount = 0, closedCount = 0;
      for (const std::string& file : files) {
        std::filesystem::path wav = folder / file;
        if (wav.extension() != ".wav") wav += ".wav";
        std::filesystem::path phonesFile = wav;
        phonesFile.replace_extension(".phones.csv");
        const animation::SpeechFrames speech = animation::speechFramesOf(wav);
        const Eigen::MatrixXd shape = shapes.of(estimators[e]->estimate(speech), estimators[e]->faps);
        std::ifstream phones(phonesFile);
        if (!phones) throw fileError(phonesFile, "cannot be read");
        std::string row;
        std::getline(phones, row);
        std::vector<eval::LabelInterval> labels;
        std::vector<PhoneClass> labelClasses;
        while (std::getline(phones, row)) {
          std::stringstream fields(row);
          std::string start, end, phone, kind;
          std::getline(fields, start, ',');
          std::getline(fields, end, ',');
          std::getline(fields, phone, ',');
          std::getline(fields, kind, ',');
          const std::map<std::string, PhoneClass> kinds{{"silence", PhoneClass::kSilence},
                                                        {"bilabial", PhoneClass::kBilabial},
                                                        {"labiodental", PhoneClass::kLabiodental},
                                                        {"open_vowel", PhoneClass::kOpenVowel},
                                                        {"rounded_vowel", PhoneClass::kRoundedVowel},
                                                        {"spread_vowel", PhoneClass::kSpreadVowel},
                                                        {"other_vowel", PhoneClass::kOtherVowel},
                                                        {"consonant", PhoneClass::kConsonant}};
          labels.push_back({std::stod(start), std::stod(end), phone});
          labelClasses.push_back(kinds.count(kind) ? kinds.at(kind) : PhoneClass::kConsonant);
        }
        std::size_t at = 0;
        for (Eigen::Index t = 0; t < shape.cols(); ++t) {
          const double seconds = static_cast<double>(t) / animation::kMouthFramesPerSecond;
          while (at + 1 < labels.size() && labels[at].endSeconds <= seconds) ++at;
          const PhoneClass c = labelClasses[at];
          opening.push_back(shape(0, t));
          target.push_back(typical.mean(c)[0]);
          if (c == PhoneClass::kOpenVowel) open += shape(0, t), ++openCount;
          if (c == PhoneClass::kBilabial) closed += shape(0, t), ++closedCount;
        }
      }
      const Eigen::Map<const Eigen::RowVectorXd> o(opening.data(), static_cast<Eigen::Index>(opening.size()));
      const Eigen::Map<const Eigen::RowVectorXd> g(target.data(), static_cast<Eigen::Index>(target.size()));
      const eval::CurveScore score = eval::scoreCurve(o, g);
      const double spread = std::sqrt((o.array() - o.mean()).square().mean());
      const double gap = (open / std::max(openCount, 1) - closed / std::max(closedCount, 1)) / std::max(spread, 1e-12);
      rhos.push_back(score.rho);
      if (language != "en") {
        sums[e].first += score.rho / others;
        sums[e].second += gap / others;
      }
      std::printf("       ρ %6.3f  gap %5.2f", score.rho, gap);
    }
    std::printf("\n");
    if (language != "en" && level != estimators.end())
      for (std::size_t e = 0; e < estimators.size(); ++e)
        beatsLevel[e] += rhos[e] > rhos[static_cast<std::size_t>(level - estimators.begin())] ? 1 : 0;
  }
  std::printf("  %-8s", "mean");
  for (const auto& [rho, gap] : sums) std::printf("       ρ %6.3f  gap %5.2f", rho, gap);
  std::printf("   (the %.0f languages other than English)\n", others);
  if (level != estimators.end()) {
    std::printf("  %-8s", "> level");
    for (const int wins : beatsLevel) std::printf(" %15d of %.0f    ", wins, others);
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
void reportChinDrop(const std::vector<const Estimator*>& estimators) {
  const face::FaceAssets assets = face::loadIctFace(face::ictFaceDirectory());
  const double mnsMillimetres = 10.0 * face::measureFapUnits(assets.points, assets.neutral.positions).mns * 1024.0;
  const animation::SpeechFrames speech = animation::speechFramesOf(sharedDataPath("beat2/2_scott_0_1_1.wav"));
  std::printf(
      "\nThe demo's speech (BEAT2, 64 s): the chin's drop (FAP 3 on the reference face, MNS0 = %.1f mm), "
      "5th / 50th / 95th percentile in mm\n",
      mnsMillimetres);
  for (const Estimator* estimator : estimators) {
    const Eigen::MatrixXd faps = estimator->estimate(speech);
    const auto jaw = std::find(estimator->faps.begin(), estimator->faps.end(), 3) - estimator->faps.begin();
    std::vector<double> drop;
    for (Eigen::Index t = 0; t < faps.cols(); ++t)
      drop.push_back(std::max(0.0, faps(jaw, t)) * mnsMillimetres / 1024.0);
    std::sort(drop.begin(), drop.end());
    const auto at = [&](double p) { return drop[static_cast<std::size_t>(p * static_cast<double>(drop.size() - 1))]; };
    std::printf("  %-50s %5.1f / %5.1f / %5.1f\n", estimator->name.c_str(), at(0.05), at(0.5), at(0.95));
  }
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

  std::printf("Mouth from audio, the recipe: %s\n", describeRecipe(arguments).c_str());
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
  {
    // The lips' natural lead over the sound, on GRID (whose word alignments, from the sound, put the lips'
    // closure where /b p/ words start): the same measure on each 3 s clip, the median over all.
    std::vector<double> leads;
    const int jawRow = static_cast<int>(std::find(corpus.faps.begin(), corpus.faps.end(), 3) - corpus.faps.begin());
    for (const TalkingClip& clip : corpus.clips)
      if (clip.speaker == "grid-s1")
        leads.push_back(1000.0 * tracking::estimateSoundOffset(
                                     clip.clip.recording.speech.levelDb, clip.clip.recording.visual.row(jawRow),
                                     clip.clip.lipShape.row(0), animation::kMouthFramesPerSecond,
                                     {.naturalLeadSeconds = 0.0, .minSeconds = 0.0})
                                     .lateSeconds);
    std::sort(leads.begin(), leads.end());
    std::printf(
        "  GRID s1 (in sync): the mouth leads the sound by %.0f ms (median over %zu clips; the lead taken as "
        "natural: %.0f ms)\n",
        leads[leads.size() / 2], leads.size(), 1000.0 * tracking::SoundSyncOptions{}.naturalLeadSeconds);
  }

  Clips gridTrain, gridTest;
  std::map<std::string, Clips> otherSpeakers;
  splitGrid(corpus, gridTrain, gridTest, otherSpeakers);
  Clips styleTalk, gridOthers;
  std::map<std::string, Clips> styleTalkSpeakers;
  for (const auto& [speaker, clips] : otherSpeakers) {
    const bool isGrid = clips.front()->clip.video.parent_path().filename() == "samples";
    for (const TalkingClip* clip : clips) {
      // bbaf2n in GRID's samples is speaker s1 himself: not another speaker.
      if (isGrid && clip->clip.video.stem() == "bbaf2n") continue;
      (isGrid ? gridOthers : styleTalk).push_back(clip);
      if (!isGrid) styleTalkSpeakers[speaker].push_back(clip);
    }
  }
  double speechSeconds = 0.0;
  const std::vector<animation::SpeechFrames> speechOnly = speechOnlyRecordings(&speechSeconds);
  if (arguments.stageTwo) std::printf("\nStage 2 speech: %.0f s of speech-only recordings\n", speechSeconds);

  std::vector<Estimator> compared;
  for (const auto& [name, model] : others) compared.push_back(modelEstimator(name, model, arguments.synthesis));

  // The recipe trained on GRID's training clips and every StyleTalk speaker: judged on GRID's held-out clips, its
  // other speakers, BEAT2, other languages and the demo.
  Clips training = gridTrain;
  training.insert(training.end(), styleTalk.begin(), styleTalk.end());
  const animation::MouthModel model = trainRecipe(training, corpus.faps, arguments, speechOnly);
  const Judged judged(model, arguments.synthesis, training, corpus.faps, compared);
  const Estimator& recipe = judged.recipe;
  const std::vector<const Estimator*>& all = judged.all;
  std::printf("\nTrained on GRID s1's training clips and all StyleTalk speakers (%zu clips); variance scale:",
              training.size());
  for (Eigen::Index k = 0; k < model.varianceScale.size(); ++k) std::printf(" %.2f", model.varianceScale[k]);
  std::printf("\n");
  judge("GRID s1, held-out clips", gridTest, all, &recipe, corpus.faps, shapes);
  judge("GRID, other speakers (never trained on)", gridOthers, all, nullptr, corpus.faps, shapes);
  reportPhoneClasses("GRID s1, held-out clips (word alignments)", gridTest, all, shapes);

  // Each StyleTalk speaker left out.
  eval::PhoneClassShapes styleTalkTruth;
  for (const auto& [speaker, clips] : styleTalkSpeakers) {
    Clips foldTraining = gridTrain;
    for (const TalkingClip* clip : styleTalk)
      if (clip->speaker != speaker) foldTraining.push_back(clip);
    const animation::MouthModel fold = trainRecipe(foldTraining, corpus.faps, arguments, speechOnly);
    const Judged foldJudged(fold, arguments.synthesis, foldTraining, corpus.faps, compared);
    judge("StyleTalk speaker left out: " + speaker, clips, foldJudged.all, &foldJudged.recipe, corpus.faps, shapes);
    reportPhoneClasses("StyleTalk speaker left out: " + speaker + " (phones)", clips, foldJudged.all, shapes);
    for (const TalkingClip* clip : clips)
      styleTalkTruth.add(eval::labelClassesAt(clip->labels, clip->labelsAreWords, animation::kMouthFramesPerSecond,
                                              clip->clip.recording.numFrames()),
                         clip->clip.lipShape);
  }

  std::vector<const Estimator*> speechJudged = all;
  speechJudged.pop_back();  // the training mean says nothing of speech without video
  judgeBeat2(speechJudged, animation::defineMouthFapMap(face::loadIctFace(face::ictFaceDirectory())));
  judgeLanguages(languages, speechJudged, styleTalkTruth, shapes);
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
  Clips gridTrain, gridTest;
  std::map<std::string, Clips> otherSpeakers;
  splitGrid(corpus, gridTrain, gridTest, otherSpeakers);
  Clips training = gridTrain;
  for (const auto& [speaker, clips] : otherSpeakers) training.insert(training.end(), clips.begin(), clips.end());
  double speechSeconds = 0.0;
  const std::vector<animation::SpeechFrames> speechOnly = speechOnlyRecordings(&speechSeconds);
  const animation::MouthModel model = trainRecipe(training, corpus.faps, arguments, speechOnly);
  animation::saveMouthModel(path, model, arguments.model);
  double seconds = 0.0;
  for (const TalkingClip* clip : training)
    seconds += clip->clip.recording.numFrames() / animation::kMouthFramesPerSecond;
  std::fprintf(stderr, "mouth model: %s; trained on %zu clips (%.0f s of talking video%s)%s; wrote %s\n",
               describeRecipe(arguments).c_str(), training.size(), seconds,
               gridTest.empty() ? "" : ", GRID s1's every fifth clip kept for `eval mouth`",
               arguments.stageTwo
                   ? (" and " + std::to_string(static_cast<int>(speechSeconds)) + " s of speech-only voices").c_str()
                   : "",
               path.c_str());
}

}  // namespace th::app
