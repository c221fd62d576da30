#include "animation/mouth_model.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>

#include "core/error.h"
#include "face/fap.h"
#include "hmm/model_file.h"
#include "hmm/training.h"

namespace th::animation {

MouthModel trainMouthModel(const std::vector<MouthRecording>& parts, const MouthModelOptions& options) {
  if (parts.empty()) throw Error("mouth model: no training data");
  Eigen::Index total = 0;
  for (const auto& part : parts) total += part.numFrames();
  Eigen::MatrixXd allVisual(parts.front().visual.rows(), total);
  Eigen::Index column = 0;
  for (const auto& part : parts) {
    allVisual.middleCols(column, part.numFrames()) = part.visual;
    column += part.numFrames();
  }
  MouthModel model;
  model.contextFrames = options.contextFrames;
  model.basis = VisualBasis::fit(allVisual, {.components = options.visualComponents, .standardise = options.standardiseVisual});

  std::vector<Eigen::MatrixXd> sequences;
  for (const auto& part : parts) {
    const Eigen::MatrixXd audio = stackContext(part.mfcc, options.contextFrames);
    Eigen::MatrixXd joint(audio.rows() + options.visualComponents, part.numFrames());
    joint.topRows(audio.rows()) = audio;
    joint.bottomRows(options.visualComponents) = model.basis.transform(part.visual);
    sequences.push_back(std::move(joint));
  }
  hmm::TrainingOptions training;
  training.numStates = options.states;
  training.numMixtures = options.mixtures;
  training.covariance = options.covariance;
  training.maxIterations = options.maxIterations;
  training.seed = options.seed;
  hmm::TrainingResult result = hmm::trainHmm(sequences, training);
  model.hmm = std::move(result.model);
  model.iterations = static_cast<int>(result.history.size()) - 1;
  const int audioSize = static_cast<int>(sequences.front().rows()) - options.visualComponents;
  model.hmm.blocks = {{"audio", 0, audioSize}, {"visual", audioSize, options.visualComponents}};
  for (int k = 0; k < audioSize; ++k) {
    model.hmm.columnNames.push_back("ctx" + std::to_string(k / parts.front().mfcc.rows() - options.contextFrames) +
                                    "_mfcc" + std::to_string(k % parts.front().mfcc.rows() + 1));
  }
  for (int k = 0; k < options.visualComponents; ++k) model.hmm.columnNames.push_back("visual" + std::to_string(k + 1));
  model.hmm.check();
  return model;
}

namespace {

nlohmann::json matrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json vectorJson(const Eigen::VectorXd& v) {
  nlohmann::json values = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) values.push_back(v[i]);
  return values;
}

Eigen::VectorXd vectorFrom(const nlohmann::json& json, const std::filesystem::path& path, const std::string& field) {
  if (!json.is_array() || json.empty()) throw fileError(path, "training.visual_basis." + field + " must be a list of numbers");
  Eigen::VectorXd v(static_cast<Eigen::Index>(json.size()));
  for (size_t i = 0; i < json.size(); ++i) {
    if (!json[i].is_number()) throw fileError(path, "training.visual_basis." + field + " must be a list of numbers");
    v[static_cast<Eigen::Index>(i)] = json[i].get<double>();
  }
  return v;
}

Eigen::MatrixXd matrixFrom(const nlohmann::json& json, const std::filesystem::path& path, const std::string& field) {
  if (!json.is_array() || json.empty() || !json[0].is_array()) {
    throw fileError(path, "training.visual_basis." + field + " must be a list of rows");
  }
  Eigen::MatrixXd m(static_cast<Eigen::Index>(json.size()), static_cast<Eigen::Index>(json[0].size()));
  for (size_t r = 0; r < json.size(); ++r) {
    if (!json[r].is_array() || json[r].size() != json[0].size()) {
      throw fileError(path, "training.visual_basis." + field + " has rows of different lengths");
    }
    for (size_t c = 0; c < json[r].size(); ++c) {
      if (!json[r][c].is_number()) throw fileError(path, "training.visual_basis." + field + " must hold numbers");
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = json[r][c].get<double>();
    }
  }
  return m;
}

}  // namespace

void saveMouthModel(const std::filesystem::path& path, const MouthModel& model, const MouthModelOptions& options) {
  nlohmann::json training;
  training["kind"] = "mouth";
  training["context_frames"] = model.contextFrames;
  training["visual_basis"] = {{"mean", vectorJson(model.basis.mean())},
                              {"scale", vectorJson(model.basis.scale())},
                              {"unmixing", matrixJson(model.basis.unmixing())},
                              {"mixing", matrixJson(model.basis.mixing())},
                              {"explained_variance", model.basis.explainedVariance()}};
  training["options"] = {{"states", options.states},
                         {"mixtures", options.mixtures},
                         {"covariance", options.covariance == hmm::CovarianceType::kFull ? "full" : "diagonal"},
                         {"context_frames", options.contextFrames},
                         {"visual_components", options.visualComponents},
                         {"standardise_visual", options.standardiseVisual},
                         {"max_iterations", options.maxIterations},
                         {"seed", options.seed}};
  training["iterations"] = model.iterations;
  if (model.fapMap) training["fap_map"] = mouthFapMapJson(*model.fapMap);
  if (!model.visualFaps.empty()) training["visual_faps"] = model.visualFaps;
  hmm::saveModel(path, model.hmm, training.dump());
}

