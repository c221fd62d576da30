// `talkinghead train head` and `talkinghead eval head`: the prosody → head-motion model on BEAT2, trained on
// the first part of the take and evaluated on both parts beside baselines that show whether the voice matters.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "animation/head_data.h"
#include "animation/head_evaluation.h"
#include "animation/head_model.h"
#include "animation/time_split.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "hmm/entropic_training.h"

namespace th::app {
namespace {

using animation::HeadVariant;

struct HeadArguments {
  std::string model;       // eval: a trained model to evaluate instead of training one
  std::string output;      // train: where to write it
  double trainingFraction = 0.75;
  int lagFrames = 6;
  animation::HeadModelOptions options;
};

void addModelOptions(CLI::App* command, HeadArguments& arguments) {
  command->add_option("--train-fraction", arguments.trainingFraction,
                      "The first this fraction of the BEAT2 take trains, the rest is held out")
      ->check(CLI::Range(0.1, 0.95));
  command->add_option("--start-states", arguments.options.startStates, "Fully connected states to start from")
      ->check(CLI::Range(2, 100));
  command->add_option("--entropic", arguments.options.entropicWeightPerFrame,
                      "Entropic prior weight per training frame (Z = this x frames)")
      ->check(CLI::Range(0.0, 10.0));
  command->add_option("--seed", arguments.options.seed, "Seed of the k-means++ start");
}

struct TrainedHead {
  animation::HeadModel model;
  double seconds = 0.0;
};

TrainedHead trainOnBeat2(const animation::HeadRecording& train, const animation::HeadModelOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  TrainedHead trained{animation::trainHeadModel({train}, options), 0.0};
  trained.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return trained;
}

void runTrain(const HeadArguments& arguments) {
  checkOutputTarget(arguments.output);
  const auto [train, test] = animation::splitByTime(animation::loadBeat2Head(), arguments.trainingFraction);
  const TrainedHead trained = trainOnBeat2(train, arguments.options);
  animation::saveHeadModel(arguments.output, trained.model, arguments.options);
  std::cerr << "head model: " << trained.model.hmm.numStates() << " states (from " << arguments.options.startStates
            << "), " << hmm::countTransitions(trained.model.hmm) << " transitions, trained on " << train.numFrames()
            << " frames in " << trained.seconds << " s; wrote " << arguments.output << '\n';
}

void printRow(const std::string& name, const animation::HeadMetrics& m) {
  std::printf("  %-56s %6.3f   %5.2f %5.2f %5.2f   %4.1f %4.1f %4.1f   %5.2f %5.2f %5.2f   %5.1f\n", name.c_str(),
              m.error, m.correlation[0], m.correlation[1], m.correlation[2], m.poseStd[0], m.poseStd[1], m.poseStd[2],
              m.velocityStd[0], m.velocityStd[1], m.velocityStd[2], 100.0 * m.jumpRate);
}

void evaluatePart(const std::string& title, const animation::HeadModel& model, const animation::HeadRecording& part,
                  int lag) {
  const Eigen::MatrixXd truth = part.rotations.colwise() - model.meanPose;
  const double jump = animation::stepQuantile(truth, 0.99);
  const animation::HeadMetrics reference = animation::evaluateHead(truth, truth, jump);
  std::printf("\n%s: %d frames (%.1f s from %.1f s); jumps: steps over %.2f deg (the truth's 99th percentile)\n",
              title.c_str(), part.numFrames(), part.numFrames() / part.framesPerSecond, part.startSeconds, jump);
  std::printf("  %-56s %6s   %-17s   %-14s   %-17s   %5s\n", "", "E", "corr p / y / r", "std p / y / r",
              "vel std p / y / r", "jump%");
  std::printf("  %-56s %6s   %5s %5s %5s   %4.1f %4.1f %4.1f   %5.2f %5.2f %5.2f   %5.1f\n", "truth", "", "", "", "",
              reference.poseStd[0], reference.poseStd[1], reference.poseStd[2], reference.velocityStd[0],
              reference.velocityStd[1], reference.velocityStd[2], 100.0 * reference.jumpRate);
  const struct {
    const char* name;
    HeadVariant variant;
  } variants[] = {{"(a) Viterbi state means (paper)", HeadVariant::kStateMeans},
                  {"(b) ML trajectory (ours)", HeadVariant::kTrajectory},
                  {"(b') posterior means (ours)", HeadVariant::kPosteriorMeans}};
  for (const auto& v : variants) {
    printRow(v.name, animation::evaluateHead(animation::synthesiseHead(model, part.prosody, {.variant = v.variant}), truth, jump));
  }
  for (const auto& v : variants) {
    const animation::HeadSynthesisOptions online{.variant = v.variant, .maxLagFrames = lag};
    printRow(std::string("(c) ") + v.name + ", online, lag " + std::to_string(animation::headLookaheadFrames(online)),
             animation::evaluateHead(animation::synthesiseHead(model, part.prosody, online), truth, jump));
  }
  std::printf("  baselines:\n");
  printRow("constant mean pose", animation::evaluateHead(Eigen::MatrixXd::Zero(3, truth.cols()), truth, jump));
  const Eigen::MatrixXd other = animation::anotherSegment(part.prosody);
  printRow("(a) with prosody from another segment",
           animation::evaluateHead(animation::synthesiseHead(model, other, {.variant = HeadVariant::kStateMeans}), truth, jump));
  printRow("(b) with prosody from another segment",
           animation::evaluateHead(animation::synthesiseHead(model, other, {.variant = HeadVariant::kTrajectory}), truth, jump));
  // One walk can land near the truth's mean offsets by luck: the average over kWalks seeds.
  constexpr int kWalks = 20;
  animation::HeadMetrics walks = animation::evaluateHead(Eigen::MatrixXd::Zero(3, truth.cols()), truth, jump);
  walks.error = 0.0;
  walks.correlation.setZero();
  walks.jumpRate = 0.0;
  for (unsigned seed = 1; seed <= kWalks; ++seed) {
    const animation::HeadMetrics walk = animation::evaluateHead(animation::randomWalkHead(model, part.numFrames(), seed), truth, jump);
    walks.error += walk.error / kWalks;
    walks.correlation += walk.correlation / kWalks;
    walks.poseStd += walk.poseStd / kWalks;
    walks.velocityStd += walk.velocityStd / kWalks;
    walks.jumpRate += walk.jumpRate / kWalks;
  }
  printRow("random walk through the motion HMM (mean of 20)", walks);
}

void runEval(const HeadArguments& arguments) {
  const auto [train, test] = animation::splitByTime(animation::loadBeat2Head(), arguments.trainingFraction);
  animation::HeadModel model;
  if (!arguments.model.empty()) {
    model = animation::loadHeadModel(arguments.model);
    std::printf("head model %s: %d states, %d transitions\n", arguments.model.c_str(), model.hmm.numStates(),
                hmm::countTransitions(model.hmm));
  } else {
    const TrainedHead trained = trainOnBeat2(train, arguments.options);
    model = trained.model;
    std::printf("head model trained on the first %d frames: %d states (from %d, Z = %.3f x frames), %d transitions, "
                "%.1f s\n",
                train.numFrames(), model.hmm.numStates(), arguments.options.startStates,
                arguments.options.entropicWeightPerFrame, hmm::countTransitions(model.hmm), trained.seconds);
  }
  std::printf("E = mean of |x^ - x|^2 / (|x^|^2 + |x|^2) over frames, rotations in degrees from the training mean "
              "pose; std in degrees, velocity std in degrees per frame (30 fps)\n");
  evaluatePart("training part", model, train, arguments.lagFrames);
  evaluatePart("held-out part", model, test, arguments.lagFrames);
  std::printf("\nThe paper's own figures, on its own data (not comparable frame for frame): E = 0.2362 train, "
              "0.2727 test.\n");
}

}  // namespace

void addTrainCommand(CLI::App& app) {
  CLI::App* train = app.add_subcommand("train", "Train the animation models from the shared recordings");
  train->require_subcommand(0, 1);  // none with --video
  auto arguments = std::make_shared<HeadArguments>();
  arguments->output = "models/head.json";
  CLI::App* head = train->add_subcommand("head", "Prosody -> head motion HMM from BEAT2 (training part)");
  addModelOptions(head, *arguments);
  head->add_option("-o,--output", arguments->output, "Model file to write (default models/head.json)");
  head->callback([arguments] { runTrain(*arguments); });
  addTrainMouthCommand(*train);
  addTrainVideoOptions(*train);
}

void addEvalHeadCommand(CLI::App& eval) {
  auto arguments = std::make_shared<HeadArguments>();
  CLI::App* head = eval.add_subcommand(
      "head", "Head motion from prosody on BEAT2: the paper's error E and more, per variant, beside baselines");
  addModelOptions(head, *arguments);
  head->add_option("--model", arguments->model, "Evaluate this head model instead of training one");
  head->add_option("--lag", arguments->lagFrames, "Decoding lag of the online variants, frames")
      ->check(CLI::Range(0, 300));
  head->callback([arguments] { runEval(*arguments); });
}

}  // namespace th::app
