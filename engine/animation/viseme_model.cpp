#include "animation/viseme_model.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_reading.h"
#include "hmm/model_file.h"
#include "hmm/training.h"

namespace th::animation {
namespace {

constexpr int kClasses = face::kNumMouthClasses;

Eigen::MatrixXd normalisedFrames(const VisemeModel& model, const SpeechFrames& speech) {
  return features::normaliseSpeech(model.normalisation, kMouthFramesPerSecond, model.priorMean, speech.levelDb,
                                   speech.mfcc);
}

Eigen::MatrixXd stackedFrames(const VisemeModel& model, const SpeechFrames& speech) {
  return features::stackContext(normalisedFrames(model, speech), model.contextFrames);
}

// LDA: the generalised eigenvectors of S_b v = λ S_w v with the largest λ, as rows.
Eigen::MatrixXd discriminantDirections(const Eigen::MatrixXd& frames, const std::vector<int>& classes, int dimensions) {
  const Eigen::Index d = frames.rows();
  const Eigen::VectorXd mean = frames.rowwise().mean();
  Eigen::MatrixXd classSums = Eigen::MatrixXd::Zero(d, kClasses);
  Eigen::VectorXd counts = Eigen::VectorXd::Zero(kClasses);
  for (Eigen::Index t = 0; t < frames.cols(); ++t) {
    classSums.col(classes[static_cast<std::size_t>(t)]) += frames.col(t);
    counts[classes[static_cast<std::size_t>(t)]] += 1.0;
  }
  Eigen::MatrixXd within = Eigen::MatrixXd::Zero(d, d);
  Eigen::MatrixXd between = Eigen::MatrixXd::Zero(d, d);
  Eigen::MatrixXd centred = frames;
  for (Eigen::Index t = 0; t < frames.cols(); ++t) {
    const int c = classes[static_cast<std::size_t>(t)];
    centred.col(t) -= classSums.col(c) / counts[c];
  }
  within = centred * centred.transpose();
  for (int c = 0; c < kClasses; ++c) {
    if (counts[c] == 0.0) continue;
    const Eigen::VectorXd offset = classSums.col(c) / counts[c] - mean;
    between += counts[c] * offset * offset.transpose();
  }
  // A small ridge keeps S_w positive definite where context columns are nearly collinear.
  within.diagonal().array() += 1e-4 * within.trace() / static_cast<double>(d);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(between, within);
  if (solver.info() != Eigen::Success) throw Error("viseme model: the discriminant analysis did not converge");
  // Eigenvalues ascend: the last columns are the most discriminating.
  Eigen::MatrixXd directions(dimensions, d);
  for (int k = 0; k < dimensions; ++k) directions.row(k) = solver.eigenvectors().col(d - 1 - k).transpose();
  return directions;
}

Eigen::MatrixXd scaledEmissions(const VisemeModel& model, const Eigen::MatrixXd& projected) {
  return model.emissionScale * model.hmm.emissionLogLikelihoods(projected);
}

nlohmann::json vectorJson(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

Eigen::VectorXd vectorOf(const JsonFields& fields, const Json& value, const std::string& field) {
  const Json& list = fields.array(value, field);
  Eigen::VectorXd v(static_cast<Eigen::Index>(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i)
    v[static_cast<Eigen::Index>(i)] = fields.number(list[i], JsonFields::indexed(field, i));
  return v;
}

}  // namespace

ClassSequence classSequenceOf(const std::vector<std::vector<int>>& labels) {
  ClassSequence sequence;
  Eigen::VectorXd runFrames = Eigen::VectorXd::Zero(kClasses);
  Eigen::VectorXd runCount = Eigen::VectorXd::Zero(kClasses);
  sequence.bigrams = Eigen::MatrixXd::Constant(kClasses, kClasses, 0.5);  // add-½ smoothing
  sequence.starts = Eigen::VectorXd::Constant(kClasses, 0.5);
  for (const std::vector<int>& classes : labels) {
    int previous = -1;
    for (const face::Run& run : face::runsOf(classes)) {
      if (run.value < 0 || run.value >= kClasses) {
        previous = -1;
        continue;
      }
      runFrames[run.value] += run.length;
      runCount[run.value] += 1.0;
      if (previous >= 0) sequence.bigrams(previous, run.value) += 1.0;
      if (run.first == 0) sequence.starts[run.value] += 1.0;
      previous = run.value;
    }
  }
  sequence.meanRun.resize(kClasses);
  for (int c = 0; c < kClasses; ++c) sequence.meanRun[c] = runCount[c] > 0.0 ? runFrames[c] / runCount[c] : 0.0;
  return sequence;
}

hmm::HmmModel classHmm(const ClassSequence& sequence, int minHold, const std::vector<hmm::GaussianMixture>& emissions) {
  const int n = kClasses * minHold;
  hmm::HmmModel model;
  model.initial = Eigen::VectorXd::Zero(n);
  model.transition = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < kClasses; ++c) {
    model.initial[c * minHold] = sequence.starts[c] / sequence.starts.sum();
    for (int k = 0; k + 1 < minHold; ++k) model.transition(c * minHold + k, c * minHold + k + 1) = 1.0;
    // The last state's stay gives the mean run: minHold − 1 + 1 / (1 − stay) frames.
    const double meanRun = sequence.meanRun[c] > 0.0 ? sequence.meanRun[c] : static_cast<double>(minHold);
    const double stay = 1.0 - 1.0 / std::max(meanRun - minHold + 1.0, 1.25);
    const int last = c * minHold + minHold - 1;
    model.transition(last, last) = stay;
    double leaving = 0.0;
    for (int to = 0; to < kClasses; ++to)
      if (to != c) leaving += sequence.bigrams(c, to);
    for (int to = 0; to < kClasses; ++to)
      if (to != c) model.transition(last, to * minHold) = (1.0 - stay) * sequence.bigrams(c, to) / leaving;
    for (int k = 0; k < minHold; ++k)
      model.states.push_back(emissions.empty() ? hmm::GaussianMixture{} : emissions[static_cast<std::size_t>(c)]);
  }
  return model;
}

face::VisemeTrack decodeClassEvidence(const hmm::HmmModel& classes, int minHoldFrames,
                                      const Eigen::MatrixXd& classLogLikelihoods) {
  face::VisemeTrack track;
  track.framesPerSecond = kMouthFramesPerSecond;
  if (classLogLikelihoods.cols() == 0) return track;
  if (classLogLikelihoods.rows() != kClasses || classes.numStates() != kClasses * minHoldFrames)
    throw Error("visemes: the evidence must have one row per mouth class and the HMM minHold states per class");
  Eigen::MatrixXd logB(classes.numStates(), classLogLikelihoods.cols());
  for (int s = 0; s < classes.numStates(); ++s) logB.row(s) = classLogLikelihoods.row(s / minHoldFrames);
  const Eigen::MatrixXd states = hmm::forwardBackward(classes, logB).stateGivenAll;
  track.posteriors = Eigen::MatrixXd::Zero(kClasses, states.cols());
  for (int s = 0; s < classes.numStates(); ++s) track.posteriors.row(s / minHoldFrames) += states.row(s);
  for (int state : hmm::viterbi(classes, logB).states) track.classes.push_back(state / minHoldFrames);
  return track;
}

void VisemeModelOptions::check() const {
  if (contextFrames < 0 || contextFrames > 20) throw Error("viseme model: context frames must be 0..20");
  if (dimensions < 1 || dimensions > kClasses - 1)
    throw Error("viseme model: dimensions must be 1.." + std::to_string(kClasses - 1));
  if (mixtures < 1 || mixtures > 16) throw Error("viseme model: mixtures must be 1..16");
  if (minHoldFrames < 1 || minHoldFrames > 15) throw Error("viseme model: the minimum hold must be 1..15 frames");
  if (!(emissionScale > 0.0 && emissionScale <= 1.0)) throw Error("viseme model: the emission scale must be in (0, 1]");
  normalisation.check();
}

VisemeModel trainVisemeModel(const std::vector<LabelledSpeech>& recordings, const VisemeModelOptions& options) {
  options.check();
  if (recordings.empty()) throw Error("viseme model: no labelled recordings");
  VisemeModel model;
  model.contextFrames = options.contextFrames;
  model.minHoldFrames = options.minHoldFrames;
  model.emissionScale = options.emissionScale;
  model.normalisation = options.normalisation;
  // The prior mean: the training speech's c1..c11, as the mouth model's.
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(recordings.front().speech.mfcc.rows());
  double frames = 0.0;
  for (const LabelledSpeech& r : recordings) {
    if (static_cast<int>(r.classes.size()) != r.speech.numFrames())
      throw Error("viseme model: a recording has " + std::to_string(r.speech.numFrames()) + " frames and " +
                  std::to_string(r.classes.size()) + " labels");
    sum += r.speech.mfcc.rowwise().sum();
    frames += r.speech.numFrames();
  }
  model.priorMean = sum / frames;

  // The labelled frames, stacked.
  std::vector<Eigen::MatrixXd> stacked;
  Eigen::Index labelled = 0;
  for (const LabelledSpeech& r : recordings) {
    stacked.push_back(stackedFrames(model, r.speech));
    for (int c : r.classes) labelled += c >= 0 ? 1 : 0;
  }
  Eigen::MatrixXd all(stacked.front().rows(), labelled);
  std::vector<int> classes;
  classes.reserve(static_cast<std::size_t>(labelled));
  for (std::size_t i = 0; i < recordings.size(); ++i)
    for (int t = 0; t < recordings[i].speech.numFrames(); ++t) {
      const int c = recordings[i].classes[static_cast<std::size_t>(t)];
      if (c < 0) continue;
      if (c >= kClasses) throw Error("viseme model: a label is not a mouth class");
      all.col(static_cast<Eigen::Index>(classes.size())) = stacked[i].col(t);
      classes.push_back(c);
    }
  model.inputMean = all.rowwise().mean();
  all.colwise() -= model.inputMean;
  model.projection = discriminantDirections(all, classes, options.dimensions);
  const Eigen::MatrixXd projected = model.projection * all;

  std::vector<hmm::GaussianMixture> emissions;
  for (int c = 0; c < kClasses; ++c) {
    std::vector<Eigen::Index> columns;
    for (std::size_t t = 0; t < classes.size(); ++t)
      if (classes[t] == c) columns.push_back(static_cast<Eigen::Index>(t));
    const int needed = options.mixtures * (options.dimensions + 1);
    if (static_cast<int>(columns.size()) < needed)
      throw Error("viseme model: class " + std::string(face::kMouthClassNames[static_cast<std::size_t>(c)]) + " has " +
                  std::to_string(columns.size()) + " labelled frames; " + std::to_string(options.mixtures) +
                  " Gaussians need " + std::to_string(needed));
    Eigen::MatrixXd own(projected.rows(), static_cast<Eigen::Index>(columns.size()));
    for (std::size_t k = 0; k < columns.size(); ++k) own.col(static_cast<Eigen::Index>(k)) = projected.col(columns[k]);
    hmm::TrainingOptions training{.numStates = 1,
                                  .numMixtures = options.mixtures,
                                  .covariance = hmm::CovarianceType::kFull,
                                  .maxIterations = 30,
                                  .seed = options.seed + static_cast<unsigned>(c)};
    emissions.push_back(hmm::trainHmm({own}, training).model.states.front());
  }
  std::vector<std::vector<int>> labels;
  for (const LabelledSpeech& r : recordings) labels.push_back(r.classes);
  model.hmm = classHmm(classSequenceOf(labels), options.minHoldFrames, emissions);
  model.hmm.check();
  return model;
}

Eigen::MatrixXd visemeFeatures(const VisemeModel& model, const SpeechFrames& speech) {
  Eigen::MatrixXd stacked = stackedFrames(model, speech);
  stacked.colwise() -= model.inputMean;
  return model.projection * stacked;
}

face::VisemeTrack decodeVisemes(const VisemeModel& model, const SpeechFrames& speech) {
  if (speech.numFrames() == 0) return decodeClassEvidence(model.hmm, model.minHoldFrames, Eigen::MatrixXd(kClasses, 0));
  // A class's states share its density: the class's evidence is its first state's.
  const Eigen::MatrixXd logB = scaledEmissions(model, visemeFeatures(model, speech));
  Eigen::MatrixXd evidence(kClasses, logB.cols());
  for (int c = 0; c < kClasses; ++c) evidence.row(c) = logB.row(c * model.minHoldFrames);
  return decodeClassEvidence(model.hmm, model.minHoldFrames, evidence);
}

std::vector<int> classifyFrames(const VisemeModel& model, const SpeechFrames& speech) {
  const Eigen::MatrixXd logB = model.hmm.emissionLogLikelihoods(visemeFeatures(model, speech));
  std::vector<int> classes;
  for (Eigen::Index t = 0; t < logB.cols(); ++t) {
    Eigen::Index best = 0;
    logB.col(t).maxCoeff(&best);
    classes.push_back(model.classOfState(static_cast<int>(best)));
  }
  return classes;
}

void saveVisemeModel(const std::filesystem::path& path, const VisemeModel& model) {
  nlohmann::json training;
  training["kind"] = "visemes";
  training["classes"] = std::vector<std::string>(face::kMouthClassNames.begin(), face::kMouthClassNames.end());
  training["context_frames"] = model.contextFrames;
  training["min_hold_frames"] = model.minHoldFrames;
  training["emission_scale"] = model.emissionScale;
  training["speech_normalisation"] = features::speechNormalisationJson(model.normalisation, model.priorMean);
  training["input_mean"] = vectorJson(model.inputMean);
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < model.projection.rows(); ++r) rows.push_back(vectorJson(model.projection.row(r)));
  training["projection"] = rows;
  hmm::saveModel(path, model.hmm, training.dump());
}

VisemeModel loadVisemeModel(const std::filesystem::path& path) {
  std::string trainingText;
  VisemeModel model;
  model.hmm = hmm::loadModel(path, &trainingText);
  const Json training =
      parseJson(trainingText, path.string(), {.maxDepth = 64, .depthNote = "", .subject = "the training metadata"});
  const JsonFields fields(path.string());
  if (!training.is_object() || !training.contains("kind") || training["kind"] != "visemes")
    throw fileError(path, "is an HMM file but not a viseme model (training.kind is not \"visemes\")");
  const Json& names = fields.array(fields.member(training, "classes", "training"), "training.classes");
  if (names.size() != face::kMouthClassNames.size())
    throw fileError(path, "training.classes must list the " + std::to_string(kClasses) + " mouth classes");
  for (std::size_t c = 0; c < names.size(); ++c)
    if (fields.string(names[c], "training.classes") != face::kMouthClassNames[c])
      throw fileError(path, "training.classes[" + std::to_string(c) + "] must be \"" +
                                std::string(face::kMouthClassNames[c]) + "\"");
  const auto integer = [&](const char* key, int low, int high) {
    const std::int64_t value = fields.integer(fields.member(training, key, "training"), std::string("training.") + key);
    if (value < low || value > high)
      throw fileError(path,
                      std::string("training.") + key + " must be " + std::to_string(low) + ".." + std::to_string(high));
    return static_cast<int>(value);
  };
  model.contextFrames = integer("context_frames", 0, 20);
  model.minHoldFrames = integer("min_hold_frames", 1, 15);
  model.emissionScale = fields.number(fields.member(training, "emission_scale", "training"), "training.emission_scale");
  if (!(model.emissionScale > 0.0 && model.emissionScale <= 1.0))
    throw fileError(path, "training.emission_scale must be in (0, 1]");
  model.normalisation = features::readSpeechNormalisation(fields.member(training, "speech_normalisation", "training"),
                                                          fields, "training.speech_normalisation", model.priorMean);
  model.inputMean = vectorOf(fields, fields.member(training, "input_mean", "training"), "training.input_mean");
  const Json& rows = fields.array(fields.member(training, "projection", "training"), "training.projection");
  const Eigen::Index inputs = (model.priorMean.size() + 1) * (2 * model.contextFrames + 1);
  if (model.priorMean.size() < 1 || model.inputMean.size() != inputs)
    throw fileError(path, "training.input_mean must hold (2 tc + 1) x (the MFCCs and the level) = " +
                              std::to_string(inputs) + " values");
  if (rows.empty() || static_cast<int>(rows.size()) != model.hmm.dimension())
    throw fileError(path, "training.projection must have one row per dimension of the HMM (" +
                              std::to_string(model.hmm.dimension()) + ")");
  model.projection.resize(static_cast<Eigen::Index>(rows.size()), inputs);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const Eigen::VectorXd row = vectorOf(fields, rows[r], JsonFields::indexed("training.projection", r));
    if (row.size() != inputs)
      throw fileError(path,
                      "training.projection[" + std::to_string(r) + "] must hold " + std::to_string(inputs) + " values");
    model.projection.row(static_cast<Eigen::Index>(r)) = row.transpose();
  }
  if (model.hmm.numStates() != kClasses * model.minHoldFrames)
    throw fileError(path, "the HMM must have min_hold_frames states per mouth class (" +
                              std::to_string(kClasses * model.minHoldFrames) + ")");
  return model;
}