MouthModel loadMouthModel(const std::filesystem::path& path) {
  std::string trainingText;
  MouthModel model;
  model.hmm = hmm::loadModel(path, &trainingText);
  const nlohmann::json training = nlohmann::json::parse(trainingText, nullptr, false);
  if (!training.is_object() || !training.contains("kind") || training["kind"] != "mouth") {
    throw fileError(path, "is an HMM file but not a mouth model (training.kind is not \"mouth\")");
  }
  if (!training.contains("context_frames") || !training["context_frames"].is_number_integer() ||
      training["context_frames"].get<int>() < 0 || training["context_frames"].get<int>() > 20) {
    throw fileError(path, "training.context_frames must be an integer 0..20");
  }
  model.contextFrames = training["context_frames"].get<int>();
  if (!training.contains("visual_basis") || !training["visual_basis"].is_object()) {
    throw fileError(path, "training.visual_basis is missing");
  }
  const nlohmann::json& basis = training["visual_basis"];
  if (!basis.contains("explained_variance") || !basis["explained_variance"].is_number()) {
    throw fileError(path, "training.visual_basis.explained_variance must be a number");
  }
  try {
    model.basis = VisualBasis::fromParts(vectorFrom(basis.value("mean", nlohmann::json()), path, "mean"),
                                         vectorFrom(basis.value("scale", nlohmann::json()), path, "scale"),
                                         matrixFrom(basis.value("unmixing", nlohmann::json()), path, "unmixing"),
                                         matrixFrom(basis.value("mixing", nlohmann::json()), path, "mixing"),
                                         basis["explained_variance"].get<double>());
  } catch (const Error& error) {
    const std::string what = error.what();
    if (what.rfind(path.string(), 0) == 0) throw;
    throw fileError(path, what);
  }
  if (training.contains("fap_map")) model.fapMap = mouthFapMapFromJson(training["fap_map"], path);
  if (training.contains("visual_faps")) {
    const nlohmann::json& faps = training["visual_faps"];
    const auto rows = static_cast<std::size_t>(model.basis.inputDimension());
    if (!faps.is_array() || faps.size() != rows)
      throw fileError(path, "training.visual_faps must list one FAP number per visual parameter (" +
                                std::to_string(rows) + ")");
    for (const nlohmann::json& number : faps) {
      if (!number.is_number_integer() || number.get<int>() < 1 || number.get<int>() > face::kNumFaps ||
          (!model.visualFaps.empty() && number.get<int>() <= model.visualFaps.back()))
        throw fileError(path, "training.visual_faps must hold FAP numbers 1..68 in ascending order");
      model.visualFaps.push_back(number.get<int>());
    }
  }
  // The audio block holds 2tc + 1 frames of MFCCs; the visual block the basis's K components.
  const int contextWidth = 2 * model.contextFrames + 1;
  int audioSize = -1;
  bool visualOk = false;
  for (const auto& block : model.hmm.blocks) {
    if (block.name == "audio" && block.begin == 0 && block.size > 0 && block.size % contextWidth == 0) audioSize = block.size;
  }
  for (const auto& block : model.hmm.blocks) {
    if (block.name == "visual") visualOk = block.begin == audioSize && block.size == model.basis.components();
  }
  if (audioSize < 0 || !visualOk) {
    throw fileError(path, "a mouth model needs an audio block at 0 of (2 tc + 1) x MFCCs and a visual block of the "
                          "basis's " + std::to_string(model.basis.components()) + " components after it");
  }
  return model;
}

Eigen::MatrixXd synthesiseMouth(const MouthModel& model, const Eigen::MatrixXd& mfcc,
                                const MouthSynthesisOptions& options, int* iterations) {
  const Eigen::MatrixXd audio = stackContext(mfcc, model.contextFrames);
  const hmm::HmmInverter inverter(model.hmm, {.maxIterations = options.maxIterations,
                                              .start = options.start,
                                              .seed = options.seed,
                                              .windowFrames = options.windowFrames});
  if (audio.rows() != inverter.audioDimension()) throw Error("mouth synthesis: the audio does not match the model");
  if (options.method == MouthMethod::kMmse) {
    if (iterations != nullptr) *iterations = 0;
    return inverter.mmse(audio);
  }
  hmm::InversionResult result = inverter.invert(audio);
  if (iterations != nullptr) *iterations = result.iterations;
  return result.visual;
}

}  // namespace th::animation

