#include "eval/mouth_protocol.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

#include "core/data_path.h"
#include "core/error.h"
#include "eval/mouth_corpus.h"
#include "face/feature_points.h"
#include "tracking/video_training.h"

namespace th::eval {
namespace {

const char* covarianceName(hmm::CovarianceType type) {
  return type == hmm::CovarianceType::kFull ? "full" : "diagonal";
}

animation::MouthSynthesisOptions withoutCompensation(animation::MouthSynthesisOptions options) {
  options.varianceCompensation = false;
  return options;
}

std::ptrdiff_t jawRowOf(const std::vector<int>& faps) {
  return std::find(faps.begin(), faps.end(), 3) - faps.begin();
}

}  // namespace

std::string describeMouthRecipe(const MouthRecipe& a) {
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

GridSplit splitGrid(const TalkingCorpus& corpus) {
  GridSplit split;
  std::map<std::filesystem::path, int> index;
  for (const TalkingClip& clip : corpus.clips) {
    if (clip.speaker != kGridSpeaker) {
      split.otherSpeakers[clip.speaker].push_back(&clip);
      continue;
    }
    const int i = index[clip.clip.video.parent_path()]++;
    (i % 5 == 4 ? split.heldOut : split.train).push_back(&clip);
  }
  return split;
}

MouthEvaluationSets mouthEvaluationSets(const TalkingCorpus& corpus) {
  GridSplit split = splitGrid(corpus);
  MouthEvaluationSets sets;
  sets.gridTrain = std::move(split.train);
  sets.gridTest = std::move(split.heldOut);
  for (const auto& [speaker, clips] : split.otherSpeakers) {
    const bool isGrid = clips.front()->clip.video.parent_path().filename() == "samples";
    for (const TalkingClip* clip : clips) {
      // bbaf2n in GRID's samples is speaker s1 himself: not another speaker.
      if (isGrid && clip->clip.video.stem() == "bbaf2n") continue;
      (isGrid ? sets.gridOthers : sets.styleTalk).push_back(clip);
      if (!isGrid) sets.styleTalkSpeakers[speaker].push_back(clip);
    }
  }
  return sets;
}

TalkingClips mouthTrainingClips(const MouthEvaluationSets& sets, const std::string& leftOut) {
  TalkingClips training = sets.gridTrain;
  for (const TalkingClip* clip : sets.styleTalk)
    if (clip->speaker != leftOut) training.push_back(clip);
  return training;
}

TalkingClips mouthModelTrainingClips(const GridSplit& split) {
  TalkingClips training = split.train;
  for (const auto& [speaker, clips] : split.otherSpeakers) training.insert(training.end(), clips.begin(), clips.end());
  return training;
}

std::vector<animation::MouthRecording> mouthRecordingsOf(const TalkingClips& clips, int otherSpeakerWeight) {
  std::vector<animation::MouthRecording> recordings;
  for (const TalkingClip* clip : clips)
    for (int copy = 0; copy < (clip->speaker == kGridSpeaker ? 1 : otherSpeakerWeight); ++copy)
      recordings.push_back(clip->clip.recording);
  return recordings;
}

// BEAT2's speaker (his audio-only takes and the first three quarters of the take with motion; the last quarter
// is judged), CMU ARCTIC's prompt and FDA-UE's male and female speaker. GRID's other speakers (grid/samples)
// are kept out: they are judged.
SpeechOnlyRecordings speechOnlyRecordings() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(sharedDataPath("speech/fda-ue")))
    if (entry.path().extension() == ".wav") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  files.push_back(sharedDataPath("speech/arctic/arctic_a0001.wav"));
  files.push_back(sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"));
  files.push_back(sharedDataPath("beat2/audio_only/2_scott_0_4_4.wav"));
  SpeechOnlyRecordings out;
  for (const auto& file : files) out.speech.push_back(animation::speechFramesOf(file));
  const animation::SpeechFrames take = animation::speechFramesOf(sharedDataPath("beat2/2_scott_0_1_1.wav"));
  out.speech.push_back(take.middleFrames(0, static_cast<Eigen::Index>(0.75 * take.numFrames())));
  for (const auto& s : out.speech) out.seconds += s.numFrames() / animation::kMouthFramesPerSecond;
  return out;
}

TrainedMouthRecipe trainMouthRecipe(const TalkingClips& clips, const std::vector<int>& faps, const MouthRecipe& recipe,
                                    const std::vector<animation::SpeechFrames>& speechOnly) {
  const auto started = std::chrono::steady_clock::now();
  TrainedMouthRecipe trained{
      animation::trainMouthModel(mouthRecordingsOf(clips, recipe.otherSpeakerWeight), recipe.model,
                                 recipe.stageTwo ? speechOnly : std::vector<animation::SpeechFrames>{}),
      0.0};
  trained.model.visualFaps = faps;
  trained.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return trained;
}

MouthEstimator modelEstimator(const std::string& name, const animation::MouthModel& model,
                              const animation::MouthSynthesisOptions& synthesis) {
  return {name,
          [&model, synthesis](const animation::SpeechFrames& speech) {
            return animation::mouthFapsOf(model, animation::synthesiseMouth(model, speech, synthesis));
          },
          animation::mouthFapNumbers(model)};
}

std::vector<Eigen::MatrixXd> estimatesFor(const MouthEstimator& estimator, const TalkingClips& clips, int shift) {
  std::vector<Eigen::MatrixXd> out;
  const auto n = static_cast<int>(clips.size());
  for (int i = 0; i < n; ++i) {
    const TalkingClip* source = clips[static_cast<std::size_t>((i + shift) % n)];
    out.push_back(estimator.estimate(source->clip.recording.speech));
  }
  return out;
}

MouthBaselines mouthBaselinesFor(const TalkingClips& training, const std::vector<int>& faps) {
  std::vector<const animation::MouthRecording*> recordings;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(faps.size()));
  double frames = 0.0;
  for (const TalkingClip* clip : training) {
    recordings.push_back(&clip->clip.recording);
    mean += clip->clip.recording.visual.rowwise().sum();
    frames += clip->clip.recording.numFrames();
  }
  mean /= frames;
  auto level = std::make_shared<LevelBaseline>(recordings, 2);
  return {
      {kLevelBaselineName, [level](const animation::SpeechFrames& speech) { return level->predict(speech); }, faps},
      {"baseline: the training mean",
       [mean](const animation::SpeechFrames& speech) { return Eigen::MatrixXd(mean.replicate(1, speech.numFrames())); },
       faps}};
}

