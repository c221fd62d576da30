#include "eval/articulation_training.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/print_to.h"
#include "eval/mouth_corpus_report.h"
#include "eval/mouth_scores.h"
#include "eval/network_corpus.h"

namespace th::eval {
namespace {

// Every recording with a truth for the network: the tracked talking corpora (GRID's phones aligned to the sound
// if given), the phone-aligned speech and the folders given, each speaker's features started at its mean.
std::vector<CorpusRecording> articulationCorpus(const ArticulationTraining& training, TalkingCorpus& talking) {
  if (!training.gridPhones.empty()) {
    const int clips = useAlignedPhones(talking, training.gridPhones);
    if (clips == 0) throw fileError(training.gridPhones, "holds no phones for GRID's clips (NAME.phones.csv)");
  }
  std::vector<CorpusRecording> corpus = networkRecordingsOf(talking);
  for (CorpusRecording& r : phoneAlignedSpeech()) corpus.push_back(std::move(r));
  if (!training.festival.empty())
    for (CorpusRecording& r : synthesisedSpeech(training.festival)) corpus.push_back(std::move(r));
  for (const std::string& folder : training.aligned)
    for (CorpusRecording& r : alignedSpeech(folder, "aligned")) corpus.push_back(std::move(r));
  startAtSpeakerMeans(corpus);
  // The anchors' FAPs are each measured from their own 1.2 s clip's most closed frame, which blurs the jaw's
  // zero: they train the classes, the lips' shape and the closures (docs/mouth.md).
  for (CorpusRecording& r : corpus)
    if (r.set == "talking/arabic-news") r.recording.faps.resize(0, 0);
  return corpus;
}

// The recordings trained on: GRID's held-out clips and the speakers left out are not.
std::vector<animation::NetworkRecording> articulationTrainingSet(const std::vector<CorpusRecording>& corpus,
                                                                 const std::vector<std::string>& leftOut) {
  const std::vector<bool> heldOut = gridHeldOut(corpus);
  std::vector<animation::NetworkRecording> training;
  std::set<std::string> speakersLeftOut;
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    const std::string& speaker = corpus[i].recording.speaker;
    if (std::find(leftOut.begin(), leftOut.end(), speaker) != leftOut.end())
      speakersLeftOut.insert(speaker);
    else if (!heldOut[i])
      training.push_back(corpus[i].recording);
  }
  for (const std::string& speaker : leftOut)
    if (!speakersLeftOut.count(speaker))
      throw std::runtime_error("--leave-out: no speaker '" + speaker + "' in the training corpora");
  return training;
}

}  // namespace

void trainArticulation(const ArticulationTraining& training, std::ostream& out, std::ostream& log) {
  checkOutputTarget(training.output);
  const auto started = std::chrono::steady_clock::now();
  const face::FaceModel face = face::FaceModel::buildDefault();
  std::vector<TalkingFolder> folders = sharedTalkingFolders();
  folders.push_back({sharedDataPath("talking/arabic-news"), ""});
  TalkingCorpus talking = loadTrackedTalkingCorpus(folders, training.tracks, face, log);
  const std::vector<CorpusRecording> corpus = articulationCorpus(training, talking);
  const std::vector<animation::NetworkRecording> recordings = articulationTrainingSet(corpus, training.leftOut);

  animation::MouthNetworkOptions options;
  options.training.epochs = training.epochs;
  options.futureSubframes = training.futureSubframes;
  options.hidden = training.hidden;
  animation::MouthNetworkTraining trained = animation::trainMouthNetwork(recordings, talking.faps, options);
  trained.model.openingGradient = openingGradient(MouthShapes(face), talking.faps, meanFaps(corpus));
  animation::saveMouthNetwork(training.output, trained.model);
  printTo(out, "wrote %s: %zu recordings, best epoch %d of %d, %.0f s\n", training.output.c_str(), recordings.size(),
          trained.report.bestEpoch, training.epochs,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

}  // namespace th::eval
