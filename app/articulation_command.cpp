// `talkinghead train articulation`: its options; the training is eval/articulation_training.h's.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "eval/articulation_training.h"
#include "eval/mouth_corpus_report.h"

namespace th::app {

void addTrainArticulationCommand(CLI::App& train) {
  auto arguments = std::make_shared<eval::ArticulationTraining>();
  CLI::App* command = train.add_subcommand(
      "articulation",
      "Speech -> mouth classes and lip closures (the default mouth's visemes and closures) from every shared corpus");
  command->add_option("-o,--output", arguments->output, "Model file to write")->capture_default_str();
  command->add_option(
      "--tracks", arguments->tracks,
      "Folder of the clips' tracks, made on first use (default: " + std::string(eval::kMouthTrackFolderHelp) + ")");
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
  command->callback([arguments] { eval::trainArticulation(*arguments, std::cout, std::cerr); });
}

}  // namespace th::app
