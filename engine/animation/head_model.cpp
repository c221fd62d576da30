#include "animation/head_model.h"

#include <Eigen/LU>
#include <nlohmann/json.hpp>
#include <map>
#include <random>
#include <string>

#include "animation/mlpg.h"
#include "core/error.h"
#include "core/json_reading.h"
#include "core/frame_store.h"
#include "hmm/forward_filter.h"
#include "hmm/entropic_training.h"
#include "hmm/forward_backward.h"
#include "hmm/model_file.h"
#include "hmm/viterbi.h"

namespace th::animation {
namespace {

// Layout of the joint model's observation: motion | motion_delta | motion_acceleration | prosody. Models made
// before the acceleration block (motion | motion_delta | prosody) still load: their trajectory has no
// acceleration term.
constexpr int kMotionBegin = 0;
constexpr int kDeltaBegin = 3;
constexpr int kAccelerationBegin = 6;
constexpr int kProsodyBegin = 9;
constexpr int kDimension = 13;
constexpr int kOldProsodyBegin = 6;
constexpr int kOldDimension = 10;

int prosodyBegin(const HeadModel& model) { return model.hasAcceleration ? kProsodyBegin : kOldProsodyBegin; }

// Per state: the pose and velocity Gaussians that synthesis reads.
struct StateTables {
  std::vector<Eigen::Vector3d> poseMean;
  std::vector<Eigen::Matrix3d> posePrecision;
  std::vector<Eigen::Vector3d> deltaMean;
  std::vector<Eigen::Matrix3d> deltaPrecision;
  std::vector<Eigen::Vector3d> accelerationMean;        // empty without the acceleration block
  std::vector<Eigen::Matrix3d> accelerationPrecision;
  Eigen::MatrixXd poseMeans;  // 3 x N, for posterior-weighted means
};

// smoothing multiplies the velocity and acceleration precisions: above 1 the trajectory moves more slowly.
StateTables tablesOf(const HeadModel& model, double smoothing = 1.0) {
  StateTables tables;
  const int n = model.hmm.numStates();
  tables.poseMeans.resize(3, n);
  for (int j = 0; j < n; ++j) {
    const hmm::Gaussian& g = model.hmm.states[static_cast<size_t>(j)].components().front();
    tables.poseMean.push_back(g.mean().segment<3>(kMotionBegin));
    tables.posePrecision.push_back(g.covariance().block<3, 3>(kMotionBegin, kMotionBegin).inverse());
    tables.deltaMean.push_back(g.mean().segment<3>(kDeltaBegin));
    tables.deltaPrecision.push_back(smoothing * g.covariance().block<3, 3>(kDeltaBegin, kDeltaBegin).inverse());
    if (model.hasAcceleration) {
      tables.accelerationMean.push_back(g.mean().segment<3>(kAccelerationBegin));
      tables.accelerationPrecision.push_back(
          smoothing * g.covariance().block<3, 3>(kAccelerationBegin, kAccelerationBegin).inverse());
    }
    tables.poseMeans.col(j) = tables.poseMean.back();
  }
  return tables;
}

Eigen::MatrixXd trajectoryFor(const StateTables& tables, const std::vector<int>& states, size_t begin, size_t end) {
  std::vector<MlpgFrame> frames;
  frames.reserve(end - begin);
  for (size_t t = begin; t < end; ++t) {
    const auto j = static_cast<size_t>(states[t]);
    frames.push_back({tables.poseMean[j], tables.posePrecision[j], tables.deltaMean[j], tables.deltaPrecision[j], {}, {}});
    if (!tables.accelerationMean.empty()) {
      frames.back().accelerationMean = tables.accelerationMean[j];
      frames.back().accelerationPrecision = tables.accelerationPrecision[j];
    }
  }
  return generateTrajectory(frames);
}

hmm::HmmModel marginal(const hmm::HmmModel& model, int begin, int size) {
  hmm::HmmModel result;
  result.initial = model.initial;
  result.transition = model.transition;
  for (const auto& state : model.states) {
    std::vector<hmm::Gaussian> components;
    for (const auto& g : state.components()) {
      components.emplace_back(g.mean().segment(begin, size), g.covariance().block(begin, begin, size, size), g.type());
    }
    result.states.emplace_back(state.weights(), std::move(components));
  }
  return result;
}

const std::vector<std::string>& columnNames() {
  static const std::vector<std::string> names = {
      "pitch",    "yaw",      "roll",      "d_pitch",  "d_yaw",  "d_roll",     "dd_pitch",
      "dd_yaw",   "dd_roll",  "pitch_st",  "energy",   "d_pitch_st", "d_energy"};
  return names;
}

}  // namespace

hmm::HmmModel prosodyModel(const HeadModel& model) {
  return marginal(model.hmm, prosodyBegin(model), ProsodyTracker::kDimension);
}

// Unvoiced and silent frames carry no prosody the model knows (the pitch is held, the energy is the room's):
// their emissions are made equal for every state, so only the transitions (which favour staying) decide there.
Eigen::MatrixXd gatedEmissions(const hmm::HmmModel& decoder, const Eigen::MatrixXd& prosody,
                               const Eigen::RowVectorXd& voiced, bool voicedOnly) {
  Eigen::MatrixXd logB = decoder.emissionLogLikelihoods(prosody);
  if (!voicedOnly || voiced.size() == 0) return logB;
  if (voiced.size() != prosody.cols()) throw Error("head synthesis: voicing and prosody differ in length");
  for (Eigen::Index t = 0; t < logB.cols(); ++t)
    if (voiced[t] <= 0.0) logB.col(t).setZero();
  return logB;
}

// Rotations in the model's units to degrees.
Eigen::Vector3d outputScale(const HeadModel& model, const HeadSynthesisOptions& options) {
  return options.amplitude * model.amplitude;
}

// The motion the voice does not explain — the variance the states' smooth trajectory leaves out of the training
// motion's, in pose and in frame-to-frame step — as a random process with that spread and step. Per axis a
// second-order autoregression with a double pole r, x_t = 2r x_{t−1} − r² x_{t−2} + σ ε_t: unlike a first-order
// one (white steps) its velocity is smooth, as a head's is. With ρ₁ its lag-1 autocorrelation, the step variance
// is 2 s² (1 − ρ₁), so ρ₁ = 1 − v² / (2 s²), r solves 2r / (1 + r²) = ρ₁, and σ gives the stationary variance s².
// It is quieter in pauses: after kHoldSeconds without a voice its gain eases to pauseVariation (people move less
// while silent). Deterministic for a seed; frames in order, so the batch and the online synthesis agree.
class ResidualMotion {
 public:
  static constexpr double kHoldSeconds = 0.3;
  static constexpr double kEaseSeconds = 0.3;

