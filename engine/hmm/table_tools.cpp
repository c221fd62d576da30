#include "hmm/table_tools.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/json_reading.h"
#include "core/numeric_csv.h"
#include "hmm/entropic_training.h"
#include "hmm/forward_backward.h"
#include "hmm/inversion.h"
#include "hmm/model_file.h"
#include "hmm/training.h"
#include "hmm/viterbi.h"

namespace th::hmm {
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

std::vector<int> modelColumns(const hmm::HmmModel& model, const NumericTable& table, int begin, int size) {
  if (model.columnNames.empty()) throw Error("the model has no column names, so its columns cannot be found in a CSV");
  std::vector<int> columns;
  for (int k = begin; k < begin + size; ++k) columns.push_back(table.column(model.columnNames[static_cast<size_t>(k)]));
  return columns;
}

}  // namespace

void trainHmmOnTable(const TableTraining& arguments, std::ostream& log) {
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
  log << "trained " << result.model.numStates() << " states on " << frames << " frames in " << result.history.size() - 1
      << " iterations; wrote " << arguments.output << '\n';
}

void writeModelInfo(const std::filesystem::path& path, std::ostream& out) {
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
  out << info.dump(2) << '\n';
}

void decodeTable(const TableDecoding& arguments) {
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

void invertTable(const TableInversion& arguments) {
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

}  // namespace th::hmm
