#include "hmm/inversion.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <random>

#include "core/error.h"
#include "hmm/forward_backward.h"

namespace th::hmm {
namespace {

Eigen::MatrixXd subBlock(const Eigen::MatrixXd& m, int rowBegin, int rows, int colBegin, int cols) {
  return m.block(rowBegin, colBegin, rows, cols);
}

}  // namespace

HmmInverter::HmmInverter(const HmmModel& jointModel, const InversionOptions& options)
    : jointModel_(jointModel), options_(options) {
  jointModel_.check();
  const ObservationBlock& audio = jointModel_.block(options.audioBlock);
  const ObservationBlock& visual = jointModel_.block(options.visualBlock);
  if (audio.size + visual.size != jointModel_.dimension()) {
    throw Error("HMM inversion: the audio and visual blocks must cover every observation dimension");
  }
  audioBegin_ = audio.begin;
  audioSize_ = audio.size;
  visualBegin_ = visual.begin;
  visualSize_ = visual.size;
  const CovarianceType type = jointModel_.covarianceType();

  for (const auto& state : jointModel_.states) maxComponents_ = std::max(maxComponents_, state.numComponents());
  components_.resize(static_cast<size_t>(jointModel_.numStates() * maxComponents_));
  audioModel_.initial = jointModel_.initial;
  audioModel_.transition = jointModel_.transition;
  if (!jointModel_.columnNames.empty()) {
    audioModel_.columnNames.assign(jointModel_.columnNames.begin() + audioBegin_,
                                   jointModel_.columnNames.begin() + audioBegin_ + audioSize_);
  }
  Eigen::VectorXd meanSum = Eigen::VectorXd::Zero(visualSize_);
  Eigen::VectorXd squareSum = Eigen::VectorXd::Zero(visualSize_);
  double weightSum = 0.0;
  for (int j = 0; j < jointModel_.numStates(); ++j) {
    const GaussianMixture& mixture = jointModel_.states[static_cast<size_t>(j)];
    std::vector<Gaussian> audioComponents;
    for (int m = 0; m < mixture.numComponents(); ++m) {
      const Gaussian& g = mixture.components()[static_cast<size_t>(m)];
      const Eigen::MatrixXd& sigma = g.covariance();
      Component& c = components_[static_cast<size_t>(j * maxComponents_ + m)];
      c.visualMean = g.mean().segment(visualBegin_, visualSize_);
      c.audioMean = g.mean().segment(audioBegin_, audioSize_);
      const Eigen::MatrixXd sigmaAudio = subBlock(sigma, audioBegin_, audioSize_, audioBegin_, audioSize_);
      if (type == CovarianceType::kFull) {
        const Eigen::MatrixXd precision = Eigen::LLT<Eigen::MatrixXd>(sigma).solve(
            Eigen::MatrixXd::Identity(sigma.rows(), sigma.cols()));
        c.visualPrecision = subBlock(precision, visualBegin_, visualSize_, visualBegin_, visualSize_);
        c.crossPrecision = subBlock(precision, visualBegin_, visualSize_, audioBegin_, audioSize_);
        const Eigen::MatrixXd sigmaAudioVisual = subBlock(sigma, audioBegin_, audioSize_, visualBegin_, visualSize_);
        c.regression = Eigen::LLT<Eigen::MatrixXd>(sigmaAudio).solve(sigmaAudioVisual).transpose();
      } else {
        c.visualPrecision = sigma.diagonal().segment(visualBegin_, visualSize_).cwiseInverse().asDiagonal();
        c.crossPrecision = Eigen::MatrixXd::Zero(visualSize_, audioSize_);
        c.regression = Eigen::MatrixXd::Zero(visualSize_, audioSize_);
      }
      c.visualTarget = c.visualPrecision * c.visualMean + c.crossPrecision * c.audioMean;
      audioComponents.emplace_back(c.audioMean, sigmaAudio, type);

      // The model's overall visual distribution (state occupancy taken as uniform): for the random start.
      const double w = mixture.weights()[m];
      meanSum += w * c.visualMean;
      squareSum += w * (sigma.diagonal().segment(visualBegin_, visualSize_) + c.visualMean.cwiseAbs2());
      weightSum += w;
    }
    audioModel_.states.emplace_back(mixture.weights(), std::move(audioComponents));
  }
  visualMean_ = meanSum / weightSum;
  visualSpread_ = (squareSum / weightSum - visualMean_.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
  audioModel_.check();
}

Eigen::MatrixXd HmmInverter::componentPosteriors(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                                 const Eigen::VectorXd* carried, double* logLikelihood,
                                                 Eigen::VectorXd* lastFrameDistribution) const {
  std::vector<Eigen::MatrixXd> componentLog;
  const Eigen::MatrixXd logB = model.emissionLogLikelihoods(frames, &componentLog);
  const Posteriors posteriors = forwardBackward(model, logB, carried);
  if (logLikelihood) *logLikelihood = posteriors.logLikelihood;
  if (lastFrameDistribution) *lastFrameDistribution = posteriors.stateGivenAll.col(frames.cols() - 1);
  Eigen::MatrixXd gamma = Eigen::MatrixXd::Zero(model.numStates() * maxComponents_, frames.cols());
  for (int j = 0; j < model.numStates(); ++j) {
    const Eigen::MatrixXd& terms = componentLog[static_cast<size_t>(j)];
    for (Eigen::Index m = 0; m < terms.rows(); ++m) {
      gamma.row(j * maxComponents_ + m) =
          posteriors.stateGivenAll.row(j).array() * (terms.row(m) - logB.row(j)).array().exp();
    }
  }
  return gamma;
}

Eigen::MatrixXd HmmInverter::conditionalMean(const Eigen::Ref<const Eigen::MatrixXd>& audio,
                                             const Eigen::MatrixXd& posteriors) const {
  Eigen::MatrixXd visual = Eigen::MatrixXd::Zero(visualSize_, audio.cols());
  for (size_t k = 0; k < components_.size(); ++k) {
    const Component& c = components_[k];
    if (c.visualMean.size() == 0) continue;  // a state with fewer components than the maximum
    const Eigen::RowVectorXd weight = posteriors.row(static_cast<Eigen::Index>(k));
    const Eigen::MatrixXd estimate = (c.regression * (audio.colwise() - c.audioMean)).colwise() + c.visualMean;
    visual += estimate * weight.asDiagonal();
  }
  return visual;
}

Eigen::MatrixXd HmmInverter::mmse(const Eigen::Ref<const Eigen::MatrixXd>& audio) const {
  if (audio.rows() != audioSize_) throw Error("HMM inversion: audio has the wrong dimension");
  if (audio.cols() == 0) return Eigen::MatrixXd(visualSize_, 0);
  return conditionalMean(audio, componentPosteriors(audioModel_, audio, nullptr, nullptr, nullptr));
}

Eigen::MatrixXd HmmInverter::runEm(const Eigen::Ref<const Eigen::MatrixXd>& audio, Eigen::MatrixXd visual,
                                   const Eigen::VectorXd* carried, std::vector<double>& logLikelihoods,
                                   int& iterations, Eigen::VectorXd* lastFrameDistribution) const {
  const Eigen::Index numFrames = audio.cols();
  Eigen::MatrixXd joint(jointModel_.dimension(), numFrames);
  joint.middleRows(audioBegin_, audioSize_) = audio;
  double previous = -std::numeric_limits<double>::infinity();
  iterations = 0;
  Eigen::MatrixXd precisionSum(visualSize_, visualSize_);
  Eigen::VectorXd targetSum(visualSize_);
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    joint.middleRows(visualBegin_, visualSize_) = visual;
    double logLikelihood = 0.0;
    const Eigen::MatrixXd gamma = componentPosteriors(jointModel_, joint, carried, &logLikelihood, lastFrameDistribution);
    logLikelihoods.push_back(logLikelihood);
    if (logLikelihood - previous < options_.tolerance * static_cast<double>(numFrames)) break;
    previous = logLikelihood;
    ++iterations;
    // The M-step (eq. 7): a d_v x d_v solve per frame.
    for (Eigen::Index t = 0; t < numFrames; ++t) {
      precisionSum.setZero();
      targetSum.setZero();
      for (size_t k = 0; k < components_.size(); ++k) {
        const double g = gamma(static_cast<Eigen::Index>(k), t);
        if (g < 1e-12) continue;
        const Component& c = components_[k];
        precisionSum += g * c.visualPrecision;
        targetSum += g * (c.visualTarget - c.crossPrecision * audio.col(t));
      }
      visual.col(t) = precisionSum.llt().solve(targetSum);
    }
  }
  // The final estimate's own likelihood is the last entry; the carried distribution matches it.
  joint.middleRows(visualBegin_, visualSize_) = visual;
  return visual;
}

InversionResult HmmInverter::invert(const Eigen::Ref<const Eigen::MatrixXd>& audio) const {
  if (audio.rows() != audioSize_) throw Error("HMM inversion: audio has the wrong dimension");
  InversionResult result;
  const Eigen::Index numFrames = audio.cols();
  result.visual.resize(visualSize_, numFrames);
  if (numFrames == 0) return result;
  const Eigen::Index window = options_.windowFrames > 0 ? options_.windowFrames : numFrames;
  std::mt19937 random(options_.seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  Eigen::VectorXd carried;
  int totalIterations = 0;
  int windows = 0;
  for (Eigen::Index start = 0; start < numFrames; start += window) {
    const Eigen::Index length = std::min(window, numFrames - start);
    const auto block = audio.middleCols(start, length);
    Eigen::MatrixXd initial;
    if (options_.start == InversionStart::kRandom) {
      initial = Eigen::MatrixXd::NullaryExpr(visualSize_, length, [&](Eigen::Index row, Eigen::Index) {
        return visualMean_[row] + visualSpread_[row] * gaussian(random);
      });
    } else {
      initial = conditionalMean(block, componentPosteriors(audioModel_, block, start > 0 ? &carried : nullptr,
                                                           nullptr, nullptr));
    }
    int iterations = 0;
    std::vector<double> logLikelihoods;
    Eigen::VectorXd lastDistribution;
    result.visual.middleCols(start, length) =
        runEm(block, std::move(initial), start > 0 ? &carried : nullptr, logLikelihoods, iterations, &lastDistribution);
    // The next window's first frame: one step of the chain from this window's last frame.
    carried = jointModel_.transition.transpose() * lastDistribution;
    carried /= carried.sum();
    if (start == 0 || options_.windowFrames <= 0) result.logLikelihoods = logLikelihoods;
    totalIterations += iterations;
    ++windows;
  }
  result.iterations = static_cast<int>(std::lround(static_cast<double>(totalIterations) / windows));
  return result;
}

}  // namespace th::hmm
