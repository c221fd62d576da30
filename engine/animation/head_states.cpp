#include "animation/head_states.h"

#include <Eigen/LU>

#include "animation/mlpg.h"
#include "core/error.h"
#include "hmm/viterbi.h"

namespace th::animation {

StateTables tablesOf(const HeadModel& model, double smoothing) {
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
    frames.push_back(
        {tables.poseMean[j], tables.posePrecision[j], tables.deltaMean[j], tables.deltaPrecision[j], {}, {}});
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

hmm::HmmModel prosodyModel(const HeadModel& model) {
  return marginal(model.hmm, prosodyBegin(model), ProsodyTracker::kDimension);
}

Eigen::MatrixXd gatedEmissions(const hmm::HmmModel& decoder, const Eigen::MatrixXd& prosody,
                               const Eigen::RowVectorXd& voiced, bool voicedOnly) {
  Eigen::MatrixXd logB = decoder.emissionLogLikelihoods(prosody);
  if (!voicedOnly || voiced.size() == 0) return logB;
  if (voiced.size() != prosody.cols()) throw Error("head synthesis: voicing and prosody differ in length");
  for (Eigen::Index t = 0; t < logB.cols(); ++t)
    if (voiced[t] <= 0.0) logB.col(t).setZero();
  return logB;
}

Eigen::Vector3d outputScale(const HeadModel& model, const HeadSynthesisOptions& options) {
  return options.amplitude * options.axisGain.cwiseProduct(model.amplitude);
}

Eigen::MatrixXd meanTrajectory(const HeadModel& model, const Eigen::MatrixXd& prosody, const Eigen::RowVectorXd& voiced,
                               bool voicedOnly, double smoothing) {
  const hmm::HmmModel decoder = prosodyModel(model);
  const std::vector<int> states = hmm::viterbi(decoder, gatedEmissions(decoder, prosody, voiced, voicedOnly)).states;
  return trajectoryFor(tablesOf(model, smoothing), states, 0, states.size());
}

}  // namespace th::animation