  ResidualMotion(const HeadModel& model, const HeadSynthesisOptions& options)
      : random_(options.seed), variation_(options.variation), pauseGain_(options.pauseVariation) {
    for (int axis = 0; axis < 3; ++axis) {
      const double s = model.residualStd[axis];
      const double v = model.residualStepStd[axis];
      if (s <= 0.0 || v <= 0.0) continue;  // a1 = a2 = σ = 0: no residual on this axis
      const double rho = std::clamp(1.0 - v * v / (2.0 * s * s), 0.0, 0.9999);
      const double r = rho > 0.0 ? (1.0 - std::sqrt(1.0 - rho * rho)) / rho : 0.0;
      a1_[axis] = 2.0 * r;
      a2_[axis] = -r * r;
      // γ₀ = σ² (1 − φ₂) / ((1 + φ₂)((1 − φ₂)² − φ₁²)) for x_t = φ₁ x_{t−1} + φ₂ x_{t−2} + σ ε_t.
      const double phi1 = a1_[axis], phi2 = a2_[axis];
      sigma_[axis] = s * std::sqrt((1.0 + phi2) * ((1.0 - phi2) * (1.0 - phi2) - phi1 * phi1) / (1.0 - phi2));
    }
  }

  Eigen::Vector3d next(bool voiced) {
    constexpr double kFps = 30.0;
    framesSinceVoice_ = voiced ? 0 : framesSinceVoice_ + 1;
    const double target = framesSinceVoice_ <= kHoldSeconds * kFps ? 1.0 : pauseGain_;
    gain_ += (target - gain_) / (kEaseSeconds * kFps);
    for (int axis = 0; axis < 3; ++axis) {
      const double x = a1_[axis] * last_[axis] + a2_[axis] * beforeLast_[axis] + sigma_[axis] * normal_(random_);
      beforeLast_[axis] = last_[axis];
      last_[axis] = x;
    }
    return variation_ * gain_ * last_;
  }