VisemeStream::VisemeStream(const VisemeModel& model, int lagFrames)
    : VisemeStream(model.hmm, model.minHoldFrames, lagFrames) {
  model_ = &model;
  normaliser_.emplace(model.normalisation, kMouthFramesPerSecond, model.priorMean);
  stacker_.emplace(model.priorMean.size() + 1, model.contextFrames);
  normalised_.resize(model.priorMean.size() + 1);
}

VisemeStream::VisemeStream(const hmm::HmmModel& classes, int minHoldFrames, int lagFrames)
    : hmm_(classes),
      minHoldFrames_(minHoldFrames),
      lagFrames_(lagFrames),
      smoother_(classes, lagFrames),
      viterbi_(classes, {.maxLagFrames = lagFrames}),
      stateEvidence_(classes.numStates()) {
  if (minHoldFrames < 1 || classes.numStates() != kClasses * minHoldFrames)
    throw Error("viseme stream: the class HMM must have minHoldFrames states per mouth class");
}

void VisemeStream::accept(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc) {
  if (model_ == nullptr) throw Error("viseme stream: speech frames need a viseme model; this stream takes evidence");
  normaliser_->accept(levelDb, mfcc, normalised_);
  stacker_->acceptFrame(normalised_);
  Eigen::VectorXd stacked;
  while (stacker_->next(stacked)) pushStacked(stacked);
}

