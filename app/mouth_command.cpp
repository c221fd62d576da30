// `talkinghead eval mouth`: the audio → mouth AV-HMM on BEAT2, trained on the first part of the take and
// measured by the paper's ε and ρ on both parts, per synthesis method, beside baselines.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "animation/mouth_data.h"
#include "animation/mouth_model.h"
#include "animation/time_split.h"
#include "cli_options.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "core/statistics.h"
#include "core/subprocess.h"
#include "eval/mouth_corpus.h"
#include "eval/mouth_evaluation.h"
#include "eval/mouth_sweep.h"
#include "face/feature_points.h"
#include "hmm/audio_retraining.h"
#include "mouth_corpus_command.h"

namespace th::app {
namespace {

struct MouthArguments {
  std::string model;  // eval: evaluate this model file instead of the two built-in configurations
  std::string modelOutput = "models/mouth.json";  // train
  animation::MouthModelOptions options{.states = 5,
                                       .mixtures = 2,
                                       .covariance = hmm::CovarianceType::kFull,
                                       .contextFrames = 2};  // what the sweep chose on validation data
  double trainingFraction = 0.75;
  int windowFrames = 30;
  bool sweep = false;
  std::string states = "3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20";
  std::string mixtures = "1,2,3,7";
  std::string contexts = "2,3,4,5";
  std::string covariances = "full,diag";
  std::string output = "docs/mouth_sweep";
  int iterations = 30;
};

std::vector<int> integerList(const std::string& text, const std::string& option) {
  std::vector<int> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stoi(item, &used));
      if (used != item.size() || values.back() < 1) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error(option + ": \"" + item + "\" is not a positive integer");
    }
  }
  if (values.empty()) throw Error(option + ": empty list");
  return values;
}

// The same frames, shifted by half their length (animation/time_split.h's baseline), level and MFCCs together.
animation::SpeechFrames anotherSegment(const animation::SpeechFrames& speech) {
  Eigen::MatrixXd both(speech.mfcc.rows() + 1, speech.mfcc.cols());
  both << speech.mfcc, speech.levelDb;
  const Eigen::MatrixXd shifted = animation::anotherSegment(both);
  return {shifted.topRows(speech.mfcc.rows()), shifted.bottomRows(1)};
}

void printRow(const std::string& name, const Eigen::MatrixXd& estimate, const Eigen::MatrixXd& truth, int iterations) {
  std::printf("  %-52s %6.3f  %6.3f", name.c_str(), eval::averageMse(estimate, truth),
              eval::averageCorrelation(estimate, truth));
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
  const Eigen::MatrixXd mean =
      animation::synthesiseMouth(model, part.speech, {.start = hmm::InversionStart::kConditionalMean}, &iterations);
  printRow("inversion, conditional-mean start (ours)", mean, truth, iterations);
  const Eigen::MatrixXd random =
      animation::synthesiseMouth(model, part.speech, {.start = hmm::InversionStart::kRandom}, &iterations);
  printRow("inversion, random start (paper)", random, truth, iterations);
  const Eigen::MatrixXd windowed =
      animation::synthesiseMouth(model, part.speech, {.windowFrames = window}, &iterations);
  printRow("inversion, windows of " + std::to_string(window) + " frames (streaming)", windowed, truth, iterations);
  printRow("MMSE estimate", animation::synthesiseMouth(model, part.speech, {.method = MouthMethod::kMmse}), truth, 0);
  // The training data's mean: the components are zero-mean there by construction.
  printRow("baseline: mean prediction (the training mean)", Eigen::MatrixXd::Zero(truth.rows(), truth.cols()), truth,
           0);
  printRow("baseline: inversion of another segment's audio",
           animation::synthesiseMouth(model, anotherSegment(part.speech), {}), truth, 0);
}

const char* covarianceName(hmm::CovarianceType type) {
  return type == hmm::CovarianceType::kFull ? "full" : "diag";
}