MouthJudged::MouthJudged(const animation::MouthModel& model, const animation::MouthSynthesisOptions& synthesis,
                         const TalkingClips& training, const std::vector<int>& faps,
                         const std::vector<MouthEstimator>& compared)
    : recipe(modelEstimator("this recipe", model, synthesis)),
      plain(modelEstimator("this recipe, no variance compensation", model, withoutCompensation(synthesis))),
      baselines(mouthBaselinesFor(training, faps)) {
  all = {&recipe, &plain};
  for (const MouthEstimator& e : compared) all.push_back(&e);
  all.push_back(&baselines.level);
  all.push_back(&baselines.mean);
}

std::array<double, 3> chinDropPercentiles(std::vector<double> drop) {
  if (drop.empty()) return {0.0, 0.0, 0.0};
  std::sort(drop.begin(), drop.end());
  const auto at = [&](double p) { return drop[static_cast<std::size_t>(p * static_cast<double>(drop.size() - 1))]; };
  return {at(0.05), at(0.5), at(0.95)};
}

std::array<double, 3> truthChinDrop(const TalkingClips& clips, const std::vector<int>& faps,
                                    double millimetresPerUnit) {
  const auto jaw = jawRowOf(faps);
  std::vector<double> drop;
  for (const TalkingClip* clip : clips)
    for (Eigen::Index t = 0; t < clip->clip.recording.numFrames(); ++t)
      drop.push_back(std::max(0.0, clip->clip.recording.visual(jaw, t)) * millimetresPerUnit);
  return chinDropPercentiles(std::move(drop));
}

double referenceJawMillimetresPerUnit() {
  const face::FaceAssets assets = face::loadIctFace(face::ictFaceDirectory());
  return 10.0 * face::measureFapUnits(assets.points, assets.neutral.positions).mns;  // the mesh is in cm
}

MouthSetJudgement judgeMouthSet(const TalkingClips& clips, const std::vector<const MouthEstimator*>& estimators,
                                const MouthEstimator* shuffled, const std::vector<int>& faps, const MouthShapes& shapes,
                                double millimetresPerUnit) {
  MouthSetJudgement set;
  set.clips = clips.size();
  for (const TalkingClip* clip : clips) set.frames += clip->clip.recording.numFrames();
  set.truthChinDrop = truthChinDrop(clips, faps, millimetresPerUnit);
  for (const MouthEstimator* estimator : estimators)
    set.rows.emplace_back(estimator->name,
                          scoreMouth(estimatesFor(*estimator, clips), estimator->faps, shapes, clips, faps));
  // The recipe on another clip's sound: what is left of its scores when the speech is not the clip's.
  if (shuffled != nullptr && clips.size() > 1)
    set.rows.emplace_back("baseline: " + shuffled->name + " on another clip's sound",
                          scoreMouth(estimatesFor(*shuffled, clips, 1), shuffled->faps, shapes, clips, faps));
  return set;
}