 private:
  std::mt19937 random_;
  std::normal_distribution<double> normal_;
  double variation_;
  double pauseGain_;
  Eigen::Vector3d a1_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d a2_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d beforeLast_ = Eigen::Vector3d::Zero();
  int framesSinceVoice_ = 1 << 20;  // the start counts as a pause
  double gain_ = 0.0;
};

// The trajectory through the Viterbi states, in model units (batch).
Eigen::MatrixXd meanTrajectory(const HeadModel& model, const Eigen::MatrixXd& prosody, const Eigen::RowVectorXd& voiced,
                               bool voicedOnly, double smoothing) {
  const hmm::HmmModel decoder = prosodyModel(model);
  const std::vector<int> states = hmm::viterbi(decoder, gatedEmissions(decoder, prosody, voiced, voicedOnly)).states;
  return trajectoryFor(tablesOf(model, smoothing), states, 0, states.size());
}

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
  model.amplitude = options.normaliseSpeakers ? Eigen::Vector3d(logSpread.array().exp().matrix()) : Eigen::Vector3d::Ones();
  std::vector<Eigen::MatrixXd> motion;
  for (const auto& part : parts) {
    const SpeakerNorm& norm = norms.at(part.speaker);
    Eigen::MatrixXd centred = part.rotations.colwise() - norm.mean;
    if (options.normaliseSpeakers) centred = norm.spread.cwiseInverse().asDiagonal() * centred;
    motion.push_back(std::move(centred));
  }

  // 1. The motion HMM, with the entropic prior carving the structure.
  hmm::TrainingOptions training;
  training.numStates = options.startStates;
  training.numMixtures = 1;
  training.covariance = hmm::CovarianceType::kFull;
  training.maxIterations = options.maxIterations;
  training.seed = options.seed;
  const hmm::TrainingResult result = hmm::trainHmm(
      motion, training,
      hmm::entropicHooks({.multinomialWeight = options.entropicWeightPerFrame * totalFrames,
                          .covarianceWeight = options.covariancePriorWeight,
                          .warmupIterations = options.warmupIterations,
                          .rampIterations = options.rampIterations}));
  const hmm::HmmModel& motionModel = result.model;
  model.history = result.history;

  // 2. Re-map velocities, accelerations and prosody onto the motion states through γ (paper, step 3). The
  // prosody only where the voice is: unvoiced frames are not decoded by it either (gatedEmissions).
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
    const hmm::Posteriors posteriors =
        hmm::forwardBackward(motionModel, motionModel.emissionLogLikelihoods(motion[s]));
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
  Eigen::VectorXd allMean = Eigen::VectorXd::Zero(kProsody);
  Eigen::MatrixXd allSecond = Eigen::MatrixXd::Zero(kProsody, kProsody);
  double allCount = 0.0;
  for (const auto& kept : voicedProsody) {
    allMean += kept.rowwise().sum();
    allSecond += kept * kept.transpose();
    allCount += static_cast<double>(kept.cols());
  }
  allMean /= allCount;
  const Eigen::MatrixXd allCovariance = allSecond / allCount - allMean * allMean.transpose();
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
    model.hmm.states.emplace_back(Eigen::VectorXd::Ones(1),
                                  std::vector<hmm::Gaussian>{hmm::Gaussian(jointMean, joint, hmm::CovarianceType::kFull)});
  }
  model.hmm.columnNames = columnNames();
  model.hmm.blocks = {{"motion", kMotionBegin, 3},
                      {"motion_delta", kDeltaBegin, 3},
                      {"motion_acceleration", kAccelerationBegin, 3},
                      {"prosody", kProsodyBegin, 4}};
  model.hmm.check();

  // 3. What the voice does not explain: the part of the training motion's variance, and of its frame-to-frame
  // steps' variance, that the trajectory from the prosody leaves out. ResidualMotion draws a process with
  // those, independent of the trajectory, so that the two together move as much as the training speakers.
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
    history.push_back({{"log_likelihood", record.logLikelihood}, {"log_prior", record.logPrior},
                       {"live_states", record.liveStates}, {"step_gain", record.stepGain}});
  }
  training["history"] = history;
  hmm::saveModel(path, model.hmm, training.dump());
}

