#include "eval/own_mouth_training.h"

#include <chrono>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/print_to.h"
#include "eval/mouth_evaluation.h"

namespace th::eval {
namespace {

void writeFapScores(std::ostream& out, const std::string& label, const FapScores& scores) {
  printTo(out, "  %-58s %6.3f / %6.3f   %6.3f / %6.3f (%d FAPs)\n", label.c_str(), scores.jawEpsilon, scores.jawRho,
          scores.epsilon, scores.rho, scores.faps);
}

void writeTrackingSummary(std::ostream& out, const tracking::VideoCorpus& corpus, const OwnMouthTraining& training) {
  int trackedNow = 0;
  double residual = 0.0, found = 0.0;
  for (const tracking::VideoClip& clip : corpus.clips) {
    trackedNow += clip.trackedNow ? 1 : 0;
    residual += clip.meanResidualPixels / static_cast<double>(corpus.clips.size());
    found += clip.faceFoundShare / static_cast<double>(corpus.clips.size());
  }
  printTo(out,
          "%zu clips from %s: %d tracked now, %zu read from %s, in %.1f s; face found in %.1f %% of frames, "
          "mean fit residual %.2f px\n",
          corpus.clips.size(), training.folder.c_str(), trackedNow,
          corpus.clips.size() - static_cast<std::size_t>(trackedNow), training.tracks.c_str(), corpus.trackingSeconds,
          100.0 * found, residual);
  for (const tracking::SkippedClip& skipped : corpus.skipped) printTo(out, "  left out: %s\n", skipped.reason.c_str());
  for (const tracking::VideoClip& clip : corpus.clips)
    if (clip.soundOffset.measured)
      printTo(out, "  %s: the sound lags the picture by %.0f ms (taken out)\n", clip.video.filename().c_str(),
              1000.0 * clip.soundOffset.lateSeconds);
}

int totalFramesOf(const std::vector<animation::MouthRecording>& recordings) {
  int frames = 0;
  for (const auto& recording : recordings) frames += recording.numFrames();
  return frames;
}

// The paper's own measure: ε and ρ on the model's K visual components rather than on FAPs, over all clips.
void writeComponentScores(std::ostream& out, const animation::MouthModel& model,
                          const std::vector<animation::MouthRecording>& test) {
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
  printTo(out, "  %-58s %6.3f / %6.3f   on its %d visual components (the paper's measure)\n", "this model, inversion",
          averageMse(estimate, truth), averageCorrelation(estimate, truth), model.basis.components());
}

// The held-out clips: this model, the compared one and the baselines.
void writeHeldOutScores(std::ostream& out, const animation::MouthModel& model,
                        const std::vector<animation::MouthRecording>& train,
                        const std::vector<animation::MouthRecording>& test, const std::vector<int>& faps,
                        const animation::MouthModel& compared, const std::filesystem::path& comparedPath,
                        int holdOutEvery) {
  printTo(out,
          "\nheld out: every %d. clip, %zu clips, %d frames. eps / rho on the jaw (FAP 3)   and on the FAPs both "
          "hold:\n",
          holdOutEvery, test.size(), totalFramesOf(test));
  const std::vector<int> modelFaps = animation::mouthFapNumbers(model);
  writeFapScores(out, "this model, inversion (conditional-mean start)",
                 scoreFaps(predictFaps(model, test), modelFaps, test, faps));
  writeFapScores(out, "this model, MMSE estimate",
                 scoreFaps(predictFaps(model, test, {.method = animation::MouthMethod::kMmse}), modelFaps, test, faps));
  writeComponentScores(out, model, test);
  writeFapScores(out, "--compare " + comparedPath.filename().string() + ", inversion",
                 scoreFaps(predictFaps(compared, test), animation::mouthFapNumbers(compared), test, faps));
  // The training clips' mean FAPs in every frame.
  const int trainFrames = totalFramesOf(train);
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(faps.size()));
  for (const auto& recording : train) mean += recording.visual.rowwise().sum() / trainFrames;
  std::vector<Eigen::MatrixXd> means;
  for (const auto& recording : test) means.push_back(mean.replicate(1, recording.numFrames()));
  writeFapScores(out, "baseline: the training mean", scoreFaps(means, faps, test, faps));
  if (test.size() > 1)
    writeFapScores(out, "baseline: this model on the next held-out clip's audio",
                   scoreFaps(predictFaps(model, test, {}, 1), modelFaps, test, faps));
}

}  // namespace

void trainMouthModelOnOwnClips(const tracking::VideoCorpus& corpus, const OwnMouthTraining& training,
                               const animation::MouthModel& compared, const std::filesystem::path& comparedPath,
                               std::ostream& out) {
  writeTrackingSummary(out, corpus, training);
  // Every holdOutEvery-th clip (by name) is held out; the rest train.
  std::vector<animation::MouthRecording> train, test;
  for (std::size_t i = 0; i < corpus.clips.size(); ++i) {
    const bool heldOut = training.holdOutEvery > 0 && (i + 1) % static_cast<std::size_t>(training.holdOutEvery) == 0;
    (heldOut ? test : train).push_back(corpus.clips[i].recording);
  }
  if (train.empty()) throw Error("train --video: no clip is left to train on");
  const int trainFrames = totalFramesOf(train);
  const auto started = std::chrono::steady_clock::now();
  const animation::MouthModel model = tracking::trainVideoMouthModel(train, corpus.faps, training.options);
  const double trainSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  animation::saveMouthModel(training.output, model, training.options);
  printTo(out,
          "mouth model: %d states x %d mixtures (%s), tc = %d, K = %d components keeping %.1f %% of the FAP "
          "variance; trained on %zu clips, %d frames (%.1f s of speech) in %.2f s (%d Baum-Welch iterations); "
          "wrote %s\n",
          model.hmm.numStates(), training.options.mixtures,
          training.options.covariance == hmm::CovarianceType::kFull ? "full" : "diagonal", model.contextFrames,
          model.basis.components(), 100.0 * model.basis.explainedVariance(), train.size(), trainFrames,
          trainFrames / 30.0, trainSeconds, model.iterations, training.output.c_str());
  if (test.empty()) return;
  writeHeldOutScores(out, model, train, test, corpus.faps, compared, comparedPath, training.holdOutEvery);
}

}  // namespace th::eval