PhoneClassJudgement judgePhoneClasses(const TalkingClips& clips, const std::vector<const MouthEstimator*>& estimators,
                                      const MouthShapes& shapes) {
  PhoneClassJudgement judgement;
  for (const MouthEstimator* estimator : estimators)
    judgement.estimated.emplace_back(estimator->name, PhoneClassShapes{});
  for (const TalkingClip* clip : clips) {
    if (clip->labels.empty()) continue;
    const std::vector<PhoneClass> classes = labelClassesAt(
        clip->labels, clip->labelsAreWords, animation::kMouthFramesPerSecond, clip->clip.recording.numFrames());
    judgement.truth.add(classes, clip->clip.lipShape);
    for (std::size_t e = 0; e < estimators.size(); ++e)
      judgement.estimated[e].second.add(
          classes, shapes.of(estimators[e]->estimate(clip->clip.recording.speech), estimators[e]->faps));
  }
  return judgement;
}

void addPhoneClassTruth(PhoneClassShapes& truth, const TalkingClips& clips) {
  for (const TalkingClip* clip : clips)
    truth.add(labelClassesAt(clip->labels, clip->labelsAreWords, animation::kMouthFramesPerSecond,
                             clip->clip.recording.numFrames()),
              clip->clip.lipShape);
}

Beat2JawJudgement judgeBeat2Jaw(const std::vector<const MouthEstimator*>& estimators,
                                const animation::MouthFapMap& map) {
  const animation::MouthRecording take = loadBeat2Mouth();
  const auto boundary = static_cast<Eigen::Index>(std::lround(0.75 * take.numFrames()));
  const Eigen::Index count = take.numFrames() - boundary;
  const Eigen::RowVectorXd truth = animation::mouthFaps(map, take.visual.row(0).tail(count)).row(0);
  Beat2JawJudgement judgement;
  judgement.seconds = static_cast<double>(count) / animation::kMouthFramesPerSecond;
  for (const MouthEstimator* estimator : estimators) {
    const Eigen::MatrixXd faps = estimator->estimate(take.speech);
    judgement.rows.emplace_back(estimator->name, scoreCurve(faps.row(jawRowOf(estimator->faps)).tail(count), truth));
  }
  return judgement;
}

std::map<std::string, std::vector<std::string>> readMultilingualIndex(const std::filesystem::path& folder) {
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
  return byLanguage;
}

std::vector<std::pair<LabelInterval, PhoneClass>> readClassedPhones(const std::filesystem::path& phonesFile) {
  std::ifstream phones(phonesFile);
  if (!phones) throw fileError(phonesFile, "cannot be read");
  const std::map<std::string, PhoneClass> kinds{{"silence", PhoneClass::kSilence},
                                                {"bilabial", PhoneClass::kBilabial},
                                                {"labiodental", PhoneClass::kLabiodental},
                                                {"open_vowel", PhoneClass::kOpenVowel},
                                                {"rounded_vowel", PhoneClass::kRoundedVowel},
                                                {"spread_vowel", PhoneClass::kSpreadVowel},
                                                {"other_vowel", PhoneClass::kOtherVowel},
                                                {"consonant", PhoneClass::kConsonant}};
  std::vector<std::pair<LabelInterval, PhoneClass>> out;
  std::string row;
  std::getline(phones, row);
  while (std::getline(phones, row)) {
    std::stringstream fields(row);
    std::string start, end, phone, kind;
    std::getline(fields, start, ',');
    std::getline(fields, end, ',');
    std::getline(fields, phone, ',');
    std::getline(fields, kind, ',');
    out.push_back(
        {{std::stod(start), std::stod(end), phone}, kinds.count(kind) ? kinds.at(kind) : PhoneClass::kConsonant});
  }
  return out;
}

