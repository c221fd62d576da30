#include "hmm/inversion.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

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
        const Eigen::MatrixXd precision =
            Eigen::LLT<Eigen::MatrixXd>(sigma).solve(Eigen::MatrixXd::Identity(sigma.rows(), sigma.cols()));
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
      c.conditionalCovariance = c.visualPrecision.llt().solve(Eigen::MatrixXd::Identity(visualSize_, visualSize_));
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
  const Eigen::Index numFrames = audio.cols();
  Eigen::MatrixXd visual(visualSize_, numFrames);
  const Eigen::Index window = options_.windowFrames > 0 ? options_.windowFrames : std::max<Eigen::Index>(numFrames, 1);
  Eigen::VectorXd carried;
  Eigen::VectorXd next;
  for (Eigen::Index start = 0; start < numFrames; start += window) {
    const Eigen::Index length = std::min(window, numFrames - start);
    visual.middleCols(start, length) =
        mmseWindow(audio.middleCols(start, length), start > 0 ? &carried : nullptr, next);
    carried = next;
  }
  return visual;
}

Eigen::MatrixXd HmmInverter::mmseWindow(const Eigen::Ref<const Eigen::MatrixXd>& audio, const Eigen::VectorXd* carried,
                                        Eigen::VectorXd& next) const {
  if (audio.rows() != audioSize_) throw Error("HMM inversion: audio has the wrong dimension");
  if (audio.cols() == 0) throw Error("HMM inversion: an empty window");
  Eigen::VectorXd last;
  Eigen::MatrixXd visual = conditionalMean(audio, componentPosteriors(audioModel_, audio, carried, nullptr, &last));
  next = nextWindowStart(last);
  return visual;
}

HmmInverter::VisualDistribution HmmInverter::conditionalDistribution(
    const Eigen::Ref<const Eigen::MatrixXd>& audio) const {
  if (audio.rows() != audioSize_) throw Error("HMM inversion: audio has the wrong dimension");
  const Eigen::Index numFrames = audio.cols();
  VisualDistribution result{Eigen::MatrixXd::Zero(visualSize_, numFrames), {}};
  result.covariance.assign(static_cast<std::size_t>(numFrames), Eigen::MatrixXd::Zero(visualSize_, visualSize_));
  const Eigen::Index window = options_.windowFrames > 0 ? options_.windowFrames : std::max<Eigen::Index>(numFrames, 1);
  Eigen::VectorXd carried;
  Eigen::VectorXd next;
  for (Eigen::Index start = 0; start < numFrames; start += window) {
    const Eigen::Index length = std::min(window, numFrames - start);
    const auto part = audio.middleCols(start, length);
    Eigen::VectorXd last;
    const Eigen::MatrixXd gamma =
        componentPosteriors(audioModel_, part, start > 0 ? &carried : nullptr, nullptr, &last);
    carried = nextWindowStart(last);
    // E[v] = Σ γ m;  Cov[v] = Σ γ (S + m mᵀ) − E[v] E[v]ᵀ.
    for (size_t k = 0; k < components_.size(); ++k) {
      const Component& c = components_[k];
      if (c.visualMean.size() == 0) continue;  // a state with fewer components than the maximum
      const Eigen::MatrixXd means = (c.regression * (part.colwise() - c.audioMean)).colwise() + c.visualMean;
      for (Eigen::Index t = 0; t < length; ++t) {
        const double g = gamma(static_cast<Eigen::Index>(k), t);
        if (g < 1e-12) continue;
        result.mean.col(start + t) += g * means.col(t);
        result.covariance[static_cast<std::size_t>(start + t)] +=
            g * (c.conditionalCovariance + means.col(t) * means.col(t).transpose());
      }
    }
    for (Eigen::Index t = start; t < start + length; ++t)
      result.covariance[static_cast<std::size_t>(t)] -= result.mean.col(t) * result.mean.col(t).transpose();
  }
  return result;
}

Eigen::VectorXd HmmInverter::nextWindowStart(const Eigen::VectorXd& lastFrameDistribution) const {
  // One step of the chain from the window's last frame.
  Eigen::VectorXd next = jointModel_.transition.transpose() * lastFrameDistribution;
  return next / next.sum();
}

