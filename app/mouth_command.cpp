// `talkinghead train mouth` and `talkinghead eval mouth`: their options. The default models come from tracked
// talking video (eval/mouth_corpus_report.h); with --beat2, the paper's model on BEAT2 (eval/beat2_mouth_report.h).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "animation/mouth_model.h"
#include "cli_options.h"
#include "commands.h"
#include "core/error.h"
#include "core/subprocess.h"
#include "eval/beat2_mouth_report.h"
#include "eval/mouth_corpus_report.h"

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

// The default models' arguments: the recipe (eval/mouth_protocol.h's MouthRecipe, whose defaults are the
// shipped model's), where the tracks are kept and what else `eval mouth` judges.
struct MouthCorpusArguments {
  eval::MouthRecipe recipe;
  std::string tracks;  // empty: eval::defaultMouthTrackFolder()
  // train: folders of talking clips, "FOLDER" or "FOLDER=SPEAKER" (eval/talking_corpus.h); empty: the shared
  // corpora (sharedTalkingFolders), GRID s1's every fifth clip held out.
  std::vector<std::string> corpora;
  std::vector<std::string> compare;  // eval: other model files judged on the same clips
  std::string multilingual;          // eval: the folder tools/multilingual_speech.py made; empty: made in the cache
  // eval: set recipe.model.covariance and recipe.synthesis.method when parsed (`--recipe-diagonal`,
  // `--recipe-inversion`).
  bool recipeDiagonal = false;
  bool recipeInversion = false;
};

// The multilingual folder: made by the tool on first use.
std::filesystem::path multilingualFolder(const std::string& given) {
  if (!given.empty()) return given;
  const std::filesystem::path folder = eval::userCacheFolder() / "multilingual";
  std::error_code missing;
  if (!std::filesystem::is_regular_file(folder / "index.csv", missing)) {
    const std::string tool = std::string(TALKINGHEAD_SOURCE_DIR) + "/tools/multilingual_speech.py";
    std::fprintf(stderr, "making the multilingual test speech: %s -o %s\n", tool.c_str(), folder.c_str());
    runProgram({"/usr/bin/python3", tool, "-o", folder.string()});
  }
  return folder;
}

void runEvalMouthCorpora(const MouthCorpusArguments& arguments) {
  eval::MouthCorpusReportOptions options;
  options.recipe = arguments.recipe;
  for (const std::string& file : arguments.compare)
    options.compared.emplace_back(file, animation::loadMouthModel(file));
  options.languages = multilingualFolder(arguments.multilingual);
  options.tracks = arguments.tracks;
  eval::reportMouthOnTalkingCorpora(options, std::cout, std::cerr);
}

void runTrainMouthCorpora(const MouthCorpusArguments& arguments, const std::string& output) {
  eval::MouthCorpusTraining training;
  training.recipe = arguments.recipe;
  training.tracks = arguments.tracks;
  training.output = output;
  for (const std::string& corpus : arguments.corpora) {
    const std::size_t equals = corpus.find('=');
    training.folders.push_back(
        {corpus.substr(0, equals), equals == std::string::npos ? std::string() : corpus.substr(equals + 1)});
  }
  eval::trainMouthOnTalkingCorpora(training, std::cerr);
}

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

// `eval mouth --beat2 --sweep`: the grid from the lists given, the progress on a terminal's stderr.
void runSweep(const MouthArguments& arguments) {
  if (!programExists("gnuplot"))
    throw Error("eval mouth --sweep: gnuplot is not installed (scripts/setup.sh installs it)");
  eval::Beat2MouthSweepOptions sweep{.grid = {.covariances = {},
                                              .contexts = integerList(arguments.contexts, "--contexts"),
                                              .mixtures = integerList(arguments.mixtures, "--mixtures"),
                                              .states = integerList(arguments.states, "--states"),
                                              .iterations = arguments.iterations},
                                     .output = arguments.output,
                                     .trainingFraction = arguments.trainingFraction};
  std::stringstream covariances(arguments.covariances);
  std::string covariance;
  while (std::getline(covariances, covariance, ',')) {
    if (covariance != "full" && covariance != "diag")
      throw Error("--covariances: \"" + covariance + "\" is not full or diag");
    sweep.grid.covariances.push_back(covariance == "full" ? hmm::CovarianceType::kFull
                                                          : hmm::CovarianceType::kDiagonal);
  }
  const bool terminal = isatty(fileno(stderr)) != 0;
  eval::sweepBeat2Mouth(sweep, std::cout, [terminal](std::size_t done, std::size_t all) {
    if (terminal) std::fprintf(stderr, "\r  %zu / %zu models", done, all);
  });
  if (terminal) std::fprintf(stderr, "\n");
}

