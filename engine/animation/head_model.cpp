#include "animation/head_model.h"

#include <Eigen/LU>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "animation/head_states.h"
#include "animation/mlpg.h"
#include "core/error.h"
#include "core/frame_store.h"
#include "core/json_reading.h"
#include "hmm/entropic_training.h"
#include "hmm/forward_backward.h"
#include "hmm/forward_filter.h"
#include "hmm/model_file.h"
#include "hmm/viterbi.h"

namespace th::animation {
namespace {

const std::vector<std::string>& columnNames() {
  static const std::vector<std::string> names = {"pitch",  "yaw",        "roll",    "d_pitch", "d_yaw",
                                                 "d_roll", "dd_pitch",   "dd_yaw",  "dd_roll", "pitch_st",
                                                 "energy", "d_pitch_st", "d_energy"};
  return names;
}

}  // namespace

namespace {

// Per speaker: the mean pose and the per-axis spread of all its recordings.
struct SpeakerNorm {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d spread = Eigen::Vector3d::Ones();
};

std::map<std::string, SpeakerNorm> speakerNorms(const std::vector<HeadRecording>& parts) {
  std::map<std::string, Eigen::Vector3d> sum, sumSquares;
  std::map<std::string, double> count;
  for (const auto& part : parts) {
    if (!count.contains(part.speaker)) {
      sum[part.speaker].setZero();
      sumSquares[part.speaker].setZero();
      count[part.speaker] = 0.0;
    }
    sum[part.speaker] += part.rotations.rowwise().sum();
    sumSquares[part.speaker] += part.rotations.array().square().matrix().rowwise().sum();
    count[part.speaker] += part.numFrames();
  }
  std::map<std::string, SpeakerNorm> norms;
  for (const auto& [speaker, n] : count) {
    SpeakerNorm norm;
    norm.mean = sum[speaker] / n;
    norm.spread = (sumSquares[speaker] / n - norm.mean.cwiseProduct(norm.mean)).cwiseMax(1e-6).cwiseSqrt();
    norms[speaker] = norm;
  }
  return norms;
}

// Step 1: the motion HMM, with the entropic prior carving the structure.
hmm::TrainingResult trainMotionHmm(const std::vector<Eigen::MatrixXd>& motion, double totalFrames,
                                   const HeadModelOptions& options) {
  hmm::TrainingOptions training;
  training.numStates = options.startStates;
  training.numMixtures = 1;
  training.covariance = hmm::CovarianceType::kFull;
  training.maxIterations = options.maxIterations;
  training.seed = options.seed;
  return hmm::trainHmm(motion, training,
                       hmm::entropicHooks({.multinomialWeight = options.entropicWeightPerFrame * totalFrames,
                                           .covarianceWeight = options.covariancePriorWeight,
                                           .warmupIterations = options.warmupIterations,
                                           .rampIterations = options.rampIterations}));
}

// The mean and covariance of the prosody of every voiced frame.
std::pair<Eigen::VectorXd, Eigen::MatrixXd> allVoicedProsody(const std::vector<Eigen::MatrixXd>& voicedProsody) {
  constexpr int kProsody = ProsodyTracker::kDimension;
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(kProsody);
  Eigen::MatrixXd second = Eigen::MatrixXd::Zero(kProsody, kProsody);
  double count = 0.0;
  for (const auto& kept : voicedProsody) {
    mean += kept.rowwise().sum();
    second += kept * kept.transpose();
    count += static_cast<double>(kept.cols());
  }
  mean /= count;
  Eigen::MatrixXd covariance = second / count - mean * mean.transpose();
  return {std::move(mean), std::move(covariance)};
}

// Step 2: re-map velocities, accelerations and prosody onto the motion states through γ (paper, step 3). The
// prosody only where the voice is: unvoiced frames are not decoded by it either (gatedEmissions).
void remapOntoMotionStates(const hmm::HmmModel& motionModel, const std::vector<HeadRecording>& parts,
                           const std::vector<Eigen::MatrixXd>& motion, HeadModel& model) {
  const int n = motionModel.numStates();
  constexpr int kDynamic = 6;
  constexpr int kProsody = ProsodyTracker::kDimension;
  Eigen::VectorXd occupancy = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd voicedOccupancy = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd dynamicFirst = Eigen::MatrixXd::Zero(kDynamic, n);
  Eigen::MatrixXd prosodyFirst = Eigen::MatrixXd::Zero(kProsody, n);
  std::vector<Eigen::MatrixXd> dynamicSecond(static_cast<size_t>(n), Eigen::MatrixXd::Zero(kDynamic, kDynamic));
  std::vector<Eigen::MatrixXd> prosodySecond(static_cast<size_t>(n), Eigen::MatrixXd::Zero(kProsody, kProsody));
  std::vector<Eigen::MatrixXd> dynamics;
  std::vector<Eigen::MatrixXd> voicedProsody;
  for (size_t s = 0; s < parts.size(); ++s) {
    Eigen::MatrixXd y(kDynamic, parts[s].numFrames());
    y.topRows(3) = deltas(motion[s]);
    y.bottomRows(3) = accelerations(motion[s]);
    const Eigen::MatrixXd& p = parts[s].prosody;
    const Eigen::RowVectorXd voiced =
        parts[s].voiced.size() != 0 ? parts[s].voiced : Eigen::RowVectorXd::Ones(parts[s].numFrames());
    const hmm::Posteriors posteriors = hmm::forwardBackward(motionModel, motionModel.emissionLogLikelihoods(motion[s]));
    for (int j = 0; j < n; ++j) {
      const Eigen::VectorXd gamma = posteriors.stateGivenAll.row(j).transpose();
      const Eigen::VectorXd voicedGamma = gamma.cwiseProduct(voiced.transpose());
      occupancy[j] += gamma.sum();
      voicedOccupancy[j] += voicedGamma.sum();
      dynamicFirst.col(j) += y * gamma;
      dynamicSecond[static_cast<size_t>(j)] += y * gamma.asDiagonal() * y.transpose();
      prosodyFirst.col(j) += p * voicedGamma;
      prosodySecond[static_cast<size_t>(j)] += p * voicedGamma.asDiagonal() * p.transpose();
    }
    dynamics.push_back(std::move(y));
    Eigen::MatrixXd kept(kProsody, static_cast<Eigen::Index>(voiced.sum()));
    for (Eigen::Index t = 0, k = 0; t < p.cols(); ++t)
      if (voiced[t] > 0.0) kept.col(k++) = p.col(t);
    if (kept.cols() > 0) voicedProsody.push_back(std::move(kept));
  }
  if (voicedProsody.empty()) throw Error("head model: no voiced frame in the training data");
  const Eigen::VectorXd dynamicFloor = hmm::varianceFloorFor(dynamics, 1e-3);
  const Eigen::VectorXd prosodyFloor = hmm::varianceFloorFor(voicedProsody, 1e-3);
  // The prosody of all voiced frames: a state the voice never visits decodes as the average voice.
  const auto [allMean, allCovariance] = allVoicedProsody(voicedProsody);
  model.hmm.initial = motionModel.initial;
  model.hmm.transition = motionModel.transition;
  for (int j = 0; j < n; ++j) {
    const hmm::Gaussian& pose = motionModel.states[static_cast<size_t>(j)].components().front();
    const double gamma = std::max(occupancy[j], 1e-12);
    const Eigen::VectorXd dynamicMean = dynamicFirst.col(j) / gamma;
    const Eigen::MatrixXd dynamicCovariance =
        dynamicSecond[static_cast<size_t>(j)] / gamma - dynamicMean * dynamicMean.transpose();
    // A few voiced frames make a poor Gaussian: shrink toward all voiced frames' (a prior of 10 frames).
    constexpr double kPriorFrames = 10.0;
    const double voicedGamma = voicedOccupancy[j];
    const Eigen::VectorXd prosodyMean = (prosodyFirst.col(j) + kPriorFrames * allMean) / (voicedGamma + kPriorFrames);
    const Eigen::MatrixXd prosodyCovariance =
        (prosodySecond[static_cast<size_t>(j)] + kPriorFrames * (allCovariance + allMean * allMean.transpose())) /
            (voicedGamma + kPriorFrames) -
        prosodyMean * prosodyMean.transpose();
    Eigen::VectorXd jointMean(kDimension);
    jointMean << pose.mean(), dynamicMean, prosodyMean;
    // Independent blocks, as the paper maps each modality on its own.
    Eigen::MatrixXd joint = Eigen::MatrixXd::Zero(kDimension, kDimension);
    joint.block<3, 3>(kMotionBegin, kMotionBegin) = pose.covariance();
    joint.block<3, 3>(kDeltaBegin, kDeltaBegin) = hmm::applyCovarianceFloor(
        dynamicCovariance.topLeftCorner(3, 3), dynamicFloor.head(3), hmm::CovarianceType::kFull);
    joint.block<3, 3>(kAccelerationBegin, kAccelerationBegin) = hmm::applyCovarianceFloor(
        dynamicCovariance.bottomRightCorner(3, 3), dynamicFloor.tail(3), hmm::CovarianceType::kFull);
    joint.block<4, 4>(kProsodyBegin, kProsodyBegin) =
        hmm::applyCovarianceFloor(prosodyCovariance, prosodyFloor, hmm::CovarianceType::kFull);
    model.hmm.states.emplace_back(Eigen::VectorXd::Ones(1), std::vector<hmm::Gaussian>{hmm::Gaussian(
                                                                jointMean, joint, hmm::CovarianceType::kFull)});
  }
  model.hmm.columnNames = columnNames();
  model.hmm.blocks = {{"motion", kMotionBegin, 3},
                      {"motion_delta", kDeltaBegin, 3},
                      {"motion_acceleration", kAccelerationBegin, 3},
                      {"prosody", kProsodyBegin, 4}};
  model.hmm.check();
}

// Step 3: what the voice does not explain: the part of the training motion's variance, and of its frame-to-frame
// steps' variance, that the trajectory from the prosody leaves out. ResidualMotion draws a process with
// those, independent of the trajectory, so that the two together move as much as the training speakers.
void fitResidualMotion(const std::vector<HeadRecording>& parts, const std::vector<Eigen::MatrixXd>& motion,
                       const std::map<std::string, SpeakerNorm>& norms, const HeadModelOptions& options,
                       HeadModel& model) {
  Eigen::Vector3d motionVariance = Eigen::Vector3d::Zero(), motionStepVariance = Eigen::Vector3d::Zero();
  Eigen::Vector3d curveVariance = Eigen::Vector3d::Zero(), curveStepVariance = Eigen::Vector3d::Zero();
  double frames = 0.0, steps = 0.0;
  const auto addMoments = [](const Eigen::MatrixXd& x, Eigen::Vector3d& variance, Eigen::Vector3d& stepVariance) {
    const Eigen::MatrixXd centred = x.colwise() - x.rowwise().mean();
    variance += centred.array().square().matrix().rowwise().sum();
    stepVariance += (x.rightCols(x.cols() - 1) - x.leftCols(x.cols() - 1)).array().square().matrix().rowwise().sum();
  };
  // The trajectory moves less on speech the model never heard than on its training speech, so with several
  // speakers each one's trajectory comes from a model trained without it (as the shipped model meets a new
  // voice); with one, from the model itself.
  std::map<std::string, HeadModel> without;
  if (options.residualFromHeldOutSpeakers && norms.size() > 1) {
    HeadModelOptions inner = options;
    inner.residualFromHeldOutSpeakers = false;
    for (const auto& [speaker, norm] : norms) {
      std::vector<HeadRecording> others;
      for (const auto& part : parts)
        if (part.speaker != speaker) others.push_back(part);
      without.emplace(speaker, trainHeadModel(others, inner));
    }
  }
  for (size_t s = 0; s < parts.size(); ++s) {
    const auto found = without.find(parts[s].speaker);
    const HeadModel& decoder = found != without.end() ? found->second : model;
    addMoments(motion[s], motionVariance, motionStepVariance);
    addMoments(meanTrajectory(decoder, parts[s].prosody, parts[s].voiced, true, 1.0), curveVariance, curveStepVariance);
    frames += static_cast<double>(motion[s].cols());
    steps += static_cast<double>(motion[s].cols() - 1);
  }
  model.residualStd = ((motionVariance - curveVariance) / frames).cwiseMax(0.0).cwiseSqrt();
  model.residualStepStd = ((motionStepVariance - curveStepVariance) / steps).cwiseMax(0.0).cwiseSqrt();
}

}  // namespace

HeadModel trainHeadModel(const std::vector<HeadRecording>& parts, const HeadModelOptions& options) {
  if (parts.empty()) throw Error("head model: no training data");
  double totalFrames = 0.0;
  for (const auto& part : parts) {
    if (part.prosody.cols() != part.rotations.cols()) throw Error("head model: prosody and rotations differ in length");
    if (part.voiced.size() != 0 && part.voiced.size() != part.rotations.cols())
      throw Error("head model: voicing and rotations differ in length");
    if (part.numFrames() < 3) throw Error("head model: a recording of fewer than 3 frames");
    totalFrames += part.numFrames();
  }
  HeadModel model;
  model.hasAcceleration = true;
  // Each speaker's motion about its own mean pose; with normaliseSpeakers, also in units of its own spread, so
  // a lively and a calm speaker teach the same shapes, and the output is scaled by the speakers' mean spread.
  const std::map<std::string, SpeakerNorm> norms = speakerNorms(parts);
  // The output's size: the speakers' geometric mean spread (spreads are scales: a speaker moving twice and one
  // moving half as much as the output are equally far from it).
  Eigen::Vector3d meanPose = Eigen::Vector3d::Zero();
  Eigen::Vector3d logSpread = Eigen::Vector3d::Zero();
  for (const auto& [speaker, norm] : norms) {
    meanPose += norm.mean / static_cast<double>(norms.size());
    logSpread += norm.spread.array().log().matrix() / static_cast<double>(norms.size());
    model.speakers.push_back(speaker);
  }
  model.meanPose = meanPose;
  model.amplitude =
      options.normaliseSpeakers ? Eigen::Vector3d(logSpread.array().exp().matrix()) : Eigen::Vector3d::Ones();
  std::vector<Eigen::MatrixXd> motion;
  for (const auto& part : parts) {
    const SpeakerNorm& norm = norms.at(part.speaker);
    Eigen::MatrixXd centred = part.rotations.colwise() - norm.mean;
    if (options.normaliseSpeakers) centred = norm.spread.cwiseInverse().asDiagonal() * centred;
    motion.push_back(std::move(centred));
  }

  const hmm::TrainingResult result = trainMotionHmm(motion, totalFrames, options);
  model.history = result.history;
  remapOntoMotionStates(result.model, parts, motion, model);
  fitResidualMotion(parts, motion, norms, options, model);
  return model;
}

void saveHeadModel(const std::filesystem::path& path, const HeadModel& model, const HeadModelOptions& options) {
  nlohmann::json training;
  training["kind"] = "head";
  training["mean_pose_deg"] = {model.meanPose[0], model.meanPose[1], model.meanPose[2]};
  training["amplitude_deg"] = {model.amplitude[0], model.amplitude[1], model.amplitude[2]};
  training["speakers"] = model.speakers;
  training["residual_std"] = {model.residualStd[0], model.residualStd[1], model.residualStd[2]};
  training["residual_step_std"] = {model.residualStepStd[0], model.residualStepStd[1], model.residualStepStd[2]};
  training["options"] = {{"start_states", options.startStates},
                         {"normalise_speakers", options.normaliseSpeakers},
                         {"entropic_weight_per_frame", options.entropicWeightPerFrame},
                         {"covariance_prior", options.covariancePriorWeight},
                         {"warmup", options.warmupIterations},
                         {"ramp", options.rampIterations},
                         {"max_iterations", options.maxIterations},
                         {"seed", options.seed}};
  nlohmann::json history = nlohmann::json::array();
  for (const auto& record : model.history) {
    history.push_back({{"log_likelihood", record.logLikelihood},
                       {"log_prior", record.logPrior},
                       {"live_states", record.liveStates},
                       {"step_gain", record.stepGain}});
  }
  training["history"] = history;
  hmm::saveModel(path, model.hmm, training.dump());
}

HeadModel loadHeadModel(const std::filesystem::path& path) {
  std::string trainingText;
  HeadModel model;
  model.hmm = hmm::loadModel(path, &trainingText);
  const Json training =
      parseJson(trainingText, path.string(), {.maxDepth = 64, .depthNote = "", .subject = "the training metadata"});
  const JsonFields fields(path.string());
  if (!training.is_object() || !training.contains("kind") || training["kind"] != "head") {
    throw fileError(path, "is an HMM file but not a head model (training.kind is not \"head\")");
  }
  const auto blockIs = [&](const std::string& name, int begin, int size) {
    for (const auto& block : model.hmm.blocks) {
      if (block.name == name) return block.begin == begin && block.size == size;
    }
    return false;
  };
  model.hasAcceleration = blockIs("motion_acceleration", kAccelerationBegin, 3);
  const bool newLayout =
      model.hasAcceleration && model.hmm.dimension() == kDimension && blockIs("prosody", kProsodyBegin, 4);
  const bool oldLayout =
      !model.hasAcceleration && model.hmm.dimension() == kOldDimension && blockIs("prosody", kOldProsodyBegin, 4);
  if (!blockIs("motion", kMotionBegin, 3) || !blockIs("motion_delta", kDeltaBegin, 3) || !(newLayout || oldLayout)) {
    throw fileError(path,
                    "a head model needs blocks motion (0, 3), motion_delta (3, 3), motion_acceleration (6, 3) "
                    "and prosody (9, 4), or the older motion, motion_delta and prosody (6, 4)");
  }
  const auto readVector = [&](const char* key, Eigen::Vector3d& out) {
    const Json& value = fields.member(training, key, "training");
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
        !value[2].is_number()) {
      throw fileError(path, std::string("training.") + key + " must be 3 numbers");
    }
    out = {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
    if (!out.allFinite()) throw fileError(path, std::string("training.") + key + " is not finite");
  };
  readVector("mean_pose_deg", model.meanPose);
  if (training.contains("amplitude_deg")) {
    readVector("amplitude_deg", model.amplitude);
    if ((model.amplitude.array() <= 0.0).any()) throw fileError(path, "training.amplitude_deg must be positive");
  }
  if (training.contains("residual_std")) {
    readVector("residual_std", model.residualStd);
    readVector("residual_step_std", model.residualStepStd);
    if ((model.residualStd.array() < 0.0).any() || (model.residualStepStd.array() < 0.0).any())
      throw fileError(path, "training.residual_std and residual_step_std must not be negative");
  }
  if (training.contains("speakers") && training["speakers"].is_array()) {
    for (const auto& speaker : training["speakers"])
      if (speaker.is_string()) model.speakers.push_back(speaker.get<std::string>());
  }
  return model;
}

}  // namespace th::animation
