// `talkinghead train --video DIR -o MODEL.json`: a mouth model of one's own speaker from talking videos. Every
// clip is tracked and fitted (tracks kept for the next run), the jaw and lip FAPs become the visual part of
// the audio-visual HMM, and the model is checked on held-out clips against baselines and another model
// (engine/tracking/video_training.h).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

#include "animation/mouth_model.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "eval/mouth_evaluation.h"
#include "face/face_model.h"
#include "pipeline/animation_models.h"
#include "tracking/video_training.h"
#include "video_folder.h"

namespace th::app {
namespace {

struct TrainVideoArguments {
  std::string folder;
  std::string output;
  std::string tracks;  // empty: beside the output, "<stem>_tracks"
  int holdOutEvery = 5;
  unsigned threads = 0;
  std::string compare;  // empty: the shipped models/mouth.json
  // Chosen on the GRID s1 training clips alone, by tools/choose_video_mouth.sh (README: "Training from video").
  // FAPs are not standardised (trainVideoMouthModel), and the model file's options say so.
  // The speech normalised, the components' deltas generated as a trajectory and the spread compensated, as the
  // shipped models are (`train mouth`).
  animation::MouthModelOptions options{.states = 6,
                                       .mixtures = 1,
                                       .covariance = hmm::CovarianceType::kFull,
                                       .contextFrames = 2,
                                       .visualComponents = 3,
                                       .standardiseVisual = false,
                                       .normaliseSpeech = true,
                                       .visualDeltas = true,
                                       .varianceValidationEvery = 5};
};

void printScores(const char* label, const eval::FapScores& scores) {
  std::printf("  %-58s %6.3f / %6.3f   %6.3f / %6.3f (%d FAPs)\n", label, scores.jawEpsilon, scores.jawRho,
              scores.epsilon, scores.rho, scores.faps);
}

void runTrainVideo(const TrainVideoArguments& arguments) {
  const std::filesystem::path output = arguments.output;
  if (output.extension() != ".json") throw fileError(output, "a model is written as JSON: give a .json name");
  checkOutputTarget(output);
  const std::filesystem::path tracks = tracksFolderFor(output, arguments.tracks);
  const std::vector<std::filesystem::path> videos = tracking::listVideos(arguments.folder);
  // The comparison model is read first: a wrong path fails before the tracking.
  const std::filesystem::path comparePath =
      arguments.compare.empty() ? pipeline::shippedModel("mouth.json") : std::filesystem::path(arguments.compare);
  const animation::MouthModel compared = animation::loadMouthModel(comparePath);

  tracking::VideoCorpusOptions options;
  options.threads = arguments.threads;
  options.synchronise = true;
  const tracking::VideoCorpus corpus = trackVideos(videos, tracks, options);
  int trackedNow = 0;
  double residual = 0.0, found = 0.0;
  for (const tracking::VideoClip& clip : corpus.clips) {
    trackedNow += clip.trackedNow ? 1 : 0;
    residual += clip.meanResidualPixels / static_cast<double>(corpus.clips.size());
    found += clip.faceFoundShare / static_cast<double>(corpus.clips.size());
  }
  std::printf(
      "%zu clips from %s: %d tracked now, %zu read from %s, in %.1f s; face found in %.1f %% of frames, "
      "mean fit residual %.2f px\n",
      corpus.clips.size(), arguments.folder.c_str(), trackedNow,
      corpus.clips.size() - static_cast<std::size_t>(trackedNow), tracks.c_str(), corpus.trackingSeconds, 100.0 * found,
      residual);
  for (const tracking::SkippedClip& skipped : corpus.skipped) std::printf("  left out: %s\n", skipped.reason.c_str());
  for (const tracking::VideoClip& clip : corpus.clips)
    if (clip.soundOffset.measured)
      std::printf("  %s: the sound lags the picture by %.0f ms (taken out)\n", clip.video.filename().c_str(),
                  1000.0 * clip.soundOffset.lateSeconds);

  // Every holdOutEvery-th clip (by name) is held out; the rest train.
  std::vector<animation::MouthRecording> train, test;
  for (std::size_t i = 0; i < corpus.clips.size(); ++i) {
    const bool heldOut = arguments.holdOutEvery > 0 && (i + 1) % static_cast<std::size_t>(arguments.holdOutEvery) == 0;
    (heldOut ? test : train).push_back(corpus.clips[i].recording);
  }
  if (train.empty()) throw Error("train --video: no clip is left to train on");
  int trainFrames = 0;
  for (const auto& recording : train) trainFrames += recording.numFrames();
  const auto started = std::chrono::steady_clock::now();
  const animation::MouthModel model = tracking::trainVideoMouthModel(train, corpus.faps, arguments.options);
  const double trainSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  animation::saveMouthModel(output, model, arguments.options);
  std::printf(
      "mouth model: %d states x %d mixtures (%s), tc = %d, K = %d components keeping %.1f %% of the FAP "
      "variance; trained on %zu clips, %d frames (%.1f s of speech) in %.2f s (%d Baum-Welch iterations); "
      "wrote %s\n",
      model.hmm.numStates(), arguments.options.mixtures,
      arguments.options.covariance == hmm::CovarianceType::kFull ? "full" : "diagonal", model.contextFrames,
      model.basis.components(), 100.0 * model.basis.explainedVariance(), train.size(), trainFrames, trainFrames / 30.0,
      trainSeconds, model.iterations, output.c_str());
  if (test.empty()) return;

  int testFrames = 0;
  for (const auto& recording : test) testFrames += recording.numFrames();
  std::printf(
      "\nheld out: every %d. clip, %zu clips, %d frames. eps / rho on the jaw (FAP 3)   and on the FAPs both "
      "hold:\n",
      arguments.holdOutEvery, test.size(), testFrames);
  const std::vector<int> modelFaps = animation::mouthFapNumbers(model);
  printScores("this model, inversion (conditional-mean start)",
              eval::scoreFaps(eval::predictFaps(model, test), modelFaps, test, corpus.faps));
  printScores("this model, MMSE estimate",
              eval::scoreFaps(eval::predictFaps(model, test, {.method = animation::MouthMethod::kMmse}), modelFaps,
                              test, corpus.faps));
  {
    // The paper's own measure: on the model's K visual components rather than on FAPs.
    std::vector<Eigen::MatrixXd> estimates, truths;
    Eigen::Index frames = 0;
    for (const auto& recording : test) {
      estimates.push_back(animation::synthesiseMouth(model, recording.speech, {.varianceCompensation = false}));
      truths.push_back(model.basis.transform(recording.visual));
      frames += recording.numFrames();
    }
    Eigen::MatrixXd estimate(model.basis.components(), frames), truth(model.basis.components(), frames);
    Eigen::Index column = 0;
    for (std::size_t i = 0; i < test.size(); ++i) {
      estimate.middleCols(column, estimates[i].cols()) = estimates[i];
      truth.middleCols(column, truths[i].cols()) = truths[i];
      column += truths[i].cols();
    }
    std::printf("  %-58s %6.3f / %6.3f   on its %d visual components (the paper's measure)\n", "this model, inversion",
                eval::averageMse(estimate, truth), eval::averageCorrelation(estimate, truth), model.basis.components());
  }
  printScores(
      ("--compare " + comparePath.filename().string() + ", inversion").c_str(),
      eval::scoreFaps(eval::predictFaps(compared, test), animation::mouthFapNumbers(compared), test, corpus.faps));
  // The training clips' mean FAPs in every frame.
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(corpus.faps.size()));
  for (const auto& recording : train) mean += recording.visual.rowwise().sum() / trainFrames;
  std::vector<Eigen::MatrixXd> means;
  for (const auto& recording : test) means.push_back(mean.replicate(1, recording.numFrames()));
  printScores("baseline: the training mean", eval::scoreFaps(means, corpus.faps, test, corpus.faps));
  if (test.size() > 1)
    printScores("baseline: this model on the next held-out clip's audio",
                eval::scoreFaps(eval::predictFaps(model, test, {}, 1), modelFaps, test, corpus.faps));
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
      .add_option("--hold-out", arguments->holdOutEvery,
                  "--video: hold out every N-th clip (by name) and report on them; 0 trains on all")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  train.add_option("--compare", arguments->compare,
                   "--video: the mouth model to compare with on the held-out clips (default: the shipped "
                   "models/mouth.json)");
  train.add_option("--states", arguments->options.states, "--video: states N")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  train.add_option("--mixtures", arguments->options.mixtures, "--video: Gaussians per state M")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  train.add_option("--context", arguments->options.contextFrames, "--video: MFCC context tc")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  train.add_option("--components", arguments->options.visualComponents, "--video: visual components K")
      ->check(CLI::Range(1, 21))
      ->capture_default_str();
  train.add_flag_function(
      "--diagonal", [arguments](std::int64_t) { arguments->options.covariance = hmm::CovarianceType::kDiagonal; },
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
