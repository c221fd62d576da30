// `talkinghead train --video DIR -o MODEL.json`: a mouth model of one's own speaker from talking videos. Every
// clip is tracked and fitted (tracks kept for the next run), the jaw and lip FAPs become the visual part of
// the audio-visual HMM, and the model is checked on held-out clips against baselines and another model
// (engine/tracking/video_training.h).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "animation/mouth_model.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/own_mouth_training.h"
#include "pipeline/animation_models.h"
#include "tracking/video_folder.h"
#include "tracking/video_training.h"

namespace th::app {
namespace {

struct TrainVideoArguments {
  eval::OwnMouthTraining training;  // its output, folder and tracks are set from the three below
  std::string folder;
  std::string output;
  std::string tracks;  // empty: beside the output, "<stem>_tracks"
  unsigned threads = 0;
  std::string compare;  // empty: the shipped models/mouth.json
};

void runTrainVideo(const TrainVideoArguments& arguments) {
  eval::OwnMouthTraining training = arguments.training;
  training.output = arguments.output;
  if (training.output.extension() != ".json")
    throw fileError(training.output, "a model is written as JSON: give a .json name");
  checkOutputTarget(training.output);
  training.folder = arguments.folder;
  training.tracks = tracking::tracksFolderFor(training.output, arguments.tracks);
  const std::vector<std::filesystem::path> videos = tracking::listVideos(arguments.folder);
  // The comparison model is read first: a wrong path fails before the tracking.
  const std::filesystem::path comparePath =
      arguments.compare.empty() ? pipeline::shippedModel("mouth.json") : std::filesystem::path(arguments.compare);
  const animation::MouthModel compared = animation::loadMouthModel(comparePath);
  tracking::VideoCorpusOptions options;
  options.threads = arguments.threads;
  options.synchronise = true;
  const tracking::VideoCorpus corpus = tracking::trackVideos(videos, training.tracks, options, std::cerr);
  eval::trainMouthModelOnOwnClips(corpus, training, compared, comparePath, std::cout);
}

}  // namespace

void addTrainVideoOptions(CLI::App& train) {
  auto arguments = std::make_shared<TrainVideoArguments>();
  train.add_option("--video", arguments->folder,
                   "Train a mouth model from the talking videos in this folder (tracks them, keeps the tracks)");
  train.add_option("-o,--output", arguments->output, "--video: the model file to write (.json)");
  train.add_option("--tracks", arguments->tracks,
                   "--video: folder for the clips' tracks, re-used while newer than the videos (default: "
                   "beside the model, <name>_tracks)");
  train
      .add_option("--hold-out", arguments->training.holdOutEvery,
                  "--video: hold out every N-th clip (by name) and report on them; 0 trains on all")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  train.add_option("--compare", arguments->compare,
                   "--video: the mouth model to compare with on the held-out clips (default: the shipped "
                   "models/mouth.json)");
  train.add_option("--states", arguments->training.options.states, "--video: states N")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  train.add_option("--mixtures", arguments->training.options.mixtures, "--video: Gaussians per state M")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  train.add_option("--context", arguments->training.options.contextFrames, "--video: MFCC context tc")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  train.add_option("--components", arguments->training.options.visualComponents, "--video: visual components K")
      ->check(CLI::Range(1, 21))
      ->capture_default_str();
  train.add_flag_function(
      "--diagonal",
      [arguments](std::int64_t) { arguments->training.options.covariance = hmm::CovarianceType::kDiagonal; },
      "--video: diagonal covariance (default full)");
  train.add_option("--threads", arguments->threads, "--video: tracking threads (0: one per core)")
      ->capture_default_str();
  train.callback([&train, arguments] {
    if (!train.get_subcommands().empty()) {
      if (!arguments->folder.empty()) throw Error("train: --video goes without a subcommand (head, mouth)");
      return;
    }
    if (arguments->folder.empty()) throw Error("train: give a subcommand (head, mouth) or --video DIR");
    if (arguments->output.empty()) throw Error("train --video: give the model file to write with -o MODEL.json");
    runTrainVideo(*arguments);
  });
}

}  // namespace th::app
