// `talkinghead train head` and `talkinghead eval head`: the prosody → head-motion model trained on several
// speakers (BEAT2's training part and StyleTalk's clips), and judged leave-one-speaker-out beside baselines that
// show whether the voice matters, by the paper's error and by what a viewer sees (speed, spread, stillness in
// pauses, the distribution of the motion).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "animation/head_model.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/head_report.h"
#include "pipeline/options.h"
#include "tracking/video_folder.h"
#include "tracking/video_training.h"

namespace th::app {
namespace {

struct HeadArguments {
  std::string model;    // eval: judge this model file too (trained on what it was trained on)
  std::string compare;  // eval: another model file to judge beside (e.g. an older default)
  std::string output;   // train: where to write it
  double trainingFraction = 0.75;
  int lagFrames = animation::kLiveHeadLagFrames;
  bool beat2Only = false;  // train: the single-speaker model of the paper's setting
  bool styleFrom = false;  // eval: the head style from another clip of each held-out speaker
  std::string video;       // train: a folder of the user's own talking videos, trained on beside the corpora
  std::string tracks;      // train --video: where the tracks are kept (default: beside the output)
  int holdOutEvery = 5;    // train --video: every N-th clip held out
  bool outputGiven = false;
  animation::HeadModelOptions options;
};

void addModelOptions(CLI::App* command, HeadArguments& arguments) {
  command
      ->add_option("--train-fraction", arguments.trainingFraction,
                   "The first this fraction of the BEAT2 take trains, the rest is held out")
      ->check(CLI::Range(0.1, 0.95))
      ->capture_default_str();
  command->add_option("--start-states", arguments.options.startStates, "Fully connected states to start from")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  command
      ->add_option("--entropic", arguments.options.entropicWeightPerFrame,
                   "Entropic prior weight per training frame (Z = this x frames)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  command->add_option("--seed", arguments.options.seed, "Seed of the k-means++ start")->capture_default_str();
  command->add_option("--iterations", arguments.options.maxIterations, "Most Baum-Welch iterations of the motion HMM")
      ->check(CLI::Range(5, 1000))
      ->capture_default_str();
  command->add_flag(
      "--residual-from-training", [&arguments](std::int64_t) { arguments.options.residualFromHeldOutSpeakers = false; },
      "Size the residual motion on the model's own training speech (one training instead of one more "
      "per speaker; the residual comes out smaller on new voices)");
  command->add_flag(
      "--no-speaker-normalisation", [&arguments](std::int64_t) { arguments.options.normaliseSpeakers = false; },
      "Keep each speaker's motion in degrees instead of in units of its own spread");
}

eval::HeadTraining trainingOf(const HeadArguments& arguments) {
  return {.output = arguments.output,
          .model = arguments.options,
          .trainingFraction = arguments.trainingFraction,
          .beat2Only = arguments.beat2Only,
          .holdOutEvery = arguments.holdOutEvery};
}

// `train head --video DIR`: the corpora and the user's own clips (one more speaker), every N-th clip held out
// and judged as eval head judges a speaker, beside the shipped model.
void runTrainVideo(const HeadArguments& arguments) {
  if (!arguments.outputGiven) throw Error("train head --video: give -o FILE.json (the shipped model stays as it is)");
  const std::filesystem::path output = arguments.output;
  if (output.extension() != ".json") throw fileError(output, "a model is written as JSON: give a .json name");
  checkOutputTarget(output);
  if (arguments.beat2Only) throw Error("train head --video: --beat2 trains BEAT2's speaker alone; leave it out");
  const std::filesystem::path tracks = tracking::tracksFolderFor(output, arguments.tracks);
  const std::vector<std::filesystem::path> videos = tracking::listVideos(arguments.video);
  const animation::HeadModel shipped = animation::loadHeadModel(pipeline::ModelOptions{}.headModelPath());
  tracking::VideoCorpusOptions withHeads;
  withHeads.heads = true;
  const tracking::VideoCorpus clips = tracking::trackVideos(videos, tracks, withHeads, std::cerr);
  eval::trainHeadModelWithOwnClips(clips, arguments.video, shipped, trainingOf(arguments), std::cout, std::cerr);
}

void runTrain(const HeadArguments& arguments) {
  if (arguments.video.empty()) {
    eval::trainHeadModelOnCorpora(trainingOf(arguments), std::cerr);
  } else {
    runTrainVideo(arguments);
  }
}

void runEval(const HeadArguments& arguments) {
  const eval::HeadReportOptions options{.model = arguments.options,
                                        .trainingFraction = arguments.trainingFraction,
                                        .lagFrames = arguments.lagFrames,
                                        .judged = arguments.model,
                                        .compare = arguments.compare};
  if (arguments.styleFrom) {
    eval::reportHeadStyles(options, std::cout);
  } else {
    eval::reportHeadLeaveOneSpeakerOut(options, std::cout);
  }
}

}  // namespace

void addTrainCommand(CLI::App& app) {
  CLI::App* train = app.add_subcommand("train", "Train the animation models from the shared recordings");
  train->require_subcommand(0, 1);  // none with --video
  auto arguments = std::make_shared<HeadArguments>();
  arguments->output = "models/head.json";
  CLI::App* head =
      train->add_subcommand("head", "Prosody -> head motion HMM from BEAT2's training part and StyleTalk's speakers");
  addModelOptions(head, *arguments);
  head->add_option("-o,--output", arguments->output, "Model file to write")->capture_default_str();
  head->add_flag("--beat2", arguments->beat2Only, "BEAT2's one speaker only (the paper's setting)");
  head->add_option("--video", arguments->video,
                   "A folder of your own talking videos (one person), tracked and trained on beside the corpora; "
                   "every N-th clip held out and judged (give -o)");
  head->add_option("--tracks", arguments->tracks,
                   "With --video: where the tracks are kept and re-used (default: beside the output, NAME_tracks)");
  head->add_option("--hold-out-every", arguments->holdOutEvery, "With --video: every N-th clip is held out")
      ->check(CLI::Range(2, 100))
      ->capture_default_str();
  head->callback([arguments, head] {
    arguments->outputGiven = head->count("--output") > 0;
    runTrain(*arguments);
  });
  addTrainMouthCommand(*train);
  addTrainVisemesCommand(*train);
  addTrainArticulationCommand(*train);
  addTrainVideoOptions(*train);
}

void addEvalHeadCommand(CLI::App& eval) {
  auto arguments = std::make_shared<HeadArguments>();
  CLI::App* head = eval.add_subcommand(
      "head",
      "Head motion from prosody, leave one speaker out: the paper's E, speed, spread, pauses, jumps and the "
      "Fréchet distance beside baselines");
  addModelOptions(head, *arguments);
  head->add_option("--model", arguments->model, "Also judge this model file on BEAT2's held-out part");
  head->add_option("--compare", arguments->compare, "Judge this model file beside the recipe (e.g. an older default)");
  head->add_option("--lag-frames,--lag", arguments->lagFrames, "Decoding lag of the online variant, frames")
      ->check(CLI::Range(0, 300))
      ->capture_default_str();
  head->add_flag("--style-from", arguments->styleFrom,
                 "Instead: each held-out speaker's head style from another clip of theirs, styled beside unstyled");
  head->callback([arguments] { runEval(*arguments); });
}

}  // namespace th::app