HeadModel loadHeadModel(const std::filesystem::path& path) {
  std::string trainingText;
  HeadModel model;
  model.hmm = hmm::loadModel(path, &trainingText);
  const Json training = parseJson(trainingText, path.string(), {.maxDepth = 64, .depthNote = "", .subject = "the training metadata"});
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
  const bool newLayout = model.hasAcceleration && model.hmm.dimension() == kDimension &&
                         blockIs("prosody", kProsodyBegin, 4);
  const bool oldLayout = !model.hasAcceleration && model.hmm.dimension() == kOldDimension &&
                         blockIs("prosody", kOldProsodyBegin, 4);
  if (!blockIs("motion", kMotionBegin, 3) || !blockIs("motion_delta", kDeltaBegin, 3) || !(newLayout || oldLayout)) {
    throw fileError(path, "a head model needs blocks motion (0, 3), motion_delta (3, 3), motion_acceleration (6, 3) "
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

Eigen::MatrixXd synthesiseHead(const HeadModel& model, const Eigen::MatrixXd& prosody, const Eigen::RowVectorXd& voiced,
                               const HeadSynthesisOptions& options) {
  if (prosody.rows() != ProsodyTracker::kDimension) throw Error("head synthesis: prosody must have 4 rows");
  if (voiced.size() != 0 && voiced.size() != prosody.cols())
    throw Error("head synthesis: voicing and prosody differ in length");
  if (prosody.cols() == 0) return Eigen::MatrixXd(3, 0);
  if (options.maxLagFrames >= 0) {
    HeadSynthesiser online(model, options);
    for (Eigen::Index t = 0; t < prosody.cols(); ++t) online.acceptProsody(prosody.col(t), voiced.size() == 0 || voiced[t] > 0.0);
    online.finish();
    Eigen::MatrixXd out(3, prosody.cols());
    for (int t = 0; t < online.numReady(); ++t) out.col(t) = online.rotation(t);
    return out;
  }
  const hmm::HmmModel decoder = prosodyModel(model);
  const StateTables tables = tablesOf(model, options.smoothing);
  const Eigen::MatrixXd logB = gatedEmissions(decoder, prosody, voiced, options.voicedOnly);
  const Eigen::Vector3d scale = outputScale(model, options);
  if (options.variant == HeadVariant::kPosteriorMeans) {
    return scale.asDiagonal() * (tables.poseMeans * hmm::forwardBackward(decoder, logB).stateGivenAll);
  }
  const std::vector<int> states = hmm::viterbi(decoder, logB).states;
  if (options.variant == HeadVariant::kTrajectory) {
    Eigen::MatrixXd out = trajectoryFor(tables, states, 0, states.size());
    ResidualMotion residual(model, options);
    for (Eigen::Index t = 0; t < out.cols(); ++t) out.col(t) += residual.next(voiced.size() == 0 || voiced[t] > 0.0);
    return scale.asDiagonal() * out;
  }
  Eigen::MatrixXd out(3, prosody.cols());
  for (size_t t = 0; t < states.size(); ++t)
    out.col(static_cast<Eigen::Index>(t)) = scale.cwiseProduct(tables.poseMean[static_cast<size_t>(states[t])]);
  return out;
}

struct HeadSynthesiser::Impl {
  HeadSynthesisOptions options;
  HeadModel model;
  hmm::HmmModel decoder;
  StateTables tables;
  std::unique_ptr<hmm::OnlineViterbi> viterbi;
  std::unique_ptr<hmm::FixedLagSmoother> smoother;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();  // model units to degrees
  std::unique_ptr<ResidualMotion> residual;         // trajectory: drawn frame by frame as the prosody comes
  FrameStore<Eigen::Vector3d> residuals;
  std::vector<Eigen::Vector4d> pending;  // batch mode: everything, solved at finish()
  std::vector<double> pendingVoiced;
  FrameStore<int> decided;               // online trajectory: states decided so far (the recent ones kept)
  FrameStore<Eigen::Vector3d> ready;
  bool finished = false;
  std::unique_ptr<hmm::ForwardFilter> filter;  // P(state | prosody so far), for display

  void drain() {
    if (options.variant == HeadVariant::kPosteriorMeans) {
      while (smoother->numReady() > static_cast<int>(ready.size())) {
        ready.push_back(scale.cwiseProduct(tables.poseMeans * smoother->posterior(static_cast<int>(ready.size()))));
      }
      return;
    }
    while (viterbi->numDecided() > static_cast<int>(decided.size())) decided.push_back(viterbi->state(static_cast<int>(decided.size())));
    viterbi->forgetBefore(static_cast<int>(decided.size()));  // copied here
    if (options.variant == HeadVariant::kStateMeans) {
      while (decided.size() > ready.size())
        ready.push_back(scale.cwiseProduct(tables.poseMean[static_cast<size_t>(decided[ready.size()])]));
      return;
    }
    // Trajectory: frame t once the states up to t + lookahead are known (or all of them, at the end).
    const auto lookahead = static_cast<size_t>(options.trajectoryLookaheadFrames);
    while (ready.size() < decided.size() && (finished || ready.size() + lookahead < decided.size())) {
      const size_t t = ready.size();
      const size_t begin = t > static_cast<size_t>(options.trajectoryWindowFrames) ? t - static_cast<size_t>(options.trajectoryWindowFrames) : 0;
      const size_t end = std::min(decided.size(), t + lookahead + 1);
      std::vector<int> window(end - begin);
      for (size_t i = begin; i < end; ++i) window[i - begin] = decided[i];
      ready.push_back(scale.cwiseProduct(
          trajectoryFor(tables, window, 0, window.size()).col(static_cast<Eigen::Index>(t - begin)) + residuals[t]));
    }
  }
};

HeadSynthesiser::HeadSynthesiser(const HeadModel& model, const HeadSynthesisOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->model = model;
  impl_->decoder = prosodyModel(model);
  impl_->tables = tablesOf(model, options.smoothing);
  impl_->scale = outputScale(model, options);
  if (options.variant == HeadVariant::kTrajectory) impl_->residual = std::make_unique<ResidualMotion>(model, options);
  impl_->filter = std::make_unique<hmm::ForwardFilter>(impl_->decoder);
  if (options.maxLagFrames < 0) return;
  if (options.variant == HeadVariant::kPosteriorMeans) {
    impl_->smoother = std::make_unique<hmm::FixedLagSmoother>(impl_->decoder, options.maxLagFrames);
  } else {
    impl_->viterbi = std::make_unique<hmm::OnlineViterbi>(impl_->decoder, hmm::OnlineViterbiOptions{options.maxLagFrames});
  }
}

HeadSynthesiser::~HeadSynthesiser() = default;

void HeadSynthesiser::acceptProsody(const Eigen::Vector4d& prosody, bool voiced) {
  if (impl_->finished) throw Error("head synthesis: prosody after finish()");
  if (impl_->options.maxLagFrames < 0) {
    impl_->pending.push_back(prosody);
    impl_->pendingVoiced.push_back(voiced ? 1.0 : 0.0);
    return;
  }
  Eigen::VectorXd logB = impl_->decoder.emissionLogLikelihoods(prosody).col(0);
  if (impl_->options.voicedOnly && !voiced) logB.setZero();
  if (impl_->residual) impl_->residuals.push_back(impl_->residual->next(voiced));
  impl_->filter->accept(logB);
  if (impl_->smoother) {
    impl_->smoother->acceptFrame(logB);
  } else {
    impl_->viterbi->acceptFrame(logB);
  }
  impl_->drain();
}

void HeadSynthesiser::finish() {
  if (impl_->finished) return;
  impl_->finished = true;
  if (impl_->options.maxLagFrames < 0) {
    Eigen::MatrixXd prosody(ProsodyTracker::kDimension, static_cast<Eigen::Index>(impl_->pending.size()));
    for (size_t t = 0; t < impl_->pending.size(); ++t) prosody.col(static_cast<Eigen::Index>(t)) = impl_->pending[t];
    const Eigen::RowVectorXd voiced =
        Eigen::Map<const Eigen::RowVectorXd>(impl_->pendingVoiced.data(), static_cast<Eigen::Index>(impl_->pendingVoiced.size()));
    const Eigen::MatrixXd rotations = synthesiseHead(impl_->model, prosody, voiced, impl_->options);
    for (Eigen::Index t = 0; t < rotations.cols(); ++t) impl_->ready.push_back(rotations.col(t));
    return;
  }
  if (impl_->smoother) {
    impl_->smoother->finish();
  } else {
    impl_->viterbi->finish();
  }
  impl_->drain();
}

int HeadSynthesiser::numReady() const { return static_cast<int>(impl_->ready.size()); }

Eigen::Vector3d HeadSynthesiser::rotation(int frame) const {
  const auto f = static_cast<size_t>(frame);
  if (frame < 0 || f < impl_->ready.firstKept() || f >= impl_->ready.size())
    throw Error("head synthesis: frame " + std::to_string(frame) + " is not held");
  return impl_->ready[f];
}

void HeadSynthesiser::forgetBefore(int frame) {
  const auto f = static_cast<size_t>(std::max(0, frame));
  impl_->ready.forgetBefore(f);
  // The trajectory of a later frame is solved over the trajectoryWindowFrames states before it.
  const auto window = static_cast<size_t>(std::max(0, impl_->options.trajectoryWindowFrames));
  impl_->decided.forgetBefore(f > window ? f - window : 0);
  impl_->residuals.forgetBefore(f);
}

const Eigen::VectorXd& HeadSynthesiser::filteredPosterior() const { return impl_->filter->posterior(); }

int HeadSynthesiser::numStates() const { return impl_->decoder.numStates(); }

std::size_t HeadSynthesiser::framesHeld() const {
  return impl_->ready.held() + impl_->decided.held() + impl_->residuals.held() + (impl_->viterbi ? impl_->viterbi->framesHeld() : 0);
}

int headLookaheadFrames(const HeadSynthesisOptions& options) {
  if (options.maxLagFrames < 0) return -1;
  return options.maxLagFrames + (options.variant == HeadVariant::kTrajectory ? options.trajectoryLookaheadFrames : 0);
}

int HeadSynthesiser::lookaheadFrames() const { return headLookaheadFrames(impl_->options); }

Eigen::MatrixXd randomWalkHead(const HeadModel& model, int numFrames, unsigned seed) {
  std::mt19937 random(seed);
  const StateTables tables = tablesOf(model);
  const hmm::HmmModel& hmm = model.hmm;
  auto draw = [&random](const Eigen::VectorXd& probabilities) {
    std::discrete_distribution<int> pick(probabilities.data(), probabilities.data() + probabilities.size());
    return pick(random);
  };
  Eigen::MatrixXd out(3, numFrames);
  int state = draw(hmm.initial);
  for (int t = 0; t < numFrames; ++t) {
    if (t > 0) state = draw(hmm.transition.row(state).transpose());
    out.col(t) = model.amplitude.cwiseProduct(tables.poseMean[static_cast<size_t>(state)]);
  }
  return out;
}

}  // namespace th::animation
