#include "animation/head_model.h"

#include <Eigen/LU>
#include <nlohmann/json.hpp>
#include <random>

#include "animation/mlpg.h"
#include "core/error.h"
#include "core/frame_store.h"
#include "hmm/forward_filter.h"
#include "hmm/entropic_training.h"
#include "hmm/forward_backward.h"
#include "hmm/model_file.h"
#include "hmm/viterbi.h"

namespace th::animation {
namespace {

// Layout of the joint model's observation: motion | motion_delta | prosody.
constexpr int kMotionBegin = 0;
constexpr int kDeltaBegin = 3;
constexpr int kProsodyBegin = 6;
constexpr int kDimension = 10;

// Per state: the pose and velocity Gaussians that synthesis reads.
struct StateTables {
  std::vector<Eigen::Vector3d> poseMean;
  std::vector<Eigen::Matrix3d> posePrecision;
  std::vector<Eigen::Vector3d> deltaMean;
  std::vector<Eigen::Matrix3d> deltaPrecision;
  Eigen::MatrixXd poseMeans;  // 3 x N, for posterior-weighted means
};

StateTables tablesOf(const HeadModel& model) {
  StateTables tables;
  const int n = model.hmm.numStates();
  tables.poseMeans.resize(3, n);
  for (int j = 0; j < n; ++j) {
    const hmm::Gaussian& g = model.hmm.states[static_cast<size_t>(j)].components().front();
    tables.poseMean.push_back(g.mean().segment<3>(kMotionBegin));
    tables.posePrecision.push_back(g.covariance().block<3, 3>(kMotionBegin, kMotionBegin).inverse());
    tables.deltaMean.push_back(g.mean().segment<3>(kDeltaBegin));
    tables.deltaPrecision.push_back(g.covariance().block<3, 3>(kDeltaBegin, kDeltaBegin).inverse());
    tables.poseMeans.col(j) = tables.poseMean.back();
  }
  return tables;
}

Eigen::MatrixXd trajectoryFor(const StateTables& tables, const std::vector<int>& states, size_t begin, size_t end) {
  std::vector<MlpgFrame> frames;
  frames.reserve(end - begin);
  for (size_t t = begin; t < end; ++t) {
    const auto j = static_cast<size_t>(states[t]);
    frames.push_back({tables.poseMean[j], tables.posePrecision[j], tables.deltaMean[j], tables.deltaPrecision[j]});
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
  static const std::vector<std::string> names = {"pitch_deg",   "yaw_deg",     "roll_deg",   "d_pitch_deg", "d_yaw_deg",
                                                 "d_roll_deg",  "pitch_st",    "energy",     "d_pitch_st",  "d_energy"};
  return names;
}

}  // namespace

hmm::HmmModel prosodyModel(const HeadModel& model) {
  return marginal(model.hmm, kProsodyBegin, ProsodyTracker::kDimension);
}

HeadModel trainHeadModel(const std::vector<HeadRecording>& parts, const HeadModelOptions& options) {
  if (parts.empty()) throw Error("head model: no training data");
  double totalFrames = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& part : parts) {
    if (part.prosody.cols() != part.rotations.cols()) throw Error("head model: prosody and rotations differ in length");
    totalFrames += part.numFrames();
    sum += part.rotations.rowwise().sum();
  }
  HeadModel model;
  model.meanPose = sum / totalFrames;
  std::vector<Eigen::MatrixXd> motion;
  for (const auto& part : parts) motion.push_back(part.rotations.colwise() - model.meanPose);

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

