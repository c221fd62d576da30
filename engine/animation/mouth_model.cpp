#include "animation/mouth_model.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "animation/mlpg.h"
#include "core/error.h"
#include "core/json_reading.h"
#include "face/fap.h"
#include "hmm/audio_retraining.h"
#include "hmm/model_file.h"
#include "hmm/training.h"

namespace th::animation {

MouthModelOptions videoMouthRecipe() {
  return {.states = 8,
          .mixtures = 2,
          .covariance = hmm::CovarianceType::kFull,
          .contextFrames = 2,
          .visualComponents = 4,
          .standardiseVisual = false,
          .normaliseSpeech = true,
          .visualDeltas = true,
          .varianceValidationEvery = 5};
}

int MouthModel::speechRowsPerFrame() const {
  if (normalisation) return static_cast<int>(normalisation->priorMean.size()) + 1;
  return hmm.block("audio").size / contextWidth();
}

Eigen::MatrixXd mouthAudioFrames(const MouthModel& model, const SpeechFrames& speech) {
  if (!model.normalisation) return speech.mfcc;
  if (speech.levelDb.size() != speech.mfcc.cols())
    throw Error("mouth synthesis: the model needs each frame's level (" + std::to_string(speech.levelDb.size()) +
                " levels for " + std::to_string(speech.mfcc.cols()) + " frames)");
  return features::normaliseSpeech(model.normalisation->options, kMouthFramesPerSecond, model.normalisation->priorMean,
                                   speech.levelDb, speech.mfcc);
}

namespace {

// The model's audio frames with their context: D·(tc + tf + 1) x T.
Eigen::MatrixXd stackedAudio(const MouthModel& model, const SpeechFrames& speech) {
  return features::stackContext(mouthAudioFrames(model, speech), model.contextFrames, model.futureContextFrames);
}

// The model itself, on all the parts given: the visual basis, the speech normalisation's prior, Baum-Welch.
MouthModel trainOnParts(const std::vector<MouthRecording>& parts, const std::vector<SpeechFrames>& speechOnly,
                        const MouthModelOptions& options) {
  Eigen::Index total = 0;
  for (const auto& part : parts) total += part.numFrames();
  Eigen::MatrixXd allVisual(parts.front().visual.rows(), total);
  Eigen::VectorXd mfccSum = Eigen::VectorXd::Zero(parts.front().speech.mfcc.rows());
  Eigen::Index column = 0;
  for (const auto& part : parts) {
    if (part.speech.numFrames() != part.numFrames())
      throw Error("mouth model: a recording has " + std::to_string(part.speech.numFrames()) + " speech frames for " +
                  std::to_string(part.numFrames()) + " visual ones");
    allVisual.middleCols(column, part.numFrames()) = part.visual;
    mfccSum += part.speech.mfcc.rowwise().sum();
    column += part.numFrames();
  }
  MouthModel model;
  model.contextFrames = options.contextFrames;
  model.futureContextFrames = options.futureContextFrames < 0 ? options.contextFrames : options.futureContextFrames;
  model.visualDeltas = options.visualDeltas;
  model.basis =
      VisualBasis::fit(allVisual, {.components = options.visualComponents, .standardise = options.standardiseVisual});
  if (options.normaliseSpeech)
    model.normalisation = MouthSpeechNormalisation{options.normalisation, mfccSum / static_cast<double>(total)};

  const int visualSize = options.visualComponents * (options.visualDeltas ? 2 : 1);
  std::vector<Eigen::MatrixXd> sequences;
  for (const auto& part : parts) {
    const Eigen::MatrixXd audio = stackedAudio(model, part.speech);
    const Eigen::MatrixXd components = model.basis.transform(part.visual);
    Eigen::MatrixXd joint(audio.rows() + visualSize, part.numFrames());
    joint.topRows(audio.rows()) = audio;
    joint.middleRows(audio.rows(), options.visualComponents) = components;
    if (options.visualDeltas) joint.bottomRows(options.visualComponents) = deltas(components);
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
  const int audioSize = static_cast<int>(sequences.front().rows()) - visualSize;
  model.hmm.blocks = {{"audio", 0, audioSize}, {"visual", audioSize, visualSize}};
  const int rowsPerFrame = audioSize / model.contextWidth();
  for (int k = 0; k < audioSize; ++k) {
    const int row = k % rowsPerFrame;
    model.hmm.columnNames.push_back(
        "ctx" + std::to_string(k / rowsPerFrame - options.contextFrames) +
        (model.normalisation && row == rowsPerFrame - 1 ? std::string("_level") : "_mfcc" + std::to_string(row + 1)));
  }
  for (int k = 0; k < options.visualComponents; ++k) model.hmm.columnNames.push_back("visual" + std::to_string(k + 1));
  if (options.visualDeltas)
    for (int k = 0; k < options.visualComponents; ++k)
      model.hmm.columnNames.push_back("d_visual" + std::to_string(k + 1));
  if (!speechOnly.empty()) {
    // Stage 2: the audio side re-estimated on the training speech and the speech-only recordings together.
    std::vector<Eigen::MatrixXd> audio;
    for (const Eigen::MatrixXd& sequence : sequences) audio.push_back(sequence.topRows(audioSize));
    for (const SpeechFrames& speech : speechOnly)
      if (speech.numFrames() > 0) audio.push_back(stackedAudio(model, speech));
    model.hmm = hmm::retrainAudio(model.hmm, audio, {.iterations = options.speechOnlyIterations}).model;
  }
  model.hmm.check();
  return model;
}

}  // namespace

MouthModel trainMouthModel(const std::vector<MouthRecording>& parts, const MouthModelOptions& options,
                           const std::vector<SpeechFrames>& speechOnly) {
  if (parts.empty()) throw Error("mouth model: no training data");
  const int every = options.varianceValidationEvery;
  if (every <= 0) return trainOnParts(parts, speechOnly, options);
  // Global variance compensation: the spread a model's estimates lose on sequences it did not see.
  std::vector<MouthRecording> fit, validation;
  for (std::size_t i = 0; i < parts.size(); ++i)
    ((i + 1) % static_cast<std::size_t>(every) == 0 ? validation : fit).push_back(parts[i]);
  if (fit.empty() || validation.empty()) return trainOnParts(parts, speechOnly, options);  // too few to measure it
  const MouthModel first = trainOnParts(fit, speechOnly, options);
  const Eigen::Index k = first.basis.components();
  Eigen::Index frames = 0;
  for (const MouthRecording& part : validation) frames += part.numFrames();
  Eigen::MatrixXd truth(k, frames), estimate(k, frames);
  Eigen::Index column = 0;
  for (const MouthRecording& part : validation) {
    truth.middleCols(column, part.numFrames()) = first.basis.transform(part.visual);
    estimate.middleCols(column, part.numFrames()) =
        synthesiseMouth(first, part.speech, {.method = MouthMethod::kMmse, .varianceCompensation = false});
    column += part.numFrames();
  }
  MouthModel model = trainOnParts(parts, speechOnly, options);
  model.varianceScale.resize(k);
  for (Eigen::Index c = 0; c < k; ++c) {
    const Eigen::RowVectorXd t = truth.row(c).array() - truth.row(c).mean();
    const Eigen::RowVectorXd e = estimate.row(c).array() - estimate.row(c).mean();
    const double ratio = std::sqrt(t.squaredNorm() / std::max(e.squaredNorm(), 1e-12));
    const double rho = t.dot(e) / std::sqrt(std::max(t.squaredNorm() * e.squaredNorm(), 1e-300));
    // The truth's spread, as far as that keeps the component's error below the mean's: scaling an estimate that
    // correlates ρ with the truth to the truth's spread leaves an error of 2(1 − ρ) of its variance, worse than
    // predicting the mean when ρ < 0.5; a factor up to 2ρ · ratio never is (on the held-out sequences).
    model.varianceScale[c] = std::max(1.0, std::min(ratio, 2.0 * std::max(rho, 0.0) * ratio));
  }
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

Eigen::VectorXd vectorFrom(const Json& json, const std::filesystem::path& path, const std::string& field,
                           const std::string& prefix = "training.visual_basis.") {
  if (!json.is_array() || json.empty()) throw fileError(path, prefix + field + " must be a list of numbers");
  Eigen::VectorXd v(static_cast<Eigen::Index>(json.size()));
  for (size_t i = 0; i < json.size(); ++i) {
    if (!json[i].is_number()) throw fileError(path, prefix + field + " must be a list of numbers");
    v[static_cast<Eigen::Index>(i)] = json[i].get<double>();
  }
  return v;
}

Eigen::MatrixXd matrixFrom(const Json& json, const std::filesystem::path& path, const std::string& field) {
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
  training["future_context_frames"] = model.futureContextFrames;
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
  if (model.normalisation) {
    const features::SpeechNormalisationOptions& n = model.normalisation->options;
    training["speech_normalisation"] = {{"mean_seconds", n.meanSeconds},
                                        {"prior_seconds", n.priorSeconds},
                                        {"peak_decay_db_per_second", n.peakDecayDbPerSecond},
                                        {"level_unit_db", n.levelUnitDb},
                                        {"prior_mean", vectorJson(model.normalisation->priorMean)}};
  }
  training["visual_deltas"] = model.visualDeltas;
  if (model.varianceScale.size() > 0) training["variance_scale"] = vectorJson(model.varianceScale);
  training["options"]["normalise_speech"] = options.normaliseSpeech;
  training["options"]["variance_validation_every"] = options.varianceValidationEvery;
  hmm::saveModel(path, model.hmm, training.dump());
}

namespace {

VisualBasis mouthBasisFrom(const Json& training, const std::filesystem::path& path) {
  if (!training.contains("visual_basis") || !training["visual_basis"].is_object()) {
    throw fileError(path, "training.visual_basis is missing");
  }
  const Json& basis = training["visual_basis"];
  if (!basis.contains("explained_variance") || !basis["explained_variance"].is_number()) {
    throw fileError(path, "training.visual_basis.explained_variance must be a number");
  }
  try {
    return VisualBasis::fromParts(
        vectorFrom(basis.value("mean", Json()), path, "mean"), vectorFrom(basis.value("scale", Json()), path, "scale"),
        matrixFrom(basis.value("unmixing", Json()), path, "unmixing"),
        matrixFrom(basis.value("mixing", Json()), path, "mixing"), basis["explained_variance"].get<double>());
  } catch (const Error& error) {
    const std::string what = error.what();
    if (what.rfind(path.string(), 0) == 0) throw;
    throw fileError(path, what);
  }
}

std::vector<int> mouthVisualFapsFrom(const Json& faps, const std::filesystem::path& path, int parameters) {
  const auto rows = static_cast<std::size_t>(parameters);
  std::vector<int> numbers;
  if (!faps.is_array() || faps.size() != rows)
    throw fileError(
        path, "training.visual_faps must list one FAP number per visual parameter (" + std::to_string(rows) + ")");
  for (const Json& number : faps) {
    if (!number.is_number_integer() || number.get<int>() < 1 || number.get<int>() > face::kNumFaps ||
        (!numbers.empty() && number.get<int>() <= numbers.back()))
      throw fileError(path, "training.visual_faps must hold FAP numbers 1..68 in ascending order");
    numbers.push_back(number.get<int>());
  }
  return numbers;
}

MouthSpeechNormalisation mouthNormalisationFrom(const Json& n, const std::filesystem::path& path) {
  const auto number = [&](const char* field) {
    if (!n.is_object() || !n.contains(field) || !n[field].is_number())
      throw fileError(path, std::string("training.speech_normalisation.") + field + " must be a number");
    return n[field].get<double>();
  };
  MouthSpeechNormalisation normalisation;
  normalisation.options = {.meanSeconds = number("mean_seconds"),
                           .priorSeconds = number("prior_seconds"),
                           .peakDecayDbPerSecond = number("peak_decay_db_per_second"),
                           .levelUnitDb = number("level_unit_db")};
  try {
    normalisation.options.check();
  } catch (const Error& error) {
    throw fileError(path, std::string("training.speech_normalisation: ") + error.what());
  }
  normalisation.priorMean =
      vectorFrom(n.value("prior_mean", Json()), path, "prior_mean", "training.speech_normalisation.");
  if (!normalisation.priorMean.allFinite())
    throw fileError(path, "training.speech_normalisation.prior_mean must be finite");
  return normalisation;
}

// The audio block holds tc + tf + 1 frames of D values (D = the prior's MFCCs + the level, when normalised); the
// visual block the basis's K components (and their deltas).
void checkMouthBlocks(const MouthModel& model, const std::filesystem::path& path) {
  const int contextWidth = model.contextWidth();
  const int visualSize = model.basis.components() * (model.visualDeltas ? 2 : 1);
  int audioSize = -1;
  bool visualOk = false;
  for (const auto& block : model.hmm.blocks) {
    if (block.name == "audio" && block.begin == 0 && block.size > 0 && block.size % contextWidth == 0)
      audioSize = block.size;
  }
  for (const auto& block : model.hmm.blocks) {
    if (block.name == "visual") visualOk = block.begin == audioSize && block.size == visualSize;
  }
  if (audioSize < 0 || !visualOk) {
    throw fileError(path,
                    "a mouth model needs an audio block at 0 of (2 tc + 1) x its audio features and a visual "
                    "block of the basis's " +
                        std::to_string(model.basis.components()) + " components" +
                        (model.visualDeltas ? " and their deltas" : "") + " after it");
  }
  if (model.normalisation && audioSize != contextWidth * (static_cast<int>(model.normalisation->priorMean.size()) + 1))
    throw fileError(path, "the audio block does not hold (2 tc + 1) frames of the normalised MFCCs and the level");
}

}  // namespace

MouthModel loadMouthModel(const std::filesystem::path& path) {
  std::string trainingText;
  MouthModel model;
  model.hmm = hmm::loadModel(path, &trainingText);
  const Json training =
      parseJson(trainingText, path.string(), {.maxDepth = 64, .depthNote = "", .subject = "the training metadata"});
  if (!training.is_object() || !training.contains("kind") || training["kind"] != "mouth") {
    throw fileError(path, "is an HMM file but not a mouth model (training.kind is not \"mouth\")");
  }
  if (!training.contains("context_frames") || !training["context_frames"].is_number_integer() ||
      training["context_frames"].get<int>() < 0 || training["context_frames"].get<int>() > 20) {
    throw fileError(path, "training.context_frames must be an integer 0..20");
  }
  model.contextFrames = training["context_frames"].get<int>();
  model.futureContextFrames = model.contextFrames;  // files before the asymmetric context: symmetric
  if (training.contains("future_context_frames")) {
    const Json& future = training["future_context_frames"];
    if (!future.is_number_integer() || future.get<int>() < 0 || future.get<int>() > 20)
      throw fileError(path, "training.future_context_frames must be an integer 0..20");
    model.futureContextFrames = future.get<int>();
  }
  model.basis = mouthBasisFrom(training, path);
  if (training.contains("fap_map")) model.fapMap = mouthFapMapFromJson(training["fap_map"], path);
  if (training.contains("visual_faps"))
    model.visualFaps = mouthVisualFapsFrom(training["visual_faps"], path, model.basis.inputDimension());
  if (training.contains("speech_normalisation"))
    model.normalisation = mouthNormalisationFrom(training["speech_normalisation"], path);
  if (training.contains("visual_deltas")) {
    if (!training["visual_deltas"].is_boolean()) throw fileError(path, "training.visual_deltas must be true or false");
    model.visualDeltas = training["visual_deltas"].get<bool>();
  }
  if (training.contains("variance_scale")) {
    model.varianceScale = vectorFrom(training["variance_scale"], path, "variance_scale", "training.");
    if (model.varianceScale.size() != model.basis.components() || !model.varianceScale.allFinite() ||
        (model.varianceScale.array() <= 0.0).any())
      throw fileError(path, "training.variance_scale must hold one positive factor per visual component (" +
                                std::to_string(model.basis.components()) + ")");
  }
  checkMouthBlocks(model, path);
  return model;
}

namespace {

// The visual components among the visual block's rows (the first K; deltas follow), with the model's variance
// compensation if asked for.
Eigen::MatrixXd finishComponents(const MouthModel& model, const Eigen::MatrixXd& visual,
                                 const MouthSynthesisOptions& options) {
  Eigen::MatrixXd components = visual.topRows(model.basis.components());
  if (options.varianceCompensation && model.varianceScale.size() == components.rows())
    components = model.varianceScale.asDiagonal() * components;
  return components;
}

// MLPG over the frames' Gaussians of [components; deltas]: means as given, precisions from the posterior's
// covariances (the static and delta blocks; their cross-covariance is left out, as MlpgFrame holds none).
Eigen::MatrixXd generateComponents(const Eigen::MatrixXd& means, const std::vector<Eigen::MatrixXd>& covariances,
                                   Eigen::Index k) {
  std::vector<MlpgFrame> frames(static_cast<std::size_t>(means.cols()));
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(k, k);
  for (Eigen::Index t = 0; t < means.cols(); ++t) {
    const Eigen::MatrixXd& covariance = covariances[static_cast<std::size_t>(t)];
    // A floor keeps a frame the model is certain of from pinning the curve with an infinite precision.
    const auto precision = [&](Eigen::Index begin) {
      Eigen::MatrixXd block = covariance.block(begin, begin, k, k);
      block = 0.5 * (block + block.transpose()) + 1e-6 * identity;
      return Eigen::MatrixXd(block.llt().solve(identity));
    };
    MlpgFrame& frame = frames[static_cast<std::size_t>(t)];
    frame.staticMean = means.col(t).head(k);
    frame.deltaMean = means.col(t).segment(k, k);
    frame.staticPrecision = precision(0);
    frame.deltaPrecision = precision(k);
  }
  return generateTrajectory(frames);
}

}  // namespace

Eigen::MatrixXd synthesiseMouth(const MouthModel& model, const SpeechFrames& speech,
                                const MouthSynthesisOptions& options, int* iterations) {
  const Eigen::MatrixXd audio = stackedAudio(model, speech);
  const hmm::HmmInverter inverter(model.hmm, {.maxIterations = options.maxIterations,
                                              .start = options.start,
                                              .seed = options.seed,
                                              .windowFrames = options.windowFrames});
  if (audio.rows() != inverter.audioDimension()) throw Error("mouth synthesis: the audio does not match the model");
  const bool trajectory = model.visualDeltas && options.trajectory && options.windowFrames == 0 && audio.cols() >= 2;
  if (iterations != nullptr) *iterations = 0;
  Eigen::MatrixXd visual;
  if (options.method == MouthMethod::kMmse) {
    if (!trajectory) return finishComponents(model, inverter.mmse(audio), options);
    const hmm::HmmInverter::VisualDistribution distribution = inverter.conditionalDistribution(audio);
    visual = generateComponents(distribution.mean, distribution.covariance, model.basis.components());
  } else {
    hmm::InversionResult result = inverter.invert(audio);
    if (iterations != nullptr) *iterations = result.iterations;
    if (!trajectory) return finishComponents(model, result.visual, options);
    // The inversion's estimates of the components and their deltas, held as surely as the posterior holds them.
    visual =
        generateComponents(result.visual, inverter.conditionalDistribution(audio).covariance, model.basis.components());
  }
  return finishComponents(model, visual, options);
}

}  // namespace th::animation

namespace th::animation {

MouthSynthesiser::MouthSynthesiser(const MouthModel& model, const MouthSynthesisOptions& options)
    : model_(model),
      options_(options),
      inverter_(model.hmm, {.maxIterations = options.maxIterations, .start = options.start, .seed = options.seed}),
      stream_(inverter_,
              options.method == MouthMethod::kMmse ? hmm::StreamingInverter::Method::kMmse
                                                   : hmm::StreamingInverter::Method::kInversion,
              options.windowFrames),
      filter_(inverter_.audioModel()) {
  const Eigen::Index width = model.contextWidth();
  if (inverter_.audioDimension() % width != 0)
    throw Error("mouth synthesis: the model's audio block is not " + std::to_string(width) + " frames of features");
  stacker_.emplace(inverter_.audioDimension() / width, model.contextFrames, model.futureContextFrames);
  if (model.normalisation) {
    normaliser_.emplace(model.normalisation->options, kMouthFramesPerSecond, model.normalisation->priorMean);
    normalised_.resize(normaliser_->outputDimension());
  }
}

void MouthSynthesiser::acceptFrame(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc) {
  if (finished_) throw Error("mouth synthesis: speech frames after finish()");
  const Eigen::Index expected =
      normaliser_ ? normaliser_->numMfcc() : stacker_->outputDimension() / model_.contextWidth();
  if (mfcc.size() != expected)
    throw Error("mouth synthesis: " + std::to_string(mfcc.size()) + " MFCCs a frame, the model has " +
                std::to_string(expected));
  if (normaliser_) {
    normaliser_->accept(levelDb, mfcc, normalised_);
    stacker_->acceptFrame(normalised_);
  } else {
    stacker_->acceptFrame(mfcc);
  }
  while (stacker_->next(stacked_)) invertFrame();
}

void MouthSynthesiser::finish() {
  if (finished_) return;
  finished_ = true;
  stacker_->inputFinished();
  while (stacker_->next(stacked_)) invertFrame();
  stream_.finish();
}

bool MouthSynthesiser::next(Eigen::VectorXd& components) {
  Eigen::VectorXd visual;
  if (!stream_.next(visual)) return false;
  components = finishComponents(model_, visual, options_).col(0);
  if (!posteriors_.empty()) {
    lastPosterior_ = std::move(posteriors_.front());
    posteriors_.pop_front();
  }
  return true;
}

int MouthSynthesiser::numStates() const {
  return inverter_.audioModel().numStates();
}

int MouthSynthesiser::lookaheadFrames() const {
  return model_.futureContextFrames + std::max(stream_.windowFrames(), 1) - 1;
}

void MouthSynthesiser::invertFrame() {
  filter_.accept(inverter_.audioModel().emissionLogLikelihoods(stacked_).col(0));
  posteriors_.push_back(filter_.posterior());
  stream_.accept(stacked_);
}

Eigen::RowVectorXd jawOpeningOf(const MouthModel& model, const Eigen::MatrixXd& components) {
  if (!model.visualFaps.empty())
    throw Error("mouth model: its visual parameters are FAPs, not a jaw opening in degrees (use mouthFapsOf)");
  // Row 0 of the visual parameters is the jaw opening (mouth_data.h).
  return model.basis.reconstruct(components).row(0);
}

constexpr const char* kDrivesNoFaps =
    "mouth model: it drives no FAPs (no FAP map, a sweep model?); make one with `talkinghead train mouth`";

bool drivesFaps(const MouthModel& model) {
  return model.fapMap.has_value() || !model.visualFaps.empty();
}

std::vector<int> mouthFapNumbers(const MouthModel& model) {
  if (!model.visualFaps.empty()) return model.visualFaps;
  if (model.fapMap) return mouthFapNumbers(*model.fapMap);
  throw Error(kDrivesNoFaps);
}

Eigen::MatrixXd mouthFapsOf(const MouthModel& model, const Eigen::MatrixXd& components) {
  if (model.visualFaps.empty()) {
    if (!model.fapMap) throw Error(kDrivesNoFaps);
    return mouthFaps(*model.fapMap, jawOpeningOf(model, components));
  }
  Eigen::MatrixXd faps = model.basis.reconstruct(components);
  for (std::size_t i = 0; i < model.visualFaps.size(); ++i)
    if (model.visualFaps[i] == 3)
      faps.row(static_cast<Eigen::Index>(i)) = faps.row(static_cast<Eigen::Index>(i)).cwiseMax(0.0);
  return faps;
}

}  // namespace th::animation
