#include "animation/mouth_network.h"

#include <algorithm>
#include <cmath>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_reading.h"
#include "features/online_features.h"
#include "nn/network_json.h"

namespace th::animation {
namespace {

constexpr int kClasses = face::kNumMouthClasses;
constexpr const char* kKind = "mouth_network";
constexpr int kFormatVersion = 2;

std::vector<nn::Head> headsFor(int components) {
  return {{"classes", nn::HeadKind::kSoftmax, 0, kClasses, 1.0},
          {"components", nn::HeadKind::kRegression, kClasses, components, 1.0},
          {"lip_shape", nn::HeadKind::kRegression, kClasses + components, 2, 1.0},
          {"shut", nn::HeadKind::kSigmoid, kClasses + components + 2, 1, 1.0}};
}
enum HeadIndex { kClassHead, kComponentHead, kShapeHead, kShutHead };

Eigen::MatrixXd normalisedSubframes(const MouthNetwork& model, const SpeechFrames& subframes,
                                    const Eigen::VectorXd* startMean = nullptr) {
  if (subframes.mfcc.rows() != kNetworkMfcc || subframes.levelDb.size() != subframes.mfcc.cols())
    throw Error("mouth network: the speech must be " + std::to_string(kNetworkMfcc) +
                " MFCCs and a level per subframe (speechSubframesOf)");
  const Eigen::VectorXd& mean =
      startMean != nullptr && startMean->size() == kNetworkMfcc ? *startMean : model.priorMean;
  return features::normaliseSpeech(model.normalisation, kSubframesPerSecond, mean, subframes.levelDb, subframes.mfcc);
}

// Frame t's input: the normalised subframes 3t − past .. 3t + future, earliest first, the edges repeated.
void stackFrame(const Eigen::MatrixXd& normalised, int past, int future, Eigen::Index frame,
                Eigen::Ref<Eigen::VectorXf> out) {
  const Eigen::Index rows = normalised.rows();
  const Eigen::Index centre = frame * kSubframesPerFrame;
  for (int k = -past; k <= future; ++k) {
    const Eigen::Index source = std::clamp<Eigen::Index>(centre + k, 0, normalised.cols() - 1);
    out.segment((k + past) * rows, rows) = normalised.col(source).cast<float>();
  }
}

}  // namespace

features::FeatureOptions subframeFeatureOptions(double frequencyWarp) {
  features::FeatureOptions options = features::batchFeatureOptions();
  options.framesPerSecond = kSubframesPerSecond;
  options.mfcc.numCoefficients = kNetworkMfcc;
  options.mfcc.frequencyWarp = frequencyWarp;
  options.contextFrames = 0;
  options.trackPitch = false;
  options.energyNormalisation = features::EnergyNormalisation::kNone;
  return options;
}

SpeechFrames speechSubframesOf(std::span<const float> samples16k, double frequencyWarp) {
  features::OnlineFeatureExtractor extractor(subframeFeatureOptions(frequencyWarp));
  extractor.acceptWaveform(samples16k);
  extractor.inputFinished();
  const int frames = extractor.numBaseFramesReady();
  SpeechFrames speech{Eigen::MatrixXd(kNetworkMfcc, frames), Eigen::RowVectorXd(frames)};
  std::vector<float> mfcc(kNetworkMfcc);
  for (int t = 0; t < frames; ++t) {
    extractor.getMfcc(t, mfcc);
    for (int k = 0; k < kNetworkMfcc; ++k) speech.mfcc(k, t) = mfcc[static_cast<std::size_t>(k)];
    speech.levelDb[t] = extractor.getLevelDb(t);
  }
  return speech;
}

void MouthNetworkOptions::check() const {
  if (pastSubframes < 0 || pastSubframes > 90) throw Error("mouth network: past subframes must be 0..90");
  if (futureSubframes < 0 || futureSubframes > 45) throw Error("mouth network: future subframes must be 0..45");
  if (visualComponents < 1 || visualComponents > 21) throw Error("mouth network: visual components must be 1..21");
  for (const int units : hidden)
    if (units < 1 || units > 4096) throw Error("mouth network: hidden layers must have 1..4096 units");
  for (const double weight : {classWeight, visualWeight, shapeWeight, closureWeight})
    if (!(weight >= 0.0)) throw Error("mouth network: the answers' weights must be >= 0");
  if (!(closedOpening > 0.0)) throw Error("mouth network: the closed opening must be > 0");
  normalisation.check();
  training.check();
}

int NetworkRecording::numFrames() const {
  Eigen::Index frames = static_cast<Eigen::Index>(classes.size());
  frames = std::max(frames, faps.cols());
  frames = std::max(frames, lipShape.cols());
  return static_cast<int>(frames);
}

int MouthNetwork::lookaheadMs() const {
  return static_cast<int>(std::lround(1000.0 * futureSubframes / kSubframesPerSecond));
}

Eigen::MatrixXf mouthNetworkInputs(const MouthNetwork& model, const SpeechFrames& subframes,
                                   const Eigen::VectorXd* startMean) {
  const Eigen::MatrixXd normalised = normalisedSubframes(model, subframes, startMean);
  const Eigen::Index frames = (normalised.cols() + kSubframesPerFrame - 1) / kSubframesPerFrame;
  Eigen::MatrixXf inputs(model.contextSubframes() * model.inputsPerSubframe(), frames);
  for (Eigen::Index t = 0; t < frames; ++t)
    stackFrame(normalised, model.pastSubframes, model.futureSubframes, t, inputs.col(t));
  return inputs;
}

namespace {

// A recording's frames as the network trains on them: inputs, and the truths it has, for frames [0, T).
nn::Frames framesOf(const MouthNetwork& model, const NetworkRecording& recording, double closedOpening) {
  const int frames = recording.numFrames();
  const Eigen::MatrixXd normalised = normalisedSubframes(model, recording.subframes, &recording.startMean);
  const int components = model.basis.components();
  nn::Frames out;
  out.inputs.resize(model.contextSubframes() * model.inputsPerSubframe(), frames);
  out.targets = Eigen::MatrixXf::Zero(model.network.outputs(), frames);
  out.mask = Eigen::MatrixXf::Zero(static_cast<Eigen::Index>(model.heads.size()), frames);
  Eigen::MatrixXd projected;
  if (recording.faps.cols() > 0) projected = model.basis.transform(recording.faps);
  for (int t = 0; t < frames; ++t) {
    stackFrame(normalised, model.pastSubframes, model.futureSubframes, t, out.inputs.col(t));
    if (t < static_cast<int>(recording.classes.size()) && recording.classes[static_cast<std::size_t>(t)] >= 0) {
      out.targets(recording.classes[static_cast<std::size_t>(t)], t) = 1.0f;
      out.mask(kClassHead, t) = 1.0f;
    }
    if (t < projected.cols()) {
      out.targets.block(kClasses, t, components, 1) = projected.col(t).cast<float>();
      out.mask(kComponentHead, t) = 1.0f;
    }
    if (t < recording.lipShape.cols()) {
      const Eigen::Vector2d shape = recording.lipShape.col(t);
      out.targets.block(kClasses + components, t, 2, 1) =
          ((shape - model.shapeMean).cwiseQuotient(model.shapeDeviation)).cast<float>();
      out.targets(kClasses + components + 2, t) = shape[0] < closedOpening ? 1.0f : 0.0f;
      out.mask(kShapeHead, t) = 1.0f;
      out.mask(kShutHead, t) = 1.0f;
    }
  }
  out.mask *= static_cast<float>(recording.weight);
  return out;
}

nn::Frames framesOf(const MouthNetwork& model, const std::vector<NetworkRecording>& recordings, double closedOpening) {
  nn::Frames all;
  Eigen::Index total = 0;
  for (const NetworkRecording& r : recordings) total += r.numFrames();
  const Eigen::Index inputs = model.contextSubframes() * model.inputsPerSubframe();
  all.inputs.resize(inputs, total);
  all.targets.resize(model.network.outputs(), total);
  all.mask.resize(static_cast<Eigen::Index>(model.heads.size()), total);
  Eigen::Index column = 0;
  for (const NetworkRecording& r : recordings) {
    const nn::Frames own = framesOf(model, r, closedOpening);
    all.inputs.middleCols(column, own.size()) = own.inputs;
    all.targets.middleCols(column, own.size()) = own.targets;
    all.mask.middleCols(column, own.size()) = own.mask;
    column += own.size();
  }
  return all;
}

}  // namespace

namespace {

// The classes' shapes: per class, the mean of its frames' FAPs less the mean over every labelled frame (rows FAPs).
Eigen::MatrixXd classShapesOf(const std::vector<NetworkRecording>& recordings, Eigen::Index rows) {
  Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(rows, kClasses);
  Eigen::VectorXd counts = Eigen::VectorXd::Zero(kClasses);
  for (const NetworkRecording& r : recordings)
    for (Eigen::Index t = 0; t < std::min<Eigen::Index>(r.faps.cols(), static_cast<Eigen::Index>(r.classes.size()));
         ++t) {
      const int c = r.classes[static_cast<std::size_t>(t)];
      if (c < 0) continue;
      sums.col(c) += r.faps.col(t);
      counts[c] += 1.0;
    }
  Eigen::MatrixXd shapes = Eigen::MatrixXd::Zero(rows, kClasses);
  if (counts.sum() > 0.0) {
    const Eigen::VectorXd mean = sums.rowwise().sum() / counts.sum();
    for (int c = 0; c < kClasses; ++c)
      if (counts[c] > 0.0) shapes.col(c) = sums.col(c) / counts[c] - mean;
  }
  return shapes;
}

}  // namespace

MouthNetworkTraining trainMouthNetwork(const std::vector<NetworkRecording>& recordings,
                                       const std::vector<int>& visualFaps, const MouthNetworkOptions& options,
                                       const std::vector<NetworkRecording>& validation) {
  options.check();
  if (recordings.empty()) throw Error("mouth network: no training recordings");
  MouthNetwork model;
  model.pastSubframes = options.pastSubframes;
  model.futureSubframes = options.futureSubframes;
  model.normalisation = options.normalisation;
  model.visualFaps = visualFaps;

  // The speech's prior mean, the FAP basis, the lips' shape statistics and the class shares, over the training
  // recordings that have each.
  Eigen::VectorXd mfccSum = Eigen::VectorXd::Zero(kNetworkMfcc);
  double subframes = 0.0;
  Eigen::Index fapFrames = 0, shapeFrames = 0;
  Eigen::VectorXd classCounts = Eigen::VectorXd::Constant(kClasses, 1.0);  // add-one
  for (const NetworkRecording& r : recordings) {
    if (r.subframes.mfcc.rows() != kNetworkMfcc)
      throw Error("mouth network: recording " + r.name + " has " + std::to_string(r.subframes.mfcc.rows()) +
                  " MFCCs a subframe, not " + std::to_string(kNetworkMfcc));
    if (r.faps.cols() > 0 && r.faps.rows() != static_cast<Eigen::Index>(visualFaps.size()))
      throw Error("mouth network: recording " + r.name + " has " + std::to_string(r.faps.rows()) + " FAP rows for " +
                  std::to_string(visualFaps.size()) + " FAPs");
    mfccSum += r.subframes.mfcc.rowwise().sum();
    subframes += static_cast<double>(r.subframes.numFrames());
    fapFrames += r.faps.cols();
    shapeFrames += r.lipShape.cols();
    for (const int c : r.classes)
      if (c >= 0) classCounts[c] += 1.0;
  }
  if (subframes < 1.0) throw Error("mouth network: the training recordings hold no speech");
  if (fapFrames <= options.visualComponents) throw Error("mouth network: too few frames of tracked FAPs");
  model.priorMean = mfccSum / subframes;
  Eigen::MatrixXd allFaps(static_cast<Eigen::Index>(visualFaps.size()), fapFrames);
  Eigen::MatrixXd allShapes(2, shapeFrames);
  Eigen::Index fapColumn = 0, shapeColumn = 0;
  for (const NetworkRecording& r : recordings) {
    allFaps.middleCols(fapColumn, r.faps.cols()) = r.faps;
    fapColumn += r.faps.cols();
    allShapes.middleCols(shapeColumn, r.lipShape.cols()) = r.lipShape;
    shapeColumn += r.lipShape.cols();
  }
  // FAPs share one unit (FAPU counts): not standardised, so the lips' small FAPs do not weigh as the jaw.
  model.basis = VisualBasis::fit(allFaps, {.components = options.visualComponents, .standardise = false});
  if (shapeFrames > 1) {
    model.shapeMean = allShapes.rowwise().mean();
    model.shapeDeviation =
        ((allShapes.colwise() - model.shapeMean).array().square().rowwise().mean().sqrt()).max(1e-6).matrix();
  }
  model.classPriors = classCounts / classCounts.sum();
  std::vector<std::vector<int>> labels;
  for (const NetworkRecording& r : recordings)
    if (!r.classes.empty()) labels.push_back(r.classes);
  model.sequence = classSequenceOf(labels);
  model.classShapes = classShapesOf(recordings, static_cast<Eigen::Index>(visualFaps.size()));

  model.heads = headsFor(options.visualComponents);
  model.heads[kClassHead].weight = options.classWeight;
  model.heads[kComponentHead].weight = options.visualWeight;
  model.heads[kShapeHead].weight = options.shapeWeight;
  model.heads[kShutHead].weight = options.closureWeight;
  const int outputs = kClasses + options.visualComponents + 3;
  model.network = nn::Network::create(
      {.inputs = model.contextSubframes() * model.inputsPerSubframe(), .hidden = options.hidden, .outputs = outputs},
      options.training.seed);
  const nn::Frames training = framesOf(model, recordings, options.closedOpening);
  model.network.fitStandardisation(training.inputs);
  MouthNetworkTraining result;
  if (validation.empty()) {
    result.report = nn::train(model.network, model.heads, training, nullptr, options.training);
  } else {
    const nn::Frames held = framesOf(model, validation, options.closedOpening);
    result.report = nn::train(model.network, model.heads, training, &held, options.training);
  }
  result.model = std::move(model);
  return result;
}

MouthNetworkOutput runMouthNetwork(const MouthNetwork& model, const SpeechFrames& subframes,
                                   const Eigen::VectorXd* startMean) {
  Eigen::MatrixXf outputs = model.network.forward(mouthNetworkInputs(model, subframes, startMean));
  nn::applyHeads(model.heads, outputs);
  const int k = model.basis.components();
  MouthNetworkOutput out;
  out.classes = outputs.topRows(kClasses).cast<double>();
  out.components = outputs.middleRows(kClasses, k).cast<double>();
  out.lipShape = (model.shapeDeviation.asDiagonal() * outputs.middleRows(kClasses + k, 2).cast<double>()).colwise() +
                 model.shapeMean;
  out.shut = outputs.row(kClasses + k + 2).cast<double>();
  return out;
}

MouthNetworkStream::MouthNetworkStream(const MouthNetwork& model)
    : model_(model),
      normaliser_(model.normalisation, kSubframesPerSecond, model.priorMean),
      inference_(model.network),
      input_(model.contextSubframes() * model.inputsPerSubframe()),
      output_(model.network.outputs(), 1) {}

void MouthNetworkStream::accept(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc) {
  if (finished_) throw Error("mouth network stream: a subframe after the end of the input");
  if (mfcc.size() != kNetworkMfcc)
    throw Error("mouth network stream: a subframe must have " + std::to_string(kNetworkMfcc) + " MFCCs");
  Eigen::VectorXd out(model_.inputsPerSubframe());
  normaliser_.accept(levelDb, mfcc, out);
  normalised_.push_back(std::move(out));
  ++received_;
}

void MouthNetworkStream::finish() {
  finished_ = true;
}

bool MouthNetworkStream::next(MouthNetworkFrame& frame) {
  const Eigen::Index centre = nextFrame_ * kSubframesPerFrame;
  const bool ready = finished_ ? centre < received_ : centre + model_.futureSubframes < received_;
  if (!ready) return false;
  // As stackFrame: the subframes centre - past .. centre + future, the edges repeated.
  const Eigen::Index rows = model_.inputsPerSubframe();
  for (int k = -model_.pastSubframes; k <= model_.futureSubframes; ++k) {
    const Eigen::Index source = std::clamp<Eigen::Index>(centre + k, 0, received_ - 1);
    input_.segment((k + model_.pastSubframes) * rows, rows) =
        normalised_[static_cast<std::size_t>(source - base_)].cast<float>();
  }
  output_.col(0) = inference_.run(input_);
  nn::applyHeads(model_.heads, output_);
  const int k = model_.basis.components();
  frame.classes = output_.col(0).head(kClasses).cast<double>();
  frame.shut = output_(kClasses + k + 2, 0);
  ++nextFrame_;
  // The next frame looks back to its centre - past.
  const Eigen::Index keepFrom = std::max<Eigen::Index>(0, nextFrame_ * kSubframesPerFrame - model_.pastSubframes);
  while (base_ < keepFrom && !normalised_.empty()) {
    normalised_.pop_front();
    ++base_;
  }
  return true;
}

Eigen::MatrixXd mouthNetworkFaps(const MouthNetwork& model, const MouthNetworkOutput& output) {
  Eigen::MatrixXd faps = model.basis.reconstruct(output.components);
  for (std::size_t i = 0; i < model.visualFaps.size(); ++i)
    if (model.visualFaps[i] == 3)
      faps.row(static_cast<Eigen::Index>(i)) = faps.row(static_cast<Eigen::Index>(i)).cwiseMax(0.0);
  return faps;
}

namespace {

Json vectorJson(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

Json matrixJson(const Eigen::MatrixXd& m) {
  Json rows = Json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) rows.push_back(vectorJson(m.row(r).transpose()));
  return rows;
}

Eigen::VectorXd vectorOf(const JsonFields& fields, const Json& value, const std::string& field, Eigen::Index size) {
  const Json& list = fields.array(value, field);
  if (size >= 0 && static_cast<Eigen::Index>(list.size()) != size)
    fields.fail(field, "must hold " + std::to_string(size) + " numbers");
  Eigen::VectorXd v(static_cast<Eigen::Index>(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i)
    v[static_cast<Eigen::Index>(i)] = fields.number(list[i], JsonFields::indexed(field, i));
  return v;
}

Eigen::MatrixXd matrixOf(const JsonFields& fields, const Json& value, const std::string& field) {
  const Json& rows = fields.array(value, field);
  if (rows.empty()) fields.fail(field, "is empty");
  const Eigen::VectorXd first = vectorOf(fields, rows[0], JsonFields::indexed(field, 0), -1);
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()), first.size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    m.row(static_cast<Eigen::Index>(r)) = vectorOf(fields, rows[r], JsonFields::indexed(field, r), first.size());
  return m;
}

}  // namespace

void saveMouthNetwork(const std::filesystem::path& path, const MouthNetwork& model) {
  Json json = {{"kind", kKind},
               {"format_version", kFormatVersion},
               {"classes", std::vector<std::string>(face::kMouthClassNames.begin(), face::kMouthClassNames.end())},
               {"past_subframes", model.pastSubframes},
               {"future_subframes", model.futureSubframes},
               {"subframes_per_second", kSubframesPerSecond},
               {"speech_normalisation", features::speechNormalisationJson(model.normalisation, model.priorMean)},
               {"visual_faps", model.visualFaps},
               {"visual_basis",
                {{"mean", vectorJson(model.basis.mean())},
                 {"scale", vectorJson(model.basis.scale())},
                 {"unmixing", matrixJson(model.basis.unmixing())},
                 {"mixing", matrixJson(model.basis.mixing())},
                 {"explained_variance", model.basis.explainedVariance()}}},
               {"lip_shape_mean", vectorJson(model.shapeMean)},
               {"lip_shape_deviation", vectorJson(model.shapeDeviation)},
               {"class_priors", vectorJson(model.classPriors)},
               {"class_shapes", matrixJson(model.classShapes)},
               {"class_sequence",
                {{"mean_run", vectorJson(model.sequence.meanRun)},
                 {"bigrams", matrixJson(model.sequence.bigrams)},
                 {"starts", vectorJson(model.sequence.starts)}}},
               {"network", nn::networkJson(model.network)}};
  if (model.openingGradient.size() > 0) json["opening_gradient"] = vectorJson(model.openingGradient);
  AtomicFile out(path);
  out.stream() << json.dump(1) << "\n";
  out.commit();
}

namespace {

// The visual FAPs and the basis of their components, which must match.
void readVisualParts(const Json& json, const JsonFields& fields, const std::filesystem::path& path,
                     MouthNetwork& model) {
  const Json& faps = fields.array(fields.member(json, "visual_faps", ""), "visual_faps");
  for (std::size_t i = 0; i < faps.size(); ++i) {
    const std::int64_t fap = fields.integer(faps[i], JsonFields::indexed("visual_faps", i));
    if (fap < 1 || fap > 68 || (!model.visualFaps.empty() && fap <= model.visualFaps.back()))
      fields.fail(JsonFields::indexed("visual_faps", i), "must be FAP numbers 1..68 in ascending order");
    model.visualFaps.push_back(static_cast<int>(fap));
  }
  const Json& basis = fields.object(fields.member(json, "visual_basis", ""), "visual_basis");
  try {
    model.basis = VisualBasis::fromParts(
        vectorOf(fields, fields.member(basis, "mean", "visual_basis"), "visual_basis.mean", -1),
        vectorOf(fields, fields.member(basis, "scale", "visual_basis"), "visual_basis.scale", -1),
        matrixOf(fields, fields.member(basis, "unmixing", "visual_basis"), "visual_basis.unmixing"),
        matrixOf(fields, fields.member(basis, "mixing", "visual_basis"), "visual_basis.mixing"),
        fields.number(fields.member(basis, "explained_variance", "visual_basis"), "visual_basis.explained_variance"));
  } catch (const Error& error) {
    const std::string what = error.what();
    if (what.rfind(path.string(), 0) == 0) throw;
    fields.fail("visual_basis", what);
  }
  if (model.basis.inputDimension() != static_cast<int>(model.visualFaps.size()))
    fields.fail("visual_faps", "must name one FAP per row of the visual basis");
}

// How the mouth classes follow one another (articulation.h's class HMM), checked.
ClassSequence classSequenceFrom(const Json& sequence, const JsonFields& fields) {
  ClassSequence result;
  fields.object(sequence, "class_sequence");
  fields.onlyKnownFields(sequence, {"mean_run", "bigrams", "starts"}, "class_sequence");
  result.meanRun =
      vectorOf(fields, fields.member(sequence, "mean_run", "class_sequence"), "class_sequence.mean_run", kClasses);
  result.starts =
      vectorOf(fields, fields.member(sequence, "starts", "class_sequence"), "class_sequence.starts", kClasses);
  result.bigrams = matrixOf(fields, fields.member(sequence, "bigrams", "class_sequence"), "class_sequence.bigrams");
  if (result.bigrams.rows() != kClasses || result.bigrams.cols() != kClasses)
    fields.fail("class_sequence.bigrams", "must be 17 x 17");
  if ((result.meanRun.array() < 0.0).any() || (result.starts.array() <= 0.0).any() ||
      (result.bigrams.array() <= 0.0).any())
    fields.fail("class_sequence", "runs must be >= 0, starts and bigrams > 0");
  return result;
}

}  // namespace

MouthNetwork loadMouthNetwork(const std::filesystem::path& path) {
  const Json json = readJsonFile(path, "mouth network");
  const JsonFields fields(path.string());
  fields.object(json, "");
  fields.onlyKnownFields(
      json,
      {"kind", "format_version", "classes", "past_subframes", "future_subframes", "subframes_per_second",
       "speech_normalisation", "visual_faps", "visual_basis", "lip_shape_mean", "lip_shape_deviation", "class_priors",
       "class_shapes", "class_sequence", "opening_gradient", "network"},
      "");
  if (fields.string(fields.member(json, "kind", ""), "kind") != kKind)
    fields.fail("kind", std::string("must be \"") + kKind + "\"");
  if (fields.integer(fields.member(json, "format_version", ""), "format_version") != kFormatVersion)
    fields.fail("format_version", "must be " + std::to_string(kFormatVersion));
  const Json& names = fields.array(fields.member(json, "classes", ""), "classes");
  if (names.size() != face::kMouthClassNames.size()) fields.fail("classes", "must list the 17 mouth classes");
  for (std::size_t c = 0; c < names.size(); ++c)
    if (fields.string(names[c], JsonFields::indexed("classes", c)) != face::kMouthClassNames[c])
      fields.fail(JsonFields::indexed("classes", c), "must be \"" + std::string(face::kMouthClassNames[c]) + "\"");
  MouthNetwork model;
  const auto integer = [&](const char* key, int low, int high) {
    const std::int64_t value = fields.integer(fields.member(json, key, ""), key);
    if (value < low || value > high) fields.fail(key, "must be " + std::to_string(low) + ".." + std::to_string(high));
    return static_cast<int>(value);
  };
  model.pastSubframes = integer("past_subframes", 0, 90);
  model.futureSubframes = integer("future_subframes", 0, 45);
  if (fields.number(fields.member(json, "subframes_per_second", ""), "subframes_per_second") != kSubframesPerSecond)
    fields.fail("subframes_per_second", "must be " + std::to_string(kSubframesPerSecond));
  model.normalisation = features::readSpeechNormalisation(fields.member(json, "speech_normalisation", ""), fields,
                                                          "speech_normalisation", model.priorMean, kNetworkMfcc);
  readVisualParts(json, fields, path, model);
  model.shapeMean = vectorOf(fields, fields.member(json, "lip_shape_mean", ""), "lip_shape_mean", 2);
  model.shapeDeviation = vectorOf(fields, fields.member(json, "lip_shape_deviation", ""), "lip_shape_deviation", 2);
  if ((model.shapeDeviation.array() <= 0.0).any()) fields.fail("lip_shape_deviation", "must be positive");
  model.classPriors = vectorOf(fields, fields.member(json, "class_priors", ""), "class_priors", kClasses);
  if ((model.classPriors.array() <= 0.0).any() || std::abs(model.classPriors.sum() - 1.0) > 1e-6)
    fields.fail("class_priors", "must be positive and sum to 1");
  model.classShapes = matrixOf(fields, fields.member(json, "class_shapes", ""), "class_shapes");
  if (model.classShapes.rows() != static_cast<Eigen::Index>(model.visualFaps.size()) ||
      model.classShapes.cols() != kClasses)
    fields.fail("class_shapes", "must be one row of 17 per visual FAP");
  model.sequence = classSequenceFrom(fields.member(json, "class_sequence", ""), fields);
  if (json.contains("opening_gradient"))
    model.openingGradient = vectorOf(fields, json["opening_gradient"], "opening_gradient",
                                     static_cast<Eigen::Index>(model.visualFaps.size()));
  model.network = nn::networkFromJson(fields.member(json, "network", ""), fields, "network");
  const int k = model.basis.components();
  if (model.network.inputs() != model.contextSubframes() * model.inputsPerSubframe())
    fields.fail("network", "has " + std::to_string(model.network.inputs()) + " inputs; the context needs " +
                               std::to_string(model.contextSubframes() * model.inputsPerSubframe()));
  if (model.network.outputs() != kClasses + k + 3)
    fields.fail("network", "has " + std::to_string(model.network.outputs()) + " outputs; the heads need " +
                               std::to_string(kClasses + k + 3));
  model.heads = headsFor(k);
  return model;
}

}  // namespace th::animation