LanguageJudgement judgeLanguages(const std::filesystem::path& folder,
                                 const std::vector<const MouthEstimator*>& estimators, const PhoneClassShapes& typical,
                                 const MouthShapes& shapes) {
  const std::map<std::string, std::vector<std::string>> byLanguage = readMultilingualIndex(folder);
  LanguageJudgement judgement;
  // Means over the languages other than English (en is there to compare with), and per estimator the languages
  // where its correlation beats the sound's level (the estimator so named, if judged).
  judgement.meanOverOthers.assign(estimators.size(), {});
  std::vector<int> beatsLevel(estimators.size(), 0);
  const auto level = std::find_if(estimators.begin(), estimators.end(), [](const MouthEstimator* e) {
    return e->name.rfind("baseline: the sound's level", 0) == 0;
  });
  judgement.others = static_cast<double>(byLanguage.size() - byLanguage.count("en"));
  const double others = judgement.others;
  for (const auto& [language, files] : byLanguage) {
    std::vector<LanguageScore> scores;
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
        const std::vector<std::pair<LabelInterval, PhoneClass>> phones = readClassedPhones(phonesFile);
        if (phones.empty()) throw fileError(phonesFile, "has no phones");
        std::size_t at = 0;
        for (Eigen::Index t = 0; t < shape.cols(); ++t) {
          const double seconds = static_cast<double>(t) / animation::kMouthFramesPerSecond;
          while (at + 1 < phones.size() && phones[at].first.endSeconds <= seconds) ++at;
          const PhoneClass c = phones[at].second;
          opening.push_back(shape(0, t));
          target.push_back(typical.mean(c)[0]);
          if (c == PhoneClass::kOpenVowel) open += shape(0, t), ++openCount;
          if (c == PhoneClass::kBilabial) closed += shape(0, t), ++closedCount;
        }
      }
      const Eigen::Map<const Eigen::RowVectorXd> o(opening.data(), static_cast<Eigen::Index>(opening.size()));
      const Eigen::Map<const Eigen::RowVectorXd> g(target.data(), static_cast<Eigen::Index>(target.size()));
      const CurveScore score = scoreCurve(o, g);
      // Not Eigen's mean(): GCC warns on it for a vector it cannot prove non-empty.
      const double mean = opening.empty() ? 0.0 : o.sum() / static_cast<double>(opening.size());
      const double spread =
          opening.empty() ? 0.0 : std::sqrt((o.array() - mean).square().sum() / static_cast<double>(opening.size()));
      const double gap = (open / std::max(openCount, 1) - closed / std::max(closedCount, 1)) / std::max(spread, 1e-12);
      scores.push_back({score.rho, gap});
      if (language != "en") {
        judgement.meanOverOthers[e].rho += score.rho / others;
        judgement.meanOverOthers[e].gap += gap / others;
      }
    }
    if (language != "en" && level != estimators.end())
      for (std::size_t e = 0; e < estimators.size(); ++e)
        beatsLevel[e] += scores[e].rho > scores[static_cast<std::size_t>(level - estimators.begin())].rho ? 1 : 0;
    judgement.languages.emplace_back(language, std::move(scores));
  }
  if (level != estimators.end()) judgement.beatsLevel = std::move(beatsLevel);
  return judgement;
}

std::vector<std::pair<std::string, std::array<double, 3>>> demoChinDrops(
    const std::vector<const MouthEstimator*>& estimators, double millimetresPerUnit) {
  const animation::SpeechFrames speech = animation::speechFramesOf(sharedDataPath("beat2/2_scott_0_1_1.wav"));
  std::vector<std::pair<std::string, std::array<double, 3>>> out;
  for (const MouthEstimator* estimator : estimators) {
    const Eigen::MatrixXd faps = estimator->estimate(speech);
    const auto jaw = jawRowOf(estimator->faps);
    std::vector<double> drop;
    for (Eigen::Index t = 0; t < faps.cols(); ++t) drop.push_back(std::max(0.0, faps(jaw, t)) * millimetresPerUnit);
    out.emplace_back(estimator->name, chinDropPercentiles(std::move(drop)));
  }
  return out;
}

LipLead gridLipLead(const TalkingCorpus& corpus) {
  std::vector<double> leads;
  const auto jawRow = static_cast<Eigen::Index>(jawRowOf(corpus.faps));
  for (const TalkingClip& clip : corpus.clips)
    if (clip.speaker == kGridSpeaker)
      leads.push_back(1000.0 * tracking::estimateSoundOffset(
                                   clip.clip.recording.speech.levelDb, clip.clip.recording.visual.row(jawRow),
                                   clip.clip.lipShape.row(0), animation::kMouthFramesPerSecond,
                                   {.naturalLeadSeconds = 0.0, .minSeconds = 0.0})
                                   .lateSeconds);
  if (leads.empty()) return {};
  std::sort(leads.begin(), leads.end());
  return {leads[leads.size() / 2], leads.size()};
}

}  // namespace th::eval
