// `talkinghead train articulation`: the mouth network (animation/mouth_network.h) that the default mouth's
// visemes and closures come from (animation/articulation.h), trained on every shared corpus with a truth for
// it — GRID s1's training clips, StyleTalk and the Arabic news anchors (tracked lips, phones), BEAT2's
// phone-aligned takes, and a folder of synthesised phone-aligned voices if given — with the face's
// inner-lip opening gradient for the closures. How well it does on speakers it never heard:
// tools/diagnostics/mouth_network_experiment and docs/mouth.md.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "animation/mouth_network.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "eval/mouth_scores.h"
#include "eval/network_corpus.h"
#include "mouth_corpus_command.h"

namespace th::app {
namespace {

struct ArticulationArguments {
  std::string output = "models/articulation.json";
  std::string tracks;    // empty: defaultMouthTrackFolder()
  std::string festival;  // tools/festival_speech.py's folder; empty: none
  std::vector<std::string>
      aligned;             // tools/align_phones.py's folders of read speech (speechocean762's training speakers)
  std::string gridPhones;  // tools/align_phones.py --grid's folder: GRID's phones where the sound puts them
  int futureSubframes = animation::MouthNetworkOptions{}.futureSubframes;
  int epochs = 20;  // as measured in docs/mouth.md (the best epoch was the last or the one before in every fold)
  // Two hidden layers of 512: on speechocean762's unseen speakers 1 point more Oculus-15 accuracy and 4-6 more
  // /p b m/ recall at the same precision than 256 (docs/mouth.md), still far under a millisecond a frame.
  std::vector<int> hidden{512, 512};
  std::vector<std::string> leftOut;  // speakers not to train on (to show or score the network on voices it never heard)
};

void runTrain(const ArticulationArguments& arguments) {
  checkOutputTarget(arguments.output);
  const auto started = std::chrono::steady_clock::now();
  const face::FaceModel face = face::FaceModel::buildDefault();
  std::vector<eval::TalkingFolder> folders = eval::sharedTalkingFolders();
  folders.push_back({sharedDataPath("talking/arabic-news"), ""});
  eval::TalkingCorpus talking = loadMouthCorpus(folders, arguments.tracks, face);
  if (!arguments.gridPhones.empty()) {
    const int clips = eval::useAlignedPhones(talking, arguments.gridPhones);
    if (clips == 0) throw fileError(arguments.gridPhones, "holds no phones for GRID's clips (NAME.phones.csv)");
  }
  std::vector<eval::CorpusRecording> corpus = eval::networkRecordingsOf(talking);
  for (eval::CorpusRecording& r : eval::phoneAlignedSpeech()) corpus.push_back(std::move(r));
  if (!arguments.festival.empty())
    for (eval::CorpusRecording& r : eval::synthesisedSpeech(arguments.festival)) corpus.push_back(std::move(r));
  for (const std::string& folder : arguments.aligned)
    for (eval::CorpusRecording& r : eval::alignedSpeech(folder, "aligned")) corpus.push_back(std::move(r));
  eval::startAtSpeakerMeans(corpus);
  // The anchors' FAPs are each measured from their own 1.2 s clip's most closed frame, which blurs the jaw's
  // zero: they train the classes, the lips' shape and the closures (docs/mouth.md).
  for (eval::CorpusRecording& r : corpus)
    if (r.set == "talking/arabic-news") r.recording.faps.resize(0, 0);
  const std::vector<bool> heldOut = eval::gridHeldOut(corpus);
  std::vector<animation::NetworkRecording> training;
  std::set<std::string> speakersLeftOut;
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    const std::string& speaker = corpus[i].recording.speaker;
    if (std::find(arguments.leftOut.begin(), arguments.leftOut.end(), speaker) != arguments.leftOut.end())
      speakersLeftOut.insert(speaker);
    else if (!heldOut[i])
      training.push_back(corpus[i].recording);
  }
  for (const std::string& speaker : arguments.leftOut)
    if (!speakersLeftOut.count(speaker))
      throw std::runtime_error("--leave-out: no speaker '" + speaker + "' in the training corpora");

  animation::MouthNetworkOptions options;
  options.training.epochs = arguments.epochs;
  options.futureSubframes = arguments.futureSubframes;
  options.hidden = arguments.hidden;
  animation::MouthNetworkTraining trained = animation::trainMouthNetwork(training, talking.faps, options);
  trained.model.openingGradient = eval::openingGradient(eval::MouthShapes(face), talking.faps, eval::meanFaps(corpus));
  animation::saveMouthNetwork(arguments.output, trained.model);
  std::printf("wrote %s: %zu recordings, best epoch %d of %d, %.0f s\n", arguments.output.c_str(), training.size(),
              trained.report.bestEpoch, arguments.epochs,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
}

}  // namespace

void addTrainArticulationCommand(CLI::App& train) {
  auto arguments = std::make_shared<ArticulationArguments>();
  CLI::App* command = train.add_subcommand(
      "articulation",
      "Speech -> mouth classes and lip closures (the default mouth's visemes and closures) from every shared corpus");
  command->add_option("-o,--output", arguments->output, "Model file to write")->capture_default_str();
  command->add_option(
      "--tracks", arguments->tracks,
      "Folder of the clips' tracks, made on first use (default: " + std::string(kMouthTrackFolderHelp) + ")");
  command->add_option("--festival", arguments->festival,
                      "Folder of synthesised phone-aligned speech to train on too (tools/festival_speech.py)");
  command->add_option("--aligned", arguments->aligned,
                      "Folder of phone-aligned read speech to train on too (tools/align_phones.py; repeatable)");
  command->add_option("--grid-phones", arguments->gridPhones,
                      "Folder of GRID's phones aligned to the sound (tools/align_phones.py --grid), instead of "
                      "phones placed in each word by typical durations");
  command
      ->add_option("--future", arguments->futureSubframes,
                   "Look-ahead in 90 fps subframes (9: 100 ms; the live presets' files use 3 and 0)")
      ->check(CLI::Range(0, 45))
      ->capture_default_str();
  command->add_option("--epochs", arguments->epochs, "Training epochs")
      ->check(CLI::Range(1, 200))
      ->capture_default_str();
  command->add_option("--hidden", arguments->hidden, "Hidden layers' widths")
      ->check(CLI::Range(1, 4096))
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--leave-out", arguments->leftOut,
                      "Speaker not to train on (repeatable; BEAT2's is scott, StyleTalk's are their folder names)");
  command->callback([arguments] { runTrain(*arguments); });
}

}  // namespace th::app