namespace th::animation {

MouthSynthesiser::MouthSynthesiser(const MouthModel& model, const MouthSynthesisOptions& options)
    : model_(model),
      inverter_(model.hmm, {.maxIterations = options.maxIterations, .start = options.start, .seed = options.seed}),
      stream_(inverter_,
              options.method == MouthMethod::kMmse ? hmm::StreamingInverter::Method::kMmse
                                                   : hmm::StreamingInverter::Method::kInversion,
              options.windowFrames),
      filter_(inverter_.audioModel()) {
  const Eigen::Index width = 2 * model.contextFrames + 1;
  if (inverter_.audioDimension() % width != 0)
    throw Error("mouth synthesis: the model's audio block is not " + std::to_string(width) + " frames of MFCCs");
  recent_.resize(inverter_.audioDimension() / width, width);
}

void MouthSynthesiser::acceptMfcc(const Eigen::Ref<const Eigen::VectorXd>& mfcc) {
  if (finished_) throw Error("mouth synthesis: MFCCs after finish()");
  if (mfcc.size() != recent_.rows())
    throw Error("mouth synthesis: " + std::to_string(mfcc.size()) + " MFCCs a frame, the model has " +
                std::to_string(recent_.rows()));
  recent_.col(received_ % recent_.cols()) = mfcc;
  ++received_;
  // Frame t's context reaches t + tc.
  while (stacked_ + model_.contextFrames < received_) stackFrame(stacked_++);
}

void MouthSynthesiser::finish() {
  if (finished_) return;
  finished_ = true;
  while (stacked_ < received_) stackFrame(stacked_++);
  stream_.finish();
}

bool MouthSynthesiser::next(Eigen::VectorXd& components) {
  if (!stream_.next(components)) return false;
  if (!posteriors_.empty()) {
    lastPosterior_ = std::move(posteriors_.front());
    posteriors_.pop_front();
  }
  return true;
}

int MouthSynthesiser::numStates() const { return inverter_.audioModel().numStates(); }

int MouthSynthesiser::lookaheadFrames() const {
  return model_.contextFrames + std::max(stream_.windowFrames(), 1) - 1;
}

void MouthSynthesiser::stackFrame(Eigen::Index t) {
  // As stackContext: frames before the first and after the last (known only at finish()) repeat them.
  const Eigen::Index rows = recent_.rows();
  const int tc = model_.contextFrames;
  Eigen::VectorXd stacked(rows * (2 * tc + 1));
  for (int offset = -tc; offset <= tc; ++offset) {
    const Eigen::Index source = std::clamp<Eigen::Index>(t + offset, 0, received_ - 1);
    stacked.segment(rows * (offset + tc), rows) = recent_.col(source % recent_.cols());
  }
  filter_.accept(inverter_.audioModel().emissionLogLikelihoods(stacked).col(0));
  posteriors_.push_back(filter_.posterior());
  stream_.accept(stacked);
}

Eigen::RowVectorXd jawOpeningOf(const MouthModel& model, const Eigen::MatrixXd& components) {
  if (!model.visualFaps.empty())
    throw Error("mouth model: its visual parameters are FAPs, not a jaw opening in degrees (use mouthFapsOf)");
  // Row 0 of the visual parameters is the jaw opening (mouth_data.h).
  return model.basis.reconstruct(components).row(0);
}

constexpr const char* kDrivesNoFaps =
    "mouth model: it drives no FAPs (no FAP map, a sweep model?); make one with `talkinghead train mouth`";

bool drivesFaps(const MouthModel& model) { return model.fapMap.has_value() || !model.visualFaps.empty(); }

std::vector<int> mouthFapNumbers(const MouthModel& model) {
  if (!model.visualFaps.empty()) return model.visualFaps;
  if (model.fapMap) return mouthFapNumbers(*model.fapMap);
  throw Error(kDrivesNoFaps);
}

Eigen::MatrixXd mouthFapsOf(const MouthModel& model, const Eigen::MatrixXd& components) {
  if (model.visualFaps.empty()) {
    if (!model.fapMap)
      throw Error(kDrivesNoFaps);
    return mouthFaps(*model.fapMap, jawOpeningOf(model, components));
  }
  Eigen::MatrixXd faps = model.basis.reconstruct(components);
  for (std::size_t i = 0; i < model.visualFaps.size(); ++i)
    if (model.visualFaps[i] == 3) faps.row(static_cast<Eigen::Index>(i)) = faps.row(static_cast<Eigen::Index>(i)).cwiseMax(0.0);
  return faps;
}

}  // namespace th::animation