void VisemeStream::pushStacked(const Eigen::VectorXd& stacked) {
  const Eigen::VectorXd projected = model_->projection * (stacked - model_->inputMean);
  const Eigen::VectorXd logB = model_->emissionScale * model_->hmm.emissionLogLikelihoods(projected).col(0);
  smoother_.acceptFrame(logB);
  viterbi_.acceptFrame(logB);
}

void VisemeStream::acceptEvidence(const Eigen::Ref<const Eigen::VectorXd>& classLogLikelihoods) {
  for (Eigen::Index s = 0; s < stateEvidence_.size(); ++s) stateEvidence_[s] = classLogLikelihoods[s / minHoldFrames_];
  smoother_.acceptFrame(stateEvidence_);
  viterbi_.acceptFrame(stateEvidence_);
}

void VisemeStream::finish() {
  if (stacker_) {
    stacker_->inputFinished();
    Eigen::VectorXd stacked;
    while (stacker_->next(stacked)) pushStacked(stacked);
  }
  smoother_.finish();
  viterbi_.finish();
}

bool VisemeStream::next(VisemeFrame& frame) {
  if (taken_ >= smoother_.numReady() || taken_ >= viterbi_.numDecided()) return false;
  const Eigen::VectorXd& state = smoother_.posterior(taken_);
  frame.probabilities = Eigen::VectorXd::Zero(face::kNumMouthClasses);
  for (int s = 0; s < hmm_.numStates(); ++s) frame.probabilities[s / minHoldFrames_] += state[s];
  // A decision forced by the lag may cut a class short of its hold: the class shown keeps it regardless.
  const int decided = viterbi_.state(taken_) / minHoldFrames_;
  if (decided != shownClass_ && (shownFrames_ >= minHoldFrames_ || taken_ == 0)) {
    shownClass_ = decided;
    shownFrames_ = 0;
  }
  ++shownFrames_;
  frame.mouthClass = shownClass_;
  ++taken_;
  smoother_.forgetBefore(taken_);
  viterbi_.forgetBefore(taken_);
  return true;
}

}  // namespace th::animation
