#include "eval/beat2_mouth_report.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "animation/fap_mapping.h"
#include "animation/mouth_data.h"
#include "animation/time_split.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/print_to.h"
#include "core/statistics.h"
#include "core/subprocess.h"
#include "eval/mouth_corpus.h"
#include "eval/mouth_evaluation.h"
#include "face/feature_points.h"
#include "features/context.h"
#include "hmm/audio_retraining.h"

namespace th::eval {
namespace {

// The same frames, shifted by half their length (animation/time_split.h's baseline), level and MFCCs together.
animation::SpeechFrames anotherSpeechSegment(const animation::SpeechFrames& speech) {
  Eigen::MatrixXd both(speech.mfcc.rows() + 1, speech.mfcc.cols());
  both << speech.mfcc, speech.levelDb;
  const Eigen::MatrixXd shifted = animation::anotherSegment(both);
  return {shifted.topRows(speech.mfcc.rows()), shifted.bottomRows(1)};
}

void writeMethodRow(std::ostream& out, const std::string& name, const Eigen::MatrixXd& estimate,
                    const Eigen::MatrixXd& truth, int iterations) {
  printTo(out, "  %-52s %6.3f  %6.3f", name.c_str(), averageMse(estimate, truth), averageCorrelation(estimate, truth));
  if (iterations > 0) printTo(out, "   %3d iterations", iterations);
  out << '\n';
}

// One part of the take: every synthesis method and the two baselines, by ε and ρ on the K visual components.
void reportPart(std::ostream& out, const std::string& title, const animation::MouthModel& model,
                const animation::MouthRecording& part, int window) {
  const Eigen::MatrixXd truth = model.basis.transform(part.visual);
  printTo(out, "  %s (%d frames)%*s      ε       ρ\n", title.c_str(), part.numFrames(),
          static_cast<int>(40 - title.size()), "");
  int iterations = 0;
  using animation::MouthMethod;
  const Eigen::MatrixXd mean =
      animation::synthesiseMouth(model, part.speech, {.start = hmm::InversionStart::kConditionalMean}, &iterations);
  writeMethodRow(out, "inversion, conditional-mean start (ours)", mean, truth, iterations);
  const Eigen::MatrixXd random =
      animation::synthesiseMouth(model, part.speech, {.start = hmm::InversionStart::kRandom}, &iterations);
  writeMethodRow(out, "inversion, random start (paper)", random, truth, iterations);
  const Eigen::MatrixXd windowed =
      animation::synthesiseMouth(model, part.speech, {.windowFrames = window}, &iterations);
  writeMethodRow(out, "inversion, windows of " + std::to_string(window) + " frames (streaming)", windowed, truth,
                 iterations);
  writeMethodRow(out, "MMSE estimate", animation::synthesiseMouth(model, part.speech, {.method = MouthMethod::kMmse}),
                 truth, 0);
  // The training data's mean: the components are zero-mean there by construction.
  writeMethodRow(out, "baseline: mean prediction (the training mean)",
                 Eigen::MatrixXd::Zero(truth.rows(), truth.cols()), truth, 0);
  writeMethodRow(out, "baseline: inversion of another segment's audio",
                 animation::synthesiseMouth(model, anotherSpeechSegment(part.speech), {}), truth, 0);
}

const char* sweepCovarianceName(hmm::CovarianceType type) {
  return type == hmm::CovarianceType::kFull ? "full" : "diag";
}

// Fig. 3 of the paper: ε and ρ on the held-out part against N, one curve per M, at the context tc chosen on the
// validation data; one PNG per covariance type, drawn by gnuplot.
void plotSweep(const std::filesystem::path& folder, const std::filesystem::path& csv, hmm::CovarianceType covariance,
               int contextFrames, const std::vector<int>& mixtures) {
  const std::string name = sweepCovarianceName(covariance);
  const std::filesystem::path png = folder / ("mouth_sweep_" + name + ".png");
  const std::filesystem::path script = folder / ("mouth_sweep_" + name + ".gp");
  {
    std::ofstream out(script);
    out << "set terminal pngcairo size 1200,480 font 'sans,11'\n"
        << "set output '" << png.string() << ".part'\n"
        << "set datafile separator ','\n"
        << "set multiplot layout 1,2 title '" << name << " covariance, tc = " << contextFrames
        << ": held-out part of BEAT2 (inversion, conditional-mean start)'\n"
        << "set xlabel 'states N'\nset grid\nset key outside right\n";
    for (const char* measure : {"epsilon", "rho"}) {
      const int column = std::string(measure) == "epsilon" ? 8 : 9;
      out << "set ylabel '" << (std::string(measure) == "epsilon" ? "AMSE (epsilon)" : "ACC (rho)") << "'\n"
          << "plot ";
      for (size_t i = 0; i < mixtures.size(); ++i) {
        out << (i ? ", " : "") << "'" << csv.string()
            << "' using ($1 == " << (covariance == hmm::CovarianceType::kFull ? 0 : 1) << " && $2 == " << contextFrames
            << " && $3 == " << mixtures[i] << " ? $4 : 1/0):" << column
            << " with linespoints title 'M = " << mixtures[i] << "'";
      }
      out << "\n";
    }
    out << "unset multiplot\n";
  }
  runProgram({"gnuplot", script.string()});
  std::filesystem::rename(png.string() + ".part", png);
  std::filesystem::remove(script);
}

// The MFCC frames of every recording in the shared folders named (files with the extension given).
std::vector<Eigen::MatrixXd> speechOnlyMfcc(const std::vector<std::string>& folders, const std::string& extension) {
  std::vector<std::filesystem::path> files;
  for (const auto& folder : folders) {
    for (const auto& entry : std::filesystem::directory_iterator(sharedDataPath(folder))) {
      if (entry.path().extension() == extension) files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  std::vector<Eigen::MatrixXd> mfcc;
  for (const auto& file : files) mfcc.push_back(animation::speechFramesOf(file).mfcc);
  return mfcc;
}

// Speech without motion, for stage 2: its MFCC frames, read once and used by every model evaluated.
struct SpeechSet {
  std::string name;
  std::vector<Eigen::MatrixXd> mfcc;
  double seconds = 0.0;
};

std::vector<SpeechSet> stageTwoSpeechSets() {
  const struct {
    const char* name;
    std::vector<std::string> folders;
    const char* extension;
  } sources[] = {{"GRID (s1 and the samples: other speakers, 81 clips)", {"grid/s1", "grid/samples"}, ".mpg"},
                 {"BEAT2 audio-only takes (the same speaker, 129 s)", {"beat2/audio_only"}, ".wav"}};
  std::vector<SpeechSet> sets;
  for (const auto& source : sources) {
    SpeechSet set{source.name, speechOnlyMfcc(source.folders, source.extension)};
    for (const auto& mfcc : set.mfcc) set.seconds += static_cast<double>(mfcc.cols()) / 30.0;
    sets.push_back(std::move(set));
  }
  return sets;
}

// Stage 2 of the paper: the audio part re-trained on speech alone (π, A, weights and the visual blocks kept).
void reportStageTwo(std::ostream& out, const animation::MouthModel& model, const animation::MouthRecording& test,
                    const std::vector<SpeechSet>& sets) {
  const Eigen::MatrixXd truth = model.basis.transform(test.visual);
  const Eigen::MatrixXd before = animation::synthesiseMouth(model, test.speech);
  printTo(out, "  %-60s ε %.3f  ρ %.3f\n", "held-out part, as trained", averageMse(before, truth),
          averageCorrelation(before, truth));
  for (const auto& set : sets) {
    std::vector<Eigen::MatrixXd> audio;
    for (const auto& mfcc : set.mfcc)
      audio.push_back(features::stackContext(mfcc, model.contextFrames, model.futureContextFrames));
    const hmm::AudioRetrainingResult retrained = hmm::retrainAudio(model.hmm, audio, {});
    animation::MouthModel adapted = model;
    adapted.hmm = retrained.model;
    const Eigen::MatrixXd after = animation::synthesiseMouth(adapted, test.speech);
    printTo(out, "  %-60s ε %.3f  ρ %.3f   (%.0f s of speech; %d joint covariances repaired)\n",
            ("re-trained on " + set.name).c_str(), averageMse(after, truth), averageCorrelation(after, truth),
            set.seconds, retrained.repairedComponents);
  }
}

// The jaw as the face will show it: FAP 3 from the predicted and from the true jaw opening, through the model's
// FAP map, on the held-out part.
void reportJawFaps(std::ostream& out, const animation::MouthModel& model, const animation::MouthRecording& test) {
  const Eigen::RowVectorXd predictedJaw =
      animation::jawOpeningOf(model, animation::synthesiseMouth(model, test.speech, {}));
  const Eigen::RowVectorXd trueJaw = test.visual.row(0);
  const Eigen::RowVectorXd predicted = animation::mouthFaps(*model.fapMap, predictedJaw).row(0);
  const Eigen::RowVectorXd truth = animation::mouthFaps(*model.fapMap, trueJaw).row(0);
  printTo(out,
          "  jaw → FAP 3 on the held-out part (inversion, conditional-mean start): correlation with the truth "
          "%.3f (jaw angle %.3f); FAP 3 1st / 50th / 99th percentile %.0f / %.0f / %.0f, the truth's %.0f / %.0f "
          "/ %.0f (true jaw %.2f° to %.2f°)\n",
          pearsonCorrelation(predicted, truth), pearsonCorrelation(predictedJaw, trueJaw), quantile(predicted, 0.01),
          quantile(predicted, 0.5), quantile(predicted, 0.99), quantile(truth, 0.01), quantile(truth, 0.5),
          quantile(truth, 0.99), trueJaw.minCoeff(), trueJaw.maxCoeff());
}

// The paper's two configurations, each trained on the training part and reported with its stage 2.
void reportPaperConfigurations(std::ostream& out, const animation::MouthRecording& train,
                               const animation::MouthRecording& test, int windowFrames) {
  const struct {
    const char* name;
    animation::MouthModelOptions options;
  } configurations[] = {
      {"full covariance, N = 4, M = 2, tc = 3", {.states = 4, .mixtures = 2, .covariance = hmm::CovarianceType::kFull}},
      {"diagonal covariance, N = 19, M = 3, tc = 3",
       {.states = 19, .mixtures = 3, .covariance = hmm::CovarianceType::kDiagonal}},
  };
  const std::vector<SpeechSet> speech = stageTwoSpeechSets();
  for (const auto& configuration : configurations) {
    const animation::MouthModel model = animation::trainMouthModel({train}, configuration.options);
    printTo(out, "\n%s (%d Baum-Welch iterations; the K components keep %.1f %% of the visual variance)\n",
            configuration.name, model.iterations, 100.0 * model.basis.explainedVariance());
    reportPart(out, "training part", model, train, windowFrames);
    reportPart(out, "held-out part", model, test, windowFrames);
    out << "  stage 2, audio re-trained on speech only (inversion, conditional-mean start):\n";
    reportStageTwo(out, model, test, speech);
  }
  out << "\nThe paper's own best, on its own data: full N = 4, M = 2: ε = 0.47, ρ = 0.75; diagonal N = 19, "
         "M = 3: ε = 0.47, ρ = 0.76.\n";
}

}  // namespace

void reportBeat2Mouth(const Beat2MouthReportOptions& options, std::ostream& out) {
  const auto [train, test] = animation::splitByTime(loadBeat2Mouth(), options.trainingFraction);
  // A bad model file fails before anything is written.
  const std::optional<animation::MouthModel> given =
      options.model.empty() ? std::nullopt : std::optional(animation::loadMouthModel(options.model));
  printTo(out,
          "Mouth from audio on BEAT2: trained on the first %d frames, held out the last %d (%.1f s). Visual: "
          "K = 2 ICA-after-PCA components of [jaw opening, 100 expression coefficients]; audio: 11 MFCC with "
          "±tc frames of context. ε = AMSE normalised by the truth's variance (mean prediction: 1), ρ = ACC.\n",
          train.numFrames(), test.numFrames(), test.numFrames() / test.framesPerSecond);
  if (!given) {
    reportPaperConfigurations(out, train, test, options.windowFrames);
    return;
  }
  printTo(out, "\n%s: %d states, tc = %d\n", options.model.c_str(), given->hmm.numStates(), given->contextFrames);
  reportPart(out, "training part", *given, train, options.windowFrames);
  reportPart(out, "held-out part", *given, test, options.windowFrames);
  if (given->fapMap) reportJawFaps(out, *given, test);
}

void sweepBeat2Mouth(const Beat2MouthSweepOptions& options, std::ostream& out,
                     const std::function<void(std::size_t, std::size_t)>& progress) {
  const auto [train, test] = animation::splitByTime(loadBeat2Mouth(), options.trainingFraction);
  // Choices are made on the last fifth of the training part, fitted on the rest; the held-out part is only
  // reported.
  const auto [fit, validation] = animation::splitByTime(train, 0.8);
  const MouthSweepGrid& grid = options.grid;
  const std::size_t total = grid.covariances.size() * grid.contexts.size() * grid.mixtures.size() * grid.states.size();
  printTo(out, "sweep: %zu models, fitted on %d frames, chosen on %d, reported on the held-out %d\n", total,
          fit.numFrames(), validation.numFrames(), test.numFrames());
  const std::vector<MouthSweepPoint> points = sweepMouthModels(grid, fit, validation, test, progress);

  std::filesystem::create_directories(options.output);
  const std::filesystem::path csv = options.output / "mouth_sweep.csv";
  writeMouthSweepCsv(csv, points);
  for (hmm::CovarianceType type : {hmm::CovarianceType::kFull, hmm::CovarianceType::kDiagonal}) {
    int failed = 0;
    const MouthSweepPoint* best = bestOnValidation(points, type, &failed);
    if (best == nullptr) continue;
    printTo(out,
            "%s covariance: chosen on validation N = %d, M = %d, tc = %d (validation ε %.3f, ρ %.3f) -> held-out "
            "ε %.3f, ρ %.3f%s\n",
            sweepCovarianceName(type), best->states, best->mixtures, best->contextFrames, best->validationEpsilon,
            best->validationRho, best->heldOutEpsilon, best->heldOutRho,
            failed ? (", " + std::to_string(failed) + " models could not be trained").c_str() : "");
    plotSweep(options.output, csv, type, best->contextFrames, grid.mixtures);
  }
  printTo(out, "wrote %s and the plots beside it\n", csv.string().c_str());
}

void trainBeat2MouthModel(const std::filesystem::path& output, const animation::MouthModelOptions& options,
                          double trainingFraction, std::ostream& log) {
  checkOutputTarget(output);
  const auto [train, test] = animation::splitByTime(loadBeat2Mouth(), trainingFraction);
  const auto start = std::chrono::steady_clock::now();
  animation::MouthModel model = animation::trainMouthModel({train}, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The jaw's geometry and the lip pattern come from the reference face (fap_mapping.h).
  model.fapMap = animation::defineMouthFapMap(face::loadIctFace(face::ictFaceDirectory()));
  animation::saveMouthModel(output, model, options);
  printTo(log, "mouth model: %d states x %d mixtures, tc = %d, trained on %d frames in %.1f s; wrote %s\n",
          model.hmm.numStates(), options.mixtures, model.contextFrames, train.numFrames(), seconds, output.c_str());
}

}  // namespace th::eval
