// `talkinghead eval mouth`: the audio → mouth AV-HMM on BEAT2, trained on the first part of the take and
// measured by the paper's ε and ρ on both parts, per synthesis method, beside baselines.
#include <cstdio>
#include <memory>
#include <string>

#include "animation/mouth_data.h"
#include "animation/mouth_evaluation.h"
#include "animation/mouth_model.h"
#include "commands.h"

namespace th::app {
namespace {

struct MouthArguments {
  double trainingFraction = 0.75;
  int windowFrames = 30;
};

// The audio of another segment of the same speaker: the same frames shifted by half their length.
Eigen::MatrixXd otherSegment(const Eigen::MatrixXd& frames) {
  const Eigen::Index half = frames.cols() / 2;
  Eigen::MatrixXd shifted(frames.rows(), frames.cols());
  shifted << frames.rightCols(frames.cols() - half), frames.leftCols(half);
  return shifted;
}

void printRow(const std::string& name, const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth, int iterations) {
  std::printf("  %-52s %6.3f  %6.3f", name.c_str(), animation::averageMse(estimate, truth),
              animation::averageCorrelation(estimate, truth));
  if (iterations > 0) std::printf("   %3d iterations", iterations);
  std::printf("\n");
}

void evaluatePart(const std::string& title, const animation::MouthModel& model, const animation::MouthRecording& part,
                  int window) {
  const Eigen::MatrixXd truth = model.basis.transform(part.visual);
  std::printf("  %s (%d frames)%*s      ε       ρ\n", title.c_str(), part.numFrames(),
              static_cast<int>(40 - title.size()), "");
  int iterations = 0;
  using animation::MouthMethod;
  const Eigen::MatrixXd mean = animation::synthesiseMouth(model, part.mfcc, {.start = hmm::InversionStart::kConditionalMean}, &iterations);
  printRow("inversion, conditional-mean start (ours)", mean, truth, iterations);
  const Eigen::MatrixXd random = animation::synthesiseMouth(model, part.mfcc, {.start = hmm::InversionStart::kRandom}, &iterations);
  printRow("inversion, random start (paper)", random, truth, iterations);
  const Eigen::MatrixXd windowed = animation::synthesiseMouth(model, part.mfcc, {.windowFrames = window}, &iterations);
  printRow("inversion, windows of " + std::to_string(window) + " frames (streaming)", windowed, truth, iterations);
  printRow("MMSE estimate", animation::synthesiseMouth(model, part.mfcc, {.method = MouthMethod::kMmse}), truth, 0);
  // The training data's mean: the components are zero-mean there by construction.
  printRow("baseline: mean prediction (the training mean)", Eigen::MatrixXd::Zero(truth.rows(), truth.cols()), truth, 0);
  printRow("baseline: inversion of another segment's audio",
           animation::synthesiseMouth(model, otherSegment(part.mfcc), {}), truth, 0);
}

void runEvalMouth(const MouthArguments& arguments) {
  const auto [train, test] = animation::splitByTime(animation::loadBeat2Mouth(), arguments.trainingFraction);
  std::printf("Mouth from audio on BEAT2: trained on the first %d frames, held out the last %d (%.1f s). Visual: "
              "K = 2 ICA-after-PCA components of [jaw opening, 100 expression coefficients]; audio: 11 MFCC with "
              "±tc frames of context. ε = AMSE normalised by the truth's variance (mean prediction: 1), ρ = ACC.\n",
              train.numFrames(), test.numFrames(), test.numFrames() / test.framesPerSecond);
  const struct {
    const char* name;
    animation::MouthModelOptions options;
  } configurations[] = {
      {"full covariance, N = 4, M = 2, tc = 3", {.states = 4, .mixtures = 2, .covariance = hmm::CovarianceType::kFull}},
      {"diagonal covariance, N = 19, M = 3, tc = 3",
       {.states = 19, .mixtures = 3, .covariance = hmm::CovarianceType::kDiagonal}},
  };
  for (const auto& configuration : configurations) {
    const animation::MouthModel model = animation::trainMouthModel({train}, configuration.options);
    std::printf("\n%s (%d Baum-Welch iterations; the K components keep %.1f %% of the visual variance)\n",
                configuration.name, model.iterations, 100.0 * model.basis.explainedVariance());
    evaluatePart("training part", model, train, arguments.windowFrames);
    evaluatePart("held-out part", model, test, arguments.windowFrames);
  }
  std::printf("\nThe paper's own best, on its own data: full N = 4, M = 2: ε = 0.47, ρ = 0.75; diagonal N = 19, "
              "M = 3: ε = 0.47, ρ = 0.76.\n");
}

}  // namespace

void addEvalMouthCommand(CLI::App& eval) {
  auto arguments = std::make_shared<MouthArguments>();
  CLI::App* mouth = eval.add_subcommand(
      "mouth", "Mouth from audio on BEAT2: the paper's ε and ρ per synthesis method, beside baselines");
  mouth->add_option("--train-fraction", arguments->trainingFraction,
                    "The first this fraction of the BEAT2 take trains, the rest is held out")
      ->check(CLI::Range(0.1, 0.95));
  mouth->add_option("--window", arguments->windowFrames, "Frames per window of the streaming inversion")
      ->check(CLI::Range(2, 10000));
  mouth->callback([arguments] { runEvalMouth(*arguments); });
}

}  // namespace th::app