Eigen::MatrixXd HmmInverter::invertWindow(const Eigen::Ref<const Eigen::MatrixXd>& audio,
                                          const Eigen::VectorXd* carried, Eigen::VectorXd& next, std::mt19937& random,
                                          int* iterations, std::vector<double>* logLikelihoods) const {
  if (audio.rows() != audioSize_) throw Error("HMM inversion: audio has the wrong dimension");
  if (audio.cols() == 0) throw Error("HMM inversion: an empty window");
  Eigen::MatrixXd initial;
  if (options_.start == InversionStart::kRandom) {
    std::normal_distribution<double> gaussian(0.0, 1.0);
    initial = Eigen::MatrixXd::NullaryExpr(visualSize_, audio.cols(), [&](Eigen::Index row, Eigen::Index) {
      return visualMean_[row] + visualSpread_[row] * gaussian(random);
    });
  } else {
    initial = conditionalMean(audio, componentPosteriors(audioModel_, audio, carried, nullptr, nullptr));
  }
  int count = 0;
  std::vector<double> values;
  Eigen::VectorXd last;
  Eigen::MatrixXd visual = runEm(audio, std::move(initial), carried, values, count, &last);
  next = nextWindowStart(last);
  if (iterations) *iterations = count;
  if (logLikelihoods) *logLikelihoods = std::move(values);
  return visual;
}

Eigen::MatrixXd HmmInverter::runEm(const Eigen::Ref<const Eigen::MatrixXd>& audio, Eigen::MatrixXd visual,
                                   const Eigen::VectorXd* carried, std::vector<double>& logLikelihoods, int& iterations,
                                   Eigen::VectorXd* lastFrameDistribution) const {
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
    const Eigen::MatrixXd gamma =
        componentPosteriors(jointModel_, joint, carried, &logLikelihood, lastFrameDistribution);
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
  Eigen::VectorXd carried;
  Eigen::VectorXd next;
  int totalIterations = 0;
  int windows = 0;
  for (Eigen::Index start = 0; start < numFrames; start += window) {
    const Eigen::Index length = std::min(window, numFrames - start);
    int iterations = 0;
    std::vector<double> logLikelihoods;
    result.visual.middleCols(start, length) = invertWindow(
        audio.middleCols(start, length), start > 0 ? &carried : nullptr, next, random, &iterations, &logLikelihoods);
    carried = next;
    if (start == 0 || options_.windowFrames <= 0) result.logLikelihoods = logLikelihoods;
    totalIterations += iterations;
    ++windows;
  }
  result.iterations = static_cast<int>(std::lround(static_cast<double>(totalIterations) / windows));
  return result;
}

StreamingInverter::StreamingInverter(const HmmInverter& inverter, Method method, int windowFrames)
    : inverter_(inverter), method_(method), windowFrames_(windowFrames), random_(inverter.options().seed) {
  if (windowFrames < 1)
    throw Error("streaming inversion: the window must be at least one frame, not " + std::to_string(windowFrames));
  window_.resize(inverter.audioDimension(), windowFrames);
}

void StreamingInverter::accept(const Eigen::Ref<const Eigen::VectorXd>& audioFrame) {
  if (audioFrame.size() != inverter_.audioDimension())
    throw Error("streaming inversion: an audio frame of " + std::to_string(audioFrame.size()) + " values, not " +
                std::to_string(inverter_.audioDimension()));
  window_.col(filled_++) = audioFrame;
  if (filled_ == windowFrames_) decode();
}

void StreamingInverter::finish() {
  if (filled_ > 0) decode();
}

bool StreamingInverter::next(Eigen::VectorXd& visual) {
  if (ready_.empty()) return false;
  visual = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

void StreamingInverter::decode() {
  const auto audio = window_.leftCols(filled_);
  Eigen::VectorXd next;
  const Eigen::VectorXd* carried = first_ ? nullptr : &carried_;
  const Eigen::MatrixXd visual = method_ == Method::kMmse
                                     ? inverter_.mmseWindow(audio, carried, next)
                                     : inverter_.invertWindow(audio, carried, next, random_, &lastIterations_);
  carried_ = std::move(next);
  first_ = false;
  filled_ = 0;
  for (Eigen::Index t = 0; t < visual.cols(); ++t) ready_.push_back(visual.col(t));
}

}  // namespace th::hmm