  // 2. Re-map velocities and prosody onto the motion states through γ (paper, step 3).
  const int n = motionModel.numStates();
  constexpr int kMapped = 3 + ProsodyTracker::kDimension;
  Eigen::VectorXd occupancy = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd firstMoment = Eigen::MatrixXd::Zero(kMapped, n);
  std::vector<Eigen::MatrixXd> secondMoment(static_cast<size_t>(n), Eigen::MatrixXd::Zero(kMapped, kMapped));
  std::vector<Eigen::MatrixXd> mapped;
  for (size_t s = 0; s < parts.size(); ++s) {
    Eigen::MatrixXd y(kMapped, parts[s].numFrames());
    y.topRows(3) = deltas(motion[s]);
    y.bottomRows(ProsodyTracker::kDimension) = parts[s].prosody;
    const hmm::Posteriors posteriors =
        hmm::forwardBackward(motionModel, motionModel.emissionLogLikelihoods(motion[s]));
    for (int j = 0; j < n; ++j) {
      const Eigen::VectorXd gamma = posteriors.stateGivenAll.row(j).transpose();
      occupancy[j] += gamma.sum();
      firstMoment.col(j) += y * gamma;
      secondMoment[static_cast<size_t>(j)] += y * gamma.asDiagonal() * y.transpose();
    }
    mapped.push_back(std::move(y));
  }
  const Eigen::VectorXd floor = hmm::varianceFloorFor(mapped, 1e-3);
  model.hmm.initial = motionModel.initial;
  model.hmm.transition = motionModel.transition;
  for (int j = 0; j < n; ++j) {
    const hmm::Gaussian& pose = motionModel.states[static_cast<size_t>(j)].components().front();
    const double gamma = std::max(occupancy[j], 1e-12);
    const Eigen::VectorXd mean = firstMoment.col(j) / gamma;
    const Eigen::MatrixXd covariance = secondMoment[static_cast<size_t>(j)] / gamma - mean * mean.transpose();
    Eigen::VectorXd jointMean(kDimension);
    jointMean << pose.mean(), mean;
    // Independent blocks, as the paper maps each modality on its own.
    Eigen::MatrixXd joint = Eigen::MatrixXd::Zero(kDimension, kDimension);
    joint.block<3, 3>(kMotionBegin, kMotionBegin) = pose.covariance();
    joint.block<3, 3>(kDeltaBegin, kDeltaBegin) =
        hmm::applyCovarianceFloor(covariance.topLeftCorner(3, 3), floor.head(3), hmm::CovarianceType::kFull);
    joint.block<4, 4>(kProsodyBegin, kProsodyBegin) =
        hmm::applyCovarianceFloor(covariance.bottomRightCorner(4, 4), floor.tail(4), hmm::CovarianceType::kFull);
    model.hmm.states.emplace_back(Eigen::VectorXd::Ones(1),
                                  std::vector<hmm::Gaussian>{hmm::Gaussian(jointMean, joint, hmm::CovarianceType::kFull)});
  }
  model.hmm.columnNames = columnNames();
  model.hmm.blocks = {{"motion", kMotionBegin, 3}, {"motion_delta", kDeltaBegin, 3}, {"prosody", kProsodyBegin, 4}};
  model.hmm.check();
  return model;
}

void saveHeadModel(const std::filesystem::path& path, const HeadModel& model, const HeadModelOptions& options) {
  nlohmann::json training;
  training["kind"] = "head";
  training["mean_pose_deg"] = {model.meanPose[0], model.meanPose[1], model.meanPose[2]};
  training["options"] = {{"start_states", options.startStates},
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
  const nlohmann::json training = nlohmann::json::parse(trainingText, nullptr, false);
  if (!training.is_object() || !training.contains("kind") || training["kind"] != "head") {
    throw fileError(path, "is an HMM file but not a head model (training.kind is not \"head\")");
  }
  const auto blockIs = [&](const std::string& name, int begin, int size) {
    for (const auto& block : model.hmm.blocks) {
      if (block.name == name) return block.begin == begin && block.size == size;
    }
    return false;
  };
  if (model.hmm.dimension() != kDimension || !blockIs("motion", kMotionBegin, 3) ||
      !blockIs("motion_delta", kDeltaBegin, 3) || !blockIs("prosody", kProsodyBegin, 4)) {
    throw fileError(path, "a head model needs blocks motion (0, 3), motion_delta (3, 3) and prosody (6, 4)");
  }
  if (!training.contains("mean_pose_deg")) throw fileError(path, "training.mean_pose_deg is missing");
  const auto& pose = training["mean_pose_deg"];
  if (!pose.is_array() || pose.size() != 3 || !pose[0].is_number() || !pose[1].is_number() || !pose[2].is_number()) {
    throw fileError(path, "training.mean_pose_deg must be 3 numbers");
  }
  model.meanPose = {pose[0].get<double>(), pose[1].get<double>(), pose[2].get<double>()};
  if (!model.meanPose.allFinite()) throw fileError(path, "training.mean_pose_deg is not finite");
  return model;
}

Eigen::MatrixXd synthesiseHead(const HeadModel& model, const Eigen::MatrixXd& prosody,
                               const HeadSynthesisOptions& options) {
  if (prosody.rows() != ProsodyTracker::kDimension) throw Error("head synthesis: prosody must have 4 rows");
  if (prosody.cols() == 0) return Eigen::MatrixXd(3, 0);
  if (options.maxLagFrames >= 0) {
    HeadSynthesiser online(model, options);
    for (Eigen::Index t = 0; t < prosody.cols(); ++t) online.acceptProsody(prosody.col(t));
    online.finish();
    Eigen::MatrixXd out(3, prosody.cols());
    for (int t = 0; t < online.numReady(); ++t) out.col(t) = online.rotation(t);
    return out;
  }
  const hmm::HmmModel decoder = prosodyModel(model);
  const StateTables tables = tablesOf(model);
  const Eigen::MatrixXd logB = decoder.emissionLogLikelihoods(prosody);
  if (options.variant == HeadVariant::kPosteriorMeans) {
    return tables.poseMeans * hmm::forwardBackward(decoder, logB).stateGivenAll;
  }
  const std::vector<int> states = hmm::viterbi(decoder, logB).states;
  if (options.variant == HeadVariant::kTrajectory) return trajectoryFor(tables, states, 0, states.size());
  Eigen::MatrixXd out(3, prosody.cols());
  for (size_t t = 0; t < states.size(); ++t) out.col(static_cast<Eigen::Index>(t)) = tables.poseMean[static_cast<size_t>(states[t])];
  return out;
}

struct HeadSynthesiser::Impl {
  HeadSynthesisOptions options;
  HeadModel model;
  hmm::HmmModel decoder;
  StateTables tables;
  std::unique_ptr<hmm::OnlineViterbi> viterbi;
  std::unique_ptr<hmm::FixedLagSmoother> smoother;
  std::vector<Eigen::Vector4d> pending;  // batch mode: everything, solved at finish()
  FrameStore<int> decided;               // online trajectory: states decided so far (the recent ones kept)
  FrameStore<Eigen::Vector3d> ready;
  bool finished = false;
  std::unique_ptr<hmm::ForwardFilter> filter;  // P(state | prosody so far), for display

  void drain() {
    if (options.variant == HeadVariant::kPosteriorMeans) {
      while (smoother->numReady() > static_cast<int>(ready.size())) {
        ready.push_back(tables.poseMeans * smoother->posterior(static_cast<int>(ready.size())));
      }
      return;
    }
    while (viterbi->numDecided() > static_cast<int>(decided.size())) decided.push_back(viterbi->state(static_cast<int>(decided.size())));
    viterbi->forgetBefore(static_cast<int>(decided.size()));  // copied here
    if (options.variant == HeadVariant::kStateMeans) {
      while (decided.size() > ready.size()) ready.push_back(tables.poseMean[static_cast<size_t>(decided[ready.size()])]);
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
      ready.push_back(trajectoryFor(tables, window, 0, window.size()).col(static_cast<Eigen::Index>(t - begin)));
    }
  }
};

HeadSynthesiser::HeadSynthesiser(const HeadModel& model, const HeadSynthesisOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  impl_->model = model;
  impl_->decoder = prosodyModel(model);
  impl_->tables = tablesOf(model);
  impl_->filter = std::make_unique<hmm::ForwardFilter>(impl_->decoder);
  if (options.maxLagFrames < 0) return;
  if (options.variant == HeadVariant::kPosteriorMeans) {
    impl_->smoother = std::make_unique<hmm::FixedLagSmoother>(impl_->decoder, options.maxLagFrames);
  } else {
    impl_->viterbi = std::make_unique<hmm::OnlineViterbi>(impl_->decoder, hmm::OnlineViterbiOptions{options.maxLagFrames});
  }
}

HeadSynthesiser::~HeadSynthesiser() = default;

void HeadSynthesiser::acceptProsody(const Eigen::Vector4d& prosody) {
  if (impl_->finished) throw Error("head synthesis: prosody after finish()");
  if (impl_->options.maxLagFrames < 0) {
    impl_->pending.push_back(prosody);
    return;
  }
  const Eigen::VectorXd logB = impl_->decoder.emissionLogLikelihoods(prosody).col(0);
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
    const Eigen::MatrixXd rotations = synthesiseHead(impl_->model, prosody, impl_->options);
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
}

const Eigen::VectorXd& HeadSynthesiser::filteredPosterior() const { return impl_->filter->posterior(); }

int HeadSynthesiser::numStates() const { return impl_->decoder.numStates(); }

std::size_t HeadSynthesiser::framesHeld() const {
  return impl_->ready.held() + impl_->decided.held() + (impl_->viterbi ? impl_->viterbi->framesHeld() : 0);
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
    out.col(t) = tables.poseMean[static_cast<size_t>(state)];
  }
  return out;
}

}  // namespace th::animation