// `eval mouth --recipe-NAME`: the default recipe's knobs (eval/mouth_corpus_report.h), to measure its variants on the
// same clips (docs/mouth.md).
void visitRecipe(MouthCorpusArguments& arguments, OptionVisitor& v) {
  eval::MouthRecipe& recipe = arguments.recipe;
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
  v.option(arguments.recipeDiagonal, {.name = "recipe-diagonal", .help = "Diagonal covariances instead of full ones"});
  v.option(arguments.recipeInversion,
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
      "Folder of the clips' tracks, made on first use (default: " + std::string(eval::kMouthTrackFolderHelp) + ")");
  CLI::Option* states =
      mouth->add_option("--states", corpus->recipe.model.states, "States N (default 8; 16 with --diagonal)")
          ->check(CLI::Range(1, 100));
  CLI::Option* mixtures = mouth
                              ->add_option("--mixtures", corpus->recipe.model.mixtures,
                                           "Gaussians per state M (default 2; 3 with --diagonal)")
                              ->check(CLI::Range(1, 20));
  mouth->add_option("--context", corpus->recipe.model.contextFrames, "MFCC context tc (frames either side)")
      ->check(CLI::Range(0, 10))
      ->capture_default_str();
  mouth
      ->add_option("--future-context", corpus->recipe.model.futureContextFrames,
                   "MFCC context after each frame, if not tc (0: a live model that waits for no later frame)")
      ->check(CLI::Range(0, 10));
  mouth->add_option("--components", corpus->recipe.model.visualComponents, "Visual components K")
      ->check(CLI::Range(1, 21))
      ->capture_default_str();
  mouth->add_flag_function(
      "--diagonal",
      [arguments, corpus](std::int64_t) {
        arguments->options.covariance = hmm::CovarianceType::kDiagonal;
        corpus->recipe.model.covariance = hmm::CovarianceType::kDiagonal;
      },
      "Diagonal covariance (default full)");
  mouth->add_option("--stage2", corpus->recipe.stageTwo, "Re-train the audio side on speech-only voices (stage 2)")
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
      eval::trainBeat2MouthModel(arguments->modelOutput, arguments->options, arguments->trainingFraction, std::cerr);
      return;
    }
    // Diagonal Gaussians each hold less: more of them (as the paper's best diagonal model, N = 19, M = 3).
    if (corpus->recipe.model.covariance == hmm::CovarianceType::kDiagonal) {
      if (states->count() == 0) corpus->recipe.model.states = 16;
      if (mixtures->count() == 0) corpus->recipe.model.mixtures = 3;
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
                    "Folder of the clips' tracks (default: " + std::string(eval::kMouthTrackFolderHelp) + ")");
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
    if (*beat2 && arguments->sweep) {
      runSweep(*arguments);
      return;
    }
    if (*beat2) {
      eval::reportBeat2Mouth({.model = arguments->model,
                              .trainingFraction = arguments->trainingFraction,
                              .windowFrames = arguments->windowFrames},
                             std::cout);
      return;
    }
    if (corpus->recipeDiagonal) corpus->recipe.model.covariance = hmm::CovarianceType::kDiagonal;
    if (corpus->recipeInversion) corpus->recipe.synthesis.method = animation::MouthMethod::kInversion;
    runEvalMouthCorpora(*corpus);
  });
}

}  // namespace th::app