// Fig. 3 of the paper: ε and ρ on the held-out part against N, one curve per M, at the context tc chosen on the
// validation data; one PNG per covariance type, drawn by gnuplot.
void plotSweep(const std::filesystem::path& folder, const std::filesystem::path& csv, hmm::CovarianceType covariance,
               int contextFrames, const std::vector<int>& mixtures) {
  const std::string name = covarianceName(covariance);
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

void runSweep(const MouthArguments& arguments, const animation::MouthRecording& train,
              const animation::MouthRecording& test) {
  if (!programExists("gnuplot"))
    throw Error("eval mouth --sweep: gnuplot is not installed (scripts/setup.sh installs it)");
  // Choices are made on the last fifth of the training part, fitted on the rest; the held-out part is only
  // reported.
  const auto [fit, validation] = animation::splitByTime(train, 0.8);
  eval::MouthSweepGrid grid{.covariances = {},
                            .contexts = integerList(arguments.contexts, "--contexts"),
                            .mixtures = integerList(arguments.mixtures, "--mixtures"),
                            .states = integerList(arguments.states, "--states"),
                            .iterations = arguments.iterations};
  std::stringstream covariances(arguments.covariances);
  std::string covariance;
  while (std::getline(covariances, covariance, ',')) {
    if (covariance != "full" && covariance != "diag")
      throw Error("--covariances: \"" + covariance + "\" is not full or diag");
    grid.covariances.push_back(covariance == "full" ? hmm::CovarianceType::kFull : hmm::CovarianceType::kDiagonal);
  }
  const std::size_t total = grid.covariances.size() * grid.contexts.size() * grid.mixtures.size() * grid.states.size();
  std::printf("sweep: %zu models, fitted on %d frames, chosen on %d, reported on the held-out %d\n", total,
              fit.numFrames(), validation.numFrames(), test.numFrames());
  const bool terminal = isatty(fileno(stderr)) != 0;
  const std::vector<eval::MouthSweepPoint> points =
      eval::sweepMouthModels(grid, fit, validation, test, [terminal](std::size_t done, std::size_t all) {
        if (terminal) std::fprintf(stderr, "\r  %zu / %zu models", done, all);
      });
  if (terminal) std::fprintf(stderr, "\n");

  std::filesystem::create_directories(arguments.output);
  const std::filesystem::path csv = std::filesystem::path(arguments.output) / "mouth_sweep.csv";
  eval::writeMouthSweepCsv(csv, points);
  for (hmm::CovarianceType type : {hmm::CovarianceType::kFull, hmm::CovarianceType::kDiagonal}) {
    int failed = 0;
    const eval::MouthSweepPoint* best = eval::bestOnValidation(points, type, &failed);
    if (best == nullptr) continue;
    std::printf(
        "%s covariance: chosen on validation N = %d, M = %d, tc = %d (validation ε %.3f, ρ %.3f) -> held-out "
        "ε %.3f, ρ %.3f%s\n",
        covarianceName(type), best->states, best->mixtures, best->contextFrames, best->validationEpsilon,
        best->validationRho, best->heldOutEpsilon, best->heldOutRho,
        failed ? (", " + std::to_string(failed) + " models could not be trained").c_str() : "");
    plotSweep(arguments.output, csv, type, best->contextFrames, grid.mixtures);
  }
  std::printf("wrote %s and the plots beside it\n", csv.string().c_str());
}

// The MFCC frames of every recording in the shared folders named (files with the extension given).
std::vector<Eigen::MatrixXd> speechOnly(const std::vector<std::string>& folders, const std::string& extension) {
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

std::vector<SpeechSet> speechSets() {
  const struct {
    const char* name;
    std::vector<std::string> folders;
    const char* extension;
  } sources[] = {{"GRID (s1 and the samples: other speakers, 81 clips)", {"grid/s1", "grid/samples"}, ".mpg"},
                 {"BEAT2 audio-only takes (the same speaker, 129 s)", {"beat2/audio_only"}, ".wav"}};
  std::vector<SpeechSet> sets;
  for (const auto& source : sources) {
    SpeechSet set{source.name, speechOnly(source.folders, source.extension)};
    for (const auto& mfcc : set.mfcc) set.seconds += static_cast<double>(mfcc.cols()) / 30.0;
    sets.push_back(std::move(set));
  }
  return sets;
}

// Stage 2 of the paper: the audio part re-trained on speech alone (π, A, weights and the visual blocks kept).
void runStage2(const animation::MouthModel& model, const animation::MouthRecording& test,
               const std::vector<SpeechSet>& sets) {
  const Eigen::MatrixXd truth = model.basis.transform(test.visual);
  const Eigen::MatrixXd before = animation::synthesiseMouth(model, test.speech);
  std::printf("  %-60s ε %.3f  ρ %.3f\n", "held-out part, as trained", eval::averageMse(before, truth),
              eval::averageCorrelation(before, truth));
  for (const auto& set : sets) {
    std::vector<Eigen::MatrixXd> audio;
    for (const auto& mfcc : set.mfcc)
      audio.push_back(features::stackContext(mfcc, model.contextFrames, model.futureContextFrames));
    const hmm::AudioRetrainingResult retrained = hmm::retrainAudio(model.hmm, audio, {});
    animation::MouthModel adapted = model;
    adapted.hmm = retrained.model;
    const Eigen::MatrixXd after = animation::synthesiseMouth(adapted, test.speech);
    std::printf("  %-60s ε %.3f  ρ %.3f   (%.0f s of speech; %d joint covariances repaired)\n",
                ("re-trained on " + set.name).c_str(), eval::averageMse(after, truth),
                eval::averageCorrelation(after, truth), set.seconds, retrained.repairedComponents);
  }
}

// The jaw as the face will show it: FAP 3 from the predicted and from the true jaw opening, through the model's
// FAP map, on the held-out part.
void reportJawFaps(const animation::MouthModel& model, const animation::MouthRecording& test) {
  const Eigen::RowVectorXd predictedJaw =
      animation::jawOpeningOf(model, animation::synthesiseMouth(model, test.speech, {}));
  const Eigen::RowVectorXd trueJaw = test.visual.row(0);
  const Eigen::RowVectorXd predicted = animation::mouthFaps(*model.fapMap, predictedJaw).row(0);
  const Eigen::RowVectorXd truth = animation::mouthFaps(*model.fapMap, trueJaw).row(0);
  std::printf(
      "  jaw → FAP 3 on the held-out part (inversion, conditional-mean start): correlation with the truth "
      "%.3f (jaw angle %.3f); FAP 3 1st / 50th / 99th percentile %.0f / %.0f / %.0f, the truth's %.0f / %.0f "
      "/ %.0f (true jaw %.2f° to %.2f°)\n",
      pearsonCorrelation(predicted, truth), pearsonCorrelation(predictedJaw, trueJaw), quantile(predicted, 0.01),
      quantile(predicted, 0.5), quantile(predicted, 0.99), quantile(truth, 0.01), quantile(truth, 0.5),
      quantile(truth, 0.99), trueJaw.minCoeff(), trueJaw.maxCoeff());
}

void runEvalMouth(const MouthArguments& arguments) {
  const auto [train, test] = animation::splitByTime(eval::loadBeat2Mouth(), arguments.trainingFraction);
  if (arguments.sweep) {
    runSweep(arguments, train, test);
    return;
  }
  // A bad model file fails before anything is printed.
  const std::optional<animation::MouthModel> given =
      arguments.model.empty() ? std::nullopt : std::optional(animation::loadMouthModel(arguments.model));
  std::printf(
      "Mouth from audio on BEAT2: trained on the first %d frames, held out the last %d (%.1f s). Visual: "
      "K = 2 ICA-after-PCA components of [jaw opening, 100 expression coefficients]; audio: 11 MFCC with "
      "±tc frames of context. ε = AMSE normalised by the truth's variance (mean prediction: 1), ρ = ACC.\n",
      train.numFrames(), test.numFrames(), test.numFrames() / test.framesPerSecond);
  if (given) {
    std::printf("\n%s: %d states, tc = %d\n", arguments.model.c_str(), given->hmm.numStates(), given->contextFrames);
    evaluatePart("training part", *given, train, arguments.windowFrames);
    evaluatePart("held-out part", *given, test, arguments.windowFrames);
    if (given->fapMap) reportJawFaps(*given, test);
    return;
  }
  const struct {
    const char* name;
    animation::MouthModelOptions options;
  } configurations[] = {
      {"full covariance, N = 4, M = 2, tc = 3", {.states = 4, .mixtures = 2, .covariance = hmm::CovarianceType::kFull}},
      {"diagonal covariance, N = 19, M = 3, tc = 3",
       {.states = 19, .mixtures = 3, .covariance = hmm::CovarianceType::kDiagonal}},
  };
  const std::vector<SpeechSet> speech = speechSets();
  for (const auto& configuration : configurations) {
    const animation::MouthModel model = animation::trainMouthModel({train}, configuration.options);
    std::printf("\n%s (%d Baum-Welch iterations; the K components keep %.1f %% of the visual variance)\n",
                configuration.name, model.iterations, 100.0 * model.basis.explainedVariance());
    evaluatePart("training part", model, train, arguments.windowFrames);
    evaluatePart("held-out part", model, test, arguments.windowFrames);
    std::printf("  stage 2, audio re-trained on speech only (inversion, conditional-mean start):\n");
    runStage2(model, test, speech);
  }
  std::printf(
      "\nThe paper's own best, on its own data: full N = 4, M = 2: ε = 0.47, ρ = 0.75; diagonal N = 19, "
      "M = 3: ε = 0.47, ρ = 0.76.\n");
}

// `eval mouth --recipe-NAME`: the default recipe's knobs (mouth_corpus_command.h), to measure its variants on the
// same clips (docs/mouth.md).
void visitRecipe(MouthCorpusArguments& recipe, OptionVisitor& v) {
  animation::MouthModelOptions& model = recipe.model;
  v.option(model.states, {.name = "recipe-states", .help = "Hidden states N", .min = 1, .max = 64});
  v.option(model.mixtures, {.name = "recipe-mixtures", .help = "Gaussians per state M", .min = 1, .max = 16});
  v.option(model.contextFrames, {.name = "recipe-context",
                                 .help = "MFCC context tc: frames each side of the frame heard",
                                 .unit = "frames",
                                 .min = 0,
                                 .max = 10});
  v.option(model.futureContextFrames, {.name = "recipe-future-context",
                                       .help = "MFCC context after the frame heard (-1: as --recipe-context)",
                                       .unit = "frames",
                                       .min = -1,
                                       .max = 10});
  v.option(model.visualComponents,
           {.name = "recipe-components", .help = "Visual components K (PCA of the mouth's FAPs)", .min = 1, .max = 16});
  v.option(model.visualDeltas,
           {.name = "recipe-deltas", .help = "the visual components' deltas and the trajectory made from them (MLPG)"});
  v.option(model.varianceValidationEvery,
           {.name = "recipe-gv-every",
            .help = "Global variance compensation: every N-th training clip held out to measure the spread (0: none)",
            .min = 0,
            .max = 100});
  v.option(model.normaliseSpeech, {.name = "recipe-normalise",
                                   .help = "the speech normaliser (running cepstral mean, level against its peak)"});
  v.option(model.normalisation.meanSeconds, {.name = "recipe-mean-seconds",
                                             .help = "The running cepstral mean's time constant",
                                             .unit = "s",
                                             .min = 0.1,
                                             .max = 600});
  v.option(model.normalisation.peakDecayDbPerSecond, {.name = "recipe-peak-decay",
                                                      .help = "How fast the level's reference peak falls",
                                                      .unit = "dB/s",
                                                      .min = 0.01,
                                                      .max = 100});
  v.option(model.maxIterations,
           {.name = "recipe-iterations", .help = "Baum-Welch iterations at most", .min = 1, .max = 1000});
  v.option(recipe.recipeDiagonal, {.name = "recipe-diagonal", .help = "Diagonal covariances instead of full ones"});
  v.option(recipe.recipeInversion,
           {.name = "recipe-inversion", .help = "Synthesis by HMM inversion (EM) instead of the MMSE estimate"});
  v.option(recipe.synthesis.trajectory,
           {.name = "recipe-trajectory", .help = "the MLPG trajectory from the MMSE estimate's Gaussians"});
  v.option(recipe.synthesis.windowFrames, {.name = "recipe-window",
                                           .help = "Frames per decoding window, as live decodes (0: the whole clip)",
                                           .unit = "frames",
                                           .min = 0,
                                           .max = 10000});
  v.option(recipe.stageTwo,
           {.name = "recipe-stage2", .help = "Stage 2: the audio side re-trained on speech-only recordings"});
  v.option(recipe.otherSpeakerWeight,
           {.name = "recipe-other-weight",
            .help = "How many times each clip of a speaker other than GRID's s1 counts in training",
            .min = 1,
            .max = 100});
}

}  // namespace

void runTrainMouth(const MouthArguments& arguments) {
  checkOutputTarget(arguments.modelOutput);
  const auto [train, test] = animation::splitByTime(eval::loadBeat2Mouth(), arguments.trainingFraction);
  const auto start = std::chrono::steady_clock::now();
  animation::MouthModel model = animation::trainMouthModel({train}, arguments.options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The jaw's geometry and the lip pattern come from the reference face (fap_mapping.h).
  model.fapMap = animation::defineMouthFapMap(face::loadIctFace(face::ictFaceDirectory()));
  animation::saveMouthModel(arguments.modelOutput, model, arguments.options);
  std::fprintf(stderr, "mouth model: %d states x %d mixtures, tc = %d, trained on %d frames in %.1f s; wrote %s\n",
               model.hmm.numStates(), arguments.options.mixtures, model.contextFrames, train.numFrames(), seconds,
               arguments.modelOutput.c_str());
}

void addTrainMouthCommand(CLI::App& train) {
  auto arguments = std::make_shared<MouthArguments>();
  auto corpus = std::make_shared<MouthCorpusArguments>();
  auto beat2 = std::make_shared<bool>(false);
  CLI::App* mouth = train.add_subcommand(
      "mouth",
      "Audio -> mouth model from the shared talking videos (GRID s1, StyleTalk), the default; --beat2: the "
      "paper's model from BEAT2's FLAME fits");
  mouth->add_option("-o,--output", arguments->modelOutput, "Model file to write (default models/mouth.json)");
  mouth->add_option(
      "--tracks", corpus->tracks,
      "Folder of the clips' tracks, made on first use (default: " + std::string(kMouthTrackFolderHelp) + ")");
  CLI::Option* states = mouth->add_option("--states", corpus->model.states, "States N (default 8; 16 with --diagonal)")
                            ->check(CLI::Range(1, 100));
  CLI::Option* mixtures =
      mouth->add_option("--mixtures", corpus->model.mixtures, "Gaussians per state M (default 2; 3 with --diagonal)")
          ->check(CLI::Range(1, 20));
  mouth->add_option("--context", corpus->model.contextFrames, "MFCC context tc (frames either side)")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  mouth
      ->add_option("--future-context", corpus->model.futureContextFrames,
                   "MFCC context after each frame, if not tc (0: a live model that waits for no later frame)")
      ->check(CLI::Range(0, 10));
  mouth->add_option("--components", corpus->model.visualComponents, "Visual components K")
      ->check(CLI::Range(1, 21))
      ->capture_default_str();
  mouth->add_flag_function(
      "--diagonal",
      [arguments, corpus](std::int64_t) {
        arguments->options.covariance = hmm::CovarianceType::kDiagonal;
        corpus->model.covariance = hmm::CovarianceType::kDiagonal;
      },
      "Diagonal covariance (default full)");
  mouth->add_option("--stage2", corpus->stageTwo, "Re-train the audio side on speech-only voices (stage 2)")
      ->capture_default_str();
  mouth->add_option("--corpus", corpus->corpora,
                    "A folder of talking clips to train on, FOLDER or FOLDER=SPEAKER (repeatable; default: the shared "
                    "GRID s1 and StyleTalk folders)");
  mouth->add_flag("--beat2", *beat2, "The paper's model: BEAT2's FLAME fits (the first --train-fraction of the take)")
      ->group("BEAT2");
  mouth
      ->add_option("--train-fraction", arguments->trainingFraction,
                   "--beat2: the first this fraction of the take trains")
      ->check(CLI::Range(0.1, 0.95))
      ->group("BEAT2");
  mouth->add_option("--beat2-states", arguments->options.states, "--beat2: states N (default 5, the sweep's choice)")
      ->check(CLI::Range(1, 100))
      ->group("BEAT2");
  mouth->add_option("--beat2-mixtures", arguments->options.mixtures, "--beat2: Gaussians per state M (default 2)")
      ->check(CLI::Range(1, 20))
      ->group("BEAT2");
  mouth->add_option("--beat2-context", arguments->options.contextFrames, "--beat2: MFCC context tc (default 2)")
      ->check(CLI::Range(0, 10))
      ->group("BEAT2");
  mouth->callback([arguments, corpus, beat2, states, mixtures] {
    if (*beat2) {
      runTrainMouth(*arguments);
      return;
    }
    // Diagonal Gaussians each hold less: more of them (as the paper's best diagonal model, N = 19, M = 3).
    if (corpus->model.covariance == hmm::CovarianceType::kDiagonal) {
      if (states->count() == 0) corpus->model.states = 16;
      if (mixtures->count() == 0) corpus->model.mixtures = 3;
    }
    runTrainMouthCorpora(*corpus, arguments->modelOutput);
  });
}

void addEvalMouthCommand(CLI::App& eval) {
  auto arguments = std::make_shared<MouthArguments>();
  auto corpus = std::make_shared<MouthCorpusArguments>();
  auto beat2 = std::make_shared<bool>(false);
  CLI::App* mouth = eval.add_subcommand(
      "mouth",
      "Mouth from audio: the default recipe on held-out GRID clips and StyleTalk speakers left out, beside "
      "baselines (--beat2: the paper's evaluation on BEAT2)");
  mouth->add_flag("--beat2", *beat2,
                  "The paper's ε and ρ on BEAT2 per synthesis method, beside baselines (and --sweep)");
  mouth->add_option("--tracks", corpus->tracks,
                    "Folder of the clips' tracks (default: " + std::string(kMouthTrackFolderHelp) + ")");
  mouth->add_option("--compare", corpus->compare, "Other mouth model files to judge on the same clips");
  mouth->add_option("--multilingual", corpus->multilingual,
                    "Folder of phone-aligned speech in other languages (tools/multilingual_speech.py; default: made "
                    "in the cache on first use)");
  addOptionsFrom(
      *mouth, [corpus](OptionVisitor& v) { visitRecipe(*corpus, v); }, "Recipe");
  mouth
      ->add_option("--train-fraction", arguments->trainingFraction,
                   "The first this fraction of the BEAT2 take trains, the rest is held out")
      ->check(CLI::Range(0.1, 0.95));
  mouth->add_option("--window-frames,--window", arguments->windowFrames, "Frames per window of the streaming inversion")
      ->check(CLI::Range(1, 10000));
  mouth->add_option("--model", arguments->model, "Evaluate this mouth model instead of the two built-in ones");
  mouth->add_flag("--sweep", arguments->sweep,
                  "Sweep N, M, tc and covariance (fitted on the first 80 % of the training part, chosen on the rest, "
                  "reported on the held-out part); writes a CSV and PNG plots like the paper's Fig. 3");
  mouth->add_option("--states", arguments->states, "Sweep: states N, comma-separated")->group("Sweep");
  mouth->add_option("--mixtures", arguments->mixtures, "Sweep: mixtures M")->group("Sweep");
  mouth->add_option("--contexts", arguments->contexts, "Sweep: MFCC context tc")->group("Sweep");
  mouth->add_option("--covariances", arguments->covariances, "Sweep: full,diag")->group("Sweep");
  mouth->add_option("--iterations", arguments->iterations, "Sweep: maximum Baum-Welch iterations")
      ->check(CLI::Range(1, 1000))
      ->group("Sweep");
  mouth->add_option("--output", arguments->output, "Sweep: folder for the CSV and the plots")->group("Sweep");
  mouth->callback([arguments, corpus, beat2] {
    if (*beat2) {
      runEvalMouth(*arguments);
      return;
    }
    if (corpus->recipeDiagonal) corpus->model.covariance = hmm::CovarianceType::kDiagonal;
    if (corpus->recipeInversion) corpus->synthesis.method = animation::MouthMethod::kInversion;
    runEvalMouthCorpora(*corpus);
  });
}

}  // namespace th::app
