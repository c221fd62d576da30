#include "hmm/audio_retraining.h"

#include <Eigen/Cholesky>

#include "core/error.h"
#include "hmm/inversion.h"
#include "hmm/training.h"

namespace th::hmm {

double assembleJointCovariance(const Eigen::MatrixXd& audioCovariance, const Eigen::MatrixXd& crossAudioVisual,
                               const Eigen::MatrixXd& visualCovariance, const ObservationBlock& audio,
                               const ObservationBlock& visual, Eigen::MatrixXd& joint) {
  const int d = audio.size + visual.size;
  double factor = 1.0;
  for (int attempt = 0; attempt < 400; ++attempt) {
    joint.setZero(d, d);
    joint.block(audio.begin, audio.begin, audio.size, audio.size) = audioCovariance;
    joint.block(visual.begin, visual.begin, visual.size, visual.size) = visualCovariance;
    joint.block(audio.begin, visual.begin, audio.size, visual.size) = factor * crossAudioVisual;
    joint.block(visual.begin, audio.begin, visual.size, audio.size) = factor * crossAudioVisual.transpose();
    if (Eigen::LLT<Eigen::MatrixXd>(joint).info() == Eigen::Success) return factor;
    factor *= 0.9;
  }
  // With no cross-covariance left the matrix is block diagonal, positive definite if both blocks are.
  joint.block(audio.begin, visual.begin, audio.size, visual.size).setZero();
  joint.block(visual.begin, audio.begin, visual.size, audio.size).setZero();
  if (Eigen::LLT<Eigen::MatrixXd>(joint).info() != Eigen::Success) {
    throw Error("audio re-training: a covariance block is not positive definite");
  }
  return 0.0;
}

AudioRetrainingResult retrainAudio(const HmmModel& jointModel, const std::vector<Eigen::MatrixXd>& audioSequences,
                                   const AudioRetrainingOptions& options) {
  const HmmInverter marginal(jointModel, {.audioBlock = options.audioBlock, .visualBlock = options.visualBlock});
  HmmModel audioModel = marginal.audioModel();
  for (const auto& sequence : audioSequences) {
    if (sequence.rows() != audioModel.dimension()) throw Error("audio re-training: audio has the wrong dimension");
  }
  EstimationHooks fixedStructure;
  // π, A and the mixture weights stay as the joint model learnt them: only the densities move.
  fixedStructure.multinomial = [](Multinomial, const Eigen::VectorXd&, const Eigen::VectorXd& previous,
                                  const MStepContext&) { return previous; };
  const Eigen::VectorXd floor = varianceFloorFor(audioSequences, options.varianceFloorFraction);
  AudioRetrainingResult result;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    result.logLikelihoods.push_back(
        baumWelchIteration(audioModel, audioSequences, floor, fixedStructure).logLikelihood);
  }

  const ObservationBlock& audio = jointModel.block(options.audioBlock);
  const ObservationBlock& visual = jointModel.block(options.visualBlock);
  result.model = jointModel;
  for (int j = 0; j < jointModel.numStates(); ++j) {
    const GaussianMixture& old = jointModel.states[static_cast<size_t>(j)];
    std::vector<Gaussian> components;
    for (int m = 0; m < old.numComponents(); ++m) {
      const Gaussian& joint = old.components()[static_cast<size_t>(m)];
      const Gaussian& newAudio = audioModel.states[static_cast<size_t>(j)].components()[static_cast<size_t>(m)];
      Eigen::VectorXd mean = joint.mean();
      mean.segment(audio.begin, audio.size) = newAudio.mean();
      const Eigen::MatrixXd& sigma = joint.covariance();
      Eigen::MatrixXd covariance;
      const double factor = assembleJointCovariance(
          newAudio.covariance(), sigma.block(audio.begin, visual.begin, audio.size, visual.size),
          sigma.block(visual.begin, visual.begin, visual.size, visual.size), audio, visual, covariance);
      if (factor < 1.0) ++result.repairedComponents;
      components.emplace_back(mean, covariance, joint.type());
    }
    result.model.states[static_cast<size_t>(j)] = GaussianMixture(old.weights(), std::move(components));
  }
  result.model.check();
  return result;
}

}  // namespace th::hmm
