// `talkinghead hmm train|info|decode|invert`: the HMM engine from the command line, on CSV files.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "core/error.h"
#include "core/json_reading.h"
#include "core/numeric_csv.h"
#include "hmm/entropic_training.h"
#include "hmm/forward_backward.h"
#include "hmm/inversion.h"
#include "hmm/model_file.h"
#include "hmm/training.h"
#include "hmm/viterbi.h"

namespace th::app {
namespace {

// Rows of `table` split into sequences by its `seq` column (a new sequence wherever the value changes), with
// the observation taken from `columns` in that order (d x T per sequence).
std::vector<Eigen::MatrixXd> sequencesOf(const NumericTable& table, const std::vector<int>& columns) {
  const int seq = table.findColumn("seq");
  std::vector<Eigen::MatrixXd> sequences;
  std::vector<std::vector<double>> current;
  auto flush = [&] {
    if (current.empty()) return;
    Eigen::MatrixXd frames(static_cast<Eigen::Index>(columns.size()), static_cast<Eigen::Index>(current.size()));
    for (size_t t = 0; t < current.size(); ++t) {
      for (size_t k = 0; k < columns.size(); ++k) {
        frames(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(t)) =
            current[t][static_cast<size_t>(columns[k])];
      }
    }
    sequences.push_back(std::move(frames));
    current.clear();
  };
  for (size_t r = 0; r < table.rows.size(); ++r) {
    if (seq >= 0 && r > 0 && table.rows[r][static_cast<size_t>(seq)] != table.rows[r - 1][static_cast<size_t>(seq)])
      flush();
    current.push_back(table.rows[r]);
  }
  flush();
  return sequences;
}

std::vector<std::string> splitNames(const std::string& list) {
  std::vector<std::string> names;
  std::stringstream stream(list);
  std::string name;
  while (std::getline(stream, name, ',')) {
    if (!name.empty()) names.push_back(name);
  }
  return names;
}

struct TrainArguments {
  std::string data;
  std::string output;
  int states = 8;
  int mixtures = 1;
  std::string covariance = "full";
  double entropic = 0.0;
  double covariancePrior = 0.0;
  int warmup = 0;
  int ramp = 0;
  int mergeCandidates = 8;
  bool noTrim = false;
  int iterations = 100;
  unsigned seed = 1;
  std::string visualColumns;
};

void runTrain(const TrainArguments& arguments) {
  const NumericTable table = readNumericCsv(arguments.data);
  const std::vector<std::string> visual = splitNames(arguments.visualColumns);
  std::vector<std::string> audio;
  for (const auto& name : table.columns) {
    if (name != "seq" && name != "time_s" && std::find(visual.begin(), visual.end(), name) == visual.end()) {
      audio.push_back(name);
    }
  }
  std::vector<std::string> names = audio;
  names.insert(names.end(), visual.begin(), visual.end());
  std::vector<int> columns;
  for (const auto& name : names) columns.push_back(table.column(name));
  if (columns.empty()) throw fileError(arguments.data, "has no observation columns");
  const auto sequences = sequencesOf(table, columns);

  hmm::TrainingOptions options;
  options.numStates = arguments.states;
  options.numMixtures = arguments.mixtures;
  options.covariance = arguments.covariance == "diag" ? hmm::CovarianceType::kDiagonal : hmm::CovarianceType::kFull;
  options.maxIterations = arguments.iterations;
  options.seed = arguments.seed;
  const bool entropic = arguments.entropic != 0.0 || arguments.covariancePrior != 0.0;
  const hmm::EstimationHooks hooks = entropic ? hmm::entropicHooks({.multinomialWeight = arguments.entropic,
                                                                    .covarianceWeight = arguments.covariancePrior,
                                                                    .trim = !arguments.noTrim,
                                                                    .warmupIterations = arguments.warmup,
                                                                    .rampIterations = arguments.ramp,
                                                                    .mergeCandidates = arguments.mergeCandidates})
                                              : hmm::EstimationHooks{};
  hmm::TrainingResult result = hmm::trainHmm(sequences, options, hooks);
  result.model.columnNames = names;
  if (!visual.empty()) {
    result.model.blocks = {{"audio", 0, static_cast<int>(audio.size())},
                           {"visual", static_cast<int>(audio.size()), static_cast<int>(visual.size())}};
  }
  double frames = 0.0;
  for (const auto& sequence : sequences) frames += static_cast<double>(sequence.cols());
  nlohmann::json training;
  training["frames"] = frames;
  training["sequences"] = sequences.size();
  training["iterations"] = result.history.size() - 1;
  training["converged"] = result.converged;
  training["options"] = {{"states", arguments.states},
                         {"mixtures", arguments.mixtures},
                         {"covariance", arguments.covariance},
                         {"entropic", arguments.entropic},
                         {"covariance_prior", arguments.covariancePrior},
                         {"warmup", arguments.warmup},
                         {"ramp", arguments.ramp},
                         {"merge_candidates", arguments.mergeCandidates},
                         {"trim", !arguments.noTrim},
                         {"seed", arguments.seed}};
  nlohmann::json history = nlohmann::json::array();
  for (const auto& record : result.history) {
    history.push_back({{"log_likelihood", record.logLikelihood},
                       {"log_prior", record.logPrior},
                       {"live_states", record.liveStates},
                       {"step_gain", record.stepGain},
                       {"trim_retries", record.trimRetries},
                       {"states_merged", record.statesMerged}});
  }
  training["history"] = history;
  hmm::saveModel(arguments.output, result.model, training.dump());
  std::cerr << "trained " << result.model.numStates() << " states on " << frames << " frames in "
            << result.history.size() - 1 << " iterations; wrote " << arguments.output << '\n';
}

void runInfo(const std::string& path) {
  std::string trainingText;
  const hmm::HmmModel model = hmm::loadModel(path, &trainingText);
  nlohmann::json info;
  info["states"] = model.numStates();
  info["dimension"] = model.dimension();
  info["mixtures"] = model.states.front().numComponents();
  info["covariance"] = model.covarianceType() == hmm::CovarianceType::kFull ? "full" : "diagonal";
  info["nonzero_transitions"] = hmm::countTransitions(model);
  nlohmann::json blocks = nlohmann::json::array();
  for (const auto& block : model.blocks)
    blocks.push_back({{"name", block.name}, {"begin", block.begin}, {"size", block.size}});
  info["blocks"] = blocks;
  if (!trainingText.empty()) {
    const Json training = parseJson(trainingText, path);
    if (training.is_object() && training.contains("history") && training.contains("frames") &&
        !training["history"].empty()) {
      const auto& last = training["history"].back();
      const double frames = training["frames"].get<double>();
      info["iterations"] = training.value("iterations", 0);
      info["final_log_likelihood_per_frame"] = last["log_likelihood"].get<double>() / frames;
      info["final_log_posterior_per_frame"] =
          (last["log_likelihood"].get<double>() + last["log_prior"].get<double>()) / frames;
    }
  }
  std::cout << info.dump(2) << '\n';
}

std::vector<int> modelColumns(const hmm::HmmModel& model, const NumericTable& table, int begin, int size) {
  if (model.columnNames.empty()) throw Error("the model has no column names, so its columns cannot be found in a CSV");
  std::vector<int> columns;
  for (int k = begin; k < begin + size; ++k) columns.push_back(table.column(model.columnNames[static_cast<size_t>(k)]));
  return columns;
}

struct DecodeArguments {
  std::string model;
  std::string data;
  std::string output;
  bool online = false;
  int maxLag = -1;
};

void runDecode(const DecodeArguments& arguments) {
  const hmm::HmmModel model = hmm::loadModel(arguments.model);
  const NumericTable table = readNumericCsv(arguments.data);
  const auto sequences = sequencesOf(table, modelColumns(model, table, 0, model.dimension()));
  std::vector<std::vector<double>> rows;
  for (const auto& frames : sequences) {
    const Eigen::MatrixXd logB = model.emissionLogLikelihoods(frames);
    if (arguments.online) {
      hmm::OnlineViterbi decoder(model, {.maxLagFrames = arguments.maxLag});
      for (Eigen::Index t = 0; t < logB.cols(); ++t) decoder.acceptFrame(logB.col(t));
      decoder.finish();
      for (int t = 0; t < decoder.numDecided(); ++t) {
        rows.push_back({static_cast<double>(decoder.state(t)), static_cast<double>(decoder.decisionLag(t))});
      }
    } else {
      for (int state : hmm::viterbi(model, logB).states) rows.push_back({static_cast<double>(state)});
    }
  }
  writeNumericCsv(
      arguments.output,
      arguments.online ? std::vector<std::string>{"state", "lag_frames"} : std::vector<std::string>{"state"}, rows);
}

struct InvertArguments {
  std::string model;
  std::string data;
  std::string output;
  std::string method = "inversion";
  int window = 0;
  std::string start = "mean";
};

void runInvert(const InvertArguments& arguments) {
  const hmm::HmmModel model = hmm::loadModel(arguments.model);
  if (model.blocks.empty()) {
    throw fileError(arguments.model, "has no audio and visual blocks to invert (train it with --visual-columns)");
  }
  const hmm::ObservationBlock& audio = model.block("audio");
  const hmm::ObservationBlock& visual = model.block("visual");
  const NumericTable table = readNumericCsv(arguments.data);
  const auto sequences = sequencesOf(table, modelColumns(model, table, audio.begin, audio.size));
  hmm::InversionOptions options;
  options.windowFrames = arguments.window;
  options.start = arguments.start == "random" ? hmm::InversionStart::kRandom : hmm::InversionStart::kConditionalMean;
  const hmm::HmmInverter inverter(model, options);
  std::vector<std::vector<double>> rows;
  for (const auto& frames : sequences) {
    const Eigen::MatrixXd estimate =
        arguments.method == "mmse" ? inverter.mmse(frames) : inverter.invert(frames).visual;
    for (Eigen::Index t = 0; t < estimate.cols(); ++t) {
      rows.emplace_back(estimate.col(t).data(), estimate.col(t).data() + estimate.rows());
    }
  }
  const std::vector<std::string> names(model.columnNames.begin() + visual.begin,
                                       model.columnNames.begin() + visual.begin + visual.size);
  writeNumericCsv(arguments.output, names, rows);
}

}  // namespace

void addHmmCommand(CLI::App& app) {
  CLI::App* hmm = app.add_subcommand("hmm", "Train, inspect, decode and invert Gaussian-mixture HMMs on CSV data");
  hmm->require_subcommand(1);

  auto train = std::make_shared<TrainArguments>();
  CLI::App* trainCommand =
      hmm->add_subcommand("train", "Train an HMM (Baum-Welch, optionally with Brand's entropic prior)");
  trainCommand->add_option("--data", train->data, "CSV with a header; a 'seq' column splits sequences")->required();
  trainCommand->add_option("--states", train->states, "Number of states (a generous start when entropic)")
      ->required()
      ->check(CLI::Range(1, 1000));
  trainCommand->add_option("--mixtures", train->mixtures, "Gaussians per state")->check(CLI::Range(1, 100));
  trainCommand->add_option("--covariance", train->covariance, "full or diag")->check(CLI::IsMember({"full", "diag"}));
  trainCommand->add_option("--entropic", train->entropic,
                           "Entropic prior weight Z on pi, transitions and mixture weights (0: maximum likelihood); "
                           "absolute, so set it against the number of frames");
  trainCommand->add_option("--covariance-prior", train->covariancePrior, "Entropic prior weight on covariances");
  trainCommand->add_option("--warmup", train->warmup, "Maximum-likelihood iterations before the prior starts");
  trainCommand->add_option("--ramp", train->ramp, "Iterations over which Z rises to its full value");
  trainCommand
      ->add_option("--merge-candidates", train->mergeCandidates,
                   "With the entropic prior: most similar state pairs tried for merging per iteration once Z "
                   "has settled; a merge is kept only if the log posterior rises (0: never)")
      ->check(CLI::Range(0, 100));
  trainCommand->add_flag("--no-trim", train->noTrim,
                         "With the entropic prior: no parameter extinction, state deletion or merging");
  trainCommand->add_option("--iterations", train->iterations, "Maximum EM iterations")->check(CLI::Range(1, 100000));
  trainCommand->add_option("--seed", train->seed, "Seed of the k-means++ initialisation");
  trainCommand->add_option("--visual-columns", train->visualColumns,
                           "Comma-separated columns forming the visual block");
  trainCommand->add_option("-o,--output", train->output, "Model file (JSON) to write")->required();
  trainCommand->callback([train] { runTrain(*train); });

  auto infoPath = std::make_shared<std::string>();
  CLI::App* info = hmm->add_subcommand("info", "Print a model's structure and training summary as JSON");
  info->add_option("model", *infoPath, "Model file")->required();
  info->callback([infoPath] { runInfo(*infoPath); });

  auto decode = std::make_shared<DecodeArguments>();
  CLI::App* decodeCommand = hmm->add_subcommand("decode", "Most likely state of every frame (Viterbi)");
  decodeCommand->add_option("model", decode->model, "Model file")->required();
  decodeCommand->add_option("--data", decode->data, "CSV with the model's columns")->required();
  decodeCommand->add_flag("--online", decode->online, "Online Viterbi (convergence points); adds a lag_frames column");
  decodeCommand->add_option("--max-lag", decode->maxLag, "Online: force a decision after this many frames");
  decodeCommand->add_option("-o,--output", decode->output, "CSV to write (column 'state')")->required();
  decodeCommand->callback([decode] { runDecode(*decode); });

  auto invert = std::make_shared<InvertArguments>();
  CLI::App* invertCommand = hmm->add_subcommand("invert", "Visual columns from audio columns by HMM inversion or MMSE");
  invertCommand->add_option("model", invert->model, "Model file with 'audio' and 'visual' blocks")->required();
  invertCommand->add_option("--data", invert->data, "CSV with the model's audio columns")->required();
  invertCommand->add_option("--method", invert->method, "inversion or mmse")
      ->check(CLI::IsMember({"inversion", "mmse"}));
  invertCommand->add_option("--window-frames,--window", invert->window, "Frames per EM window (0: whole sequence)")
      ->check(CLI::Range(0, 1000000));
  invertCommand->add_option("--start", invert->start, "mean (conditional mean) or random")
      ->check(CLI::IsMember({"mean", "random"}));
  invertCommand->add_option("-o,--output", invert->output, "CSV of the visual columns")->required();
  invertCommand->callback([invert] { runInvert(*invert); });
}

}  // namespace th::app
