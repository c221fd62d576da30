// `talkinghead train visemes` and `talkinghead eval visemes`: the viseme model (animation/viseme_model.h) from the
// shared data's phone-aligned speech, and its accuracy on speakers it never heard.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "core/atomic_file.h"
#include "eval/viseme_corpus.h"
#include "face/visemes.h"

namespace th::app {
namespace {

struct VisemeArguments {
  animation::VisemeModelOptions model;
  std::string output = "models/visemes.json";
  int lagFrames = 2;
  bool sweep = false;
};

void addRecipeOptions(CLI::App* command, VisemeArguments& arguments) {
  command->add_option("--context", arguments.model.contextFrames, "Context frames each side (30 fps)")
      ->check(CLI::Range(0, 20))
      ->capture_default_str();
  command->add_option("--dimensions", arguments.model.dimensions, "Discriminant directions kept")
      ->check(CLI::Range(1, face::kNumMouthClasses - 1))
      ->capture_default_str();
  command->add_option("--mixtures", arguments.model.mixtures, "Gaussians per mouth class")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  command->add_option("--min-hold", arguments.model.minHoldFrames, "Frames a viseme is shown at least")
      ->check(CLI::Range(1, 15))
      ->capture_default_str();
  command->add_option("--emission-scale", arguments.model.emissionScale, "Weight of the sound against the sequence")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
}

std::vector<std::string> names(const auto& list) {
  std::vector<std::string> out;
  for (std::string_view name : list) out.emplace_back(name);
  return out;
}

void printScores(const char* what, const eval::VisemeScores& scores, double fps) {
  const eval::HoldTimes& holds = scores.holds();
  std::printf("  %-34s %6.1f%% %8.1f%% %8.1f%%", what, 100.0 * scores.oculusAccuracy(),
              100.0 * scores.rhubarbAccuracy(), 100.0 * scores.classAccuracy());
  if (holds.runFrames.empty()) {
    std::printf("   %8s %9s %8s %7s\n", "-", "-", "-", "0");  // one viseme throughout
    return;
  }
  std::printf("   %5.0f ms %6.0f ms %7.1f%% %7.1f\n", 1000.0 * holds.shortest() / fps,
              1000.0 * holds.medianFrames() / fps, 100.0 * holds.shortRunShare(2),
              holds.switchesPerSecond(fps, scores.frames()));
}

void runEval(const VisemeArguments& arguments) {
  const std::vector<eval::VisemeRecording> corpus = eval::loadVisemeCorpus();
  const double fps = 30.0;
  const auto judge = [&](const animation::VisemeModelOptions& options) {
    return eval::leaveOneSpeakerOut(corpus, options, arguments.lagFrames);
  };
  const eval::VisemeEvaluation result = judge(arguments.model);
  int frames = 0;
  for (const eval::VisemeRecording& r : corpus) frames += r.speech.numFrames();
  std::printf("Visemes from speech, leave one speaker out (%zu speakers:", result.speakers.size());
  for (const std::string& speaker : result.speakers) std::printf(" %s", speaker.c_str());
  std::printf("; %d frames, %.0f s, %d with a phone)\n", frames, frames / fps, result.batch.labelledFrames());
  std::printf("  %-34s %7s %9s %9s   %8s %9s %8s %7s\n", "", "Oculus", "Rhubarb", "classes", "shortest", "median",
              "<=2 fr", "per s");
  printScores("HMM, whole recording (animate)", result.batch, fps);
  printScores(("HMM, streamed, lag " + std::to_string(arguments.lagFrames) + " (live)").c_str(), result.stream, fps);
  printScores("each frame alone (no HMM)", result.frameByFrame, fps);
  printScores("the most frequent class", result.majority, fps);
  const eval::HoldTimes& truth = result.batch.referenceHolds();
  std::printf("  %-34s %7s %9s %9s   %5.0f ms %6.0f ms %7.1f%% %7.1f\n", "the phones' own classes", "", "", "",
              1000.0 * truth.shortest() / fps, 1000.0 * truth.medianFrames() / fps, 100.0 * truth.shortRunShare(2),
              truth.switchesPerSecond(fps, result.batch.frames()));
  std::printf("\nOculus visemes, HMM whole recording (rows: the phones' viseme; %% of its frames decoded as each)\n%s",
              eval::formatConfusion(result.batch.oculusConfusion(), names(face::kOculusVisemeNames)).c_str());
  std::vector<std::string> shapes;
  for (char shape : face::kRhubarbShapes) shapes.emplace_back(1, shape);
  std::printf("\nRhubarb shapes, HMM whole recording\n%s",
              eval::formatConfusion(result.batch.rhubarbConfusion(), shapes).c_str());
  if (arguments.sweep) {
    std::printf("\nMinimum hold (frames) against accuracy and flicker, whole recording:\n");
    for (int hold : {1, 2, 3, 4, 5}) {
      animation::VisemeModelOptions options = arguments.model;
      options.minHoldFrames = hold;
      printScores(("min hold " + std::to_string(hold)).c_str(), judge(options).batch, fps);
    }
    std::printf("\nEmission scale:\n");
    for (double scale : {0.1, 0.2, 0.35, 0.5, 1.0}) {
      animation::VisemeModelOptions options = arguments.model;
      options.emissionScale = scale;
      char label[64];
      std::snprintf(label, sizeof label, "emission scale %.2f", scale);
      printScores(label, judge(options).batch, fps);
    }
  }
}

void runTrain(const VisemeArguments& arguments) {
  checkOutputTarget(arguments.output);
  const std::vector<eval::VisemeRecording> corpus = eval::loadVisemeCorpus();
  const animation::VisemeModel model = animation::trainVisemeModel(eval::labelledSpeechOf(corpus), arguments.model);
  animation::saveVisemeModel(arguments.output, model);
  int frames = 0;
  for (const eval::VisemeRecording& r : corpus) frames += r.speech.numFrames();
  std::cout << "wrote " << arguments.output << ": " << face::kNumMouthClasses << " mouth classes from " << corpus.size()
            << " recordings (" << frames << " frames), min hold " << model.minHoldFrames << " frames\n";
}

}  // namespace

void addTrainVisemesCommand(CLI::App& train) {
  auto arguments = std::make_shared<VisemeArguments>();
  CLI::App* command = train.add_subcommand(
      "visemes", "Speech -> visemes (Oculus, VRM, Rhubarb) from BEAT2's and StyleTalk's phone-aligned speech");
  addRecipeOptions(command, *arguments);
  command->add_option("-o,--output", arguments->output, "Model file to write")->capture_default_str();
  command->callback([arguments] { runTrain(*arguments); });
}

void addEvalVisemesCommand(CLI::App& eval) {
  auto arguments = std::make_shared<VisemeArguments>();
  CLI::App* command = eval.add_subcommand(
      "visemes",
      "Visemes from speech, leave one speaker out: accuracy against the phones, confusion matrices, hold times");
  addRecipeOptions(command, *arguments);
  command->add_option("--lag-frames,--lag", arguments->lagFrames, "Decision lag of the streamed decoder, frames")
      ->check(CLI::Range(0, 60))
      ->capture_default_str();
  command->add_flag("--sweep", arguments->sweep, "Also the minimum hold and the emission scale, one at a time");
  command->callback([arguments] { runEval(*arguments); });
}

}  // namespace th::app
