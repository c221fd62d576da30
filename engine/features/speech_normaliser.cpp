#include "features/speech_normaliser.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace th::features {

void SpeechNormalisationOptions::check() const {
  if (!(meanSeconds > 0.0 && std::isfinite(meanSeconds)))
    throw Error("speech normalisation: the running mean's time constant must be positive");
  if (!(priorSeconds >= 0.0 && std::isfinite(priorSeconds)))
    throw Error("speech normalisation: the prior's weight must be zero or more seconds");
  if (!(peakDecayDbPerSecond > 0.0 && std::isfinite(peakDecayDbPerSecond)))
    throw Error("speech normalisation: the peak's decay must be positive");
  if (!(levelUnitDb > 0.0 && std::isfinite(levelUnitDb)))
    throw Error("speech normalisation: the level's unit must be positive");
}

OnlineSpeechNormaliser::OnlineSpeechNormaliser(const SpeechNormalisationOptions& options, double framesPerSecond,
                                               const Eigen::VectorXd& priorMean)
    : options_(options), framesPerSecond_(framesPerSecond), priorMean_(priorMean) {
  options.check();
  if (!(framesPerSecond > 0.0)) throw Error("speech normalisation: the frame rate must be positive");
  if (priorMean.size() == 0 || !priorMean.allFinite())
    throw Error("speech normalisation: the prior mean must hold finite values, one per MFCC");
  reset();
}

void OnlineSpeechNormaliser::reset() {
  mean_ = priorMean_;
  count_ = options_.priorSeconds * framesPerSecond_;
  peakDb_ = 0.0;
  started_ = false;
}

void OnlineSpeechNormaliser::accept(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc,
                                    Eigen::Ref<Eigen::VectorXd> out) {
  // An exponential window whose weight starts as a running average over the prior's frames and the stream's:
  // early frames move the mean as much as an average would, later ones as the window allows.
  count_ += 1.0;
  const double alpha = std::max(1.0 / count_, 1.0 / (options_.meanSeconds * framesPerSecond_));
  mean_ += alpha * (mfcc - mean_);
  out.head(mean_.size()) = mfcc - mean_;

  const double decay = options_.peakDecayDbPerSecond / framesPerSecond_;
  peakDb_ = started_ ? std::max(levelDb, peakDb_ - decay) : levelDb;
  started_ = true;
  out[mean_.size()] = (levelDb - peakDb_) / options_.levelUnitDb;
}

Eigen::MatrixXd normaliseSpeech(const SpeechNormalisationOptions& options, double framesPerSecond,
                                const Eigen::VectorXd& priorMean, const Eigen::RowVectorXd& levelDb,
                                const Eigen::MatrixXd& mfcc) {
  if (levelDb.size() != mfcc.cols())
    throw Error("speech normalisation: " + std::to_string(levelDb.size()) + " levels for " +
                std::to_string(mfcc.cols()) + " MFCC frames");
  if (mfcc.rows() != priorMean.size())
    throw Error("speech normalisation: " + std::to_string(mfcc.rows()) + " MFCCs a frame, the prior has " +
                std::to_string(priorMean.size()));
  OnlineSpeechNormaliser normaliser(options, framesPerSecond, priorMean);
  Eigen::MatrixXd out(normaliser.outputDimension(), mfcc.cols());
  for (Eigen::Index t = 0; t < mfcc.cols(); ++t) normaliser.accept(levelDb[t], mfcc.col(t), out.col(t));
  return out;
}

Json speechNormalisationJson(const SpeechNormalisationOptions& options, const Eigen::VectorXd& priorMean) {
  return {{"mean_seconds", options.meanSeconds},
          {"prior_seconds", options.priorSeconds},
          {"peak_decay_db_per_second", options.peakDecayDbPerSecond},
          {"level_unit_db", options.levelUnitDb},
          {"prior_mean", std::vector<double>(priorMean.data(), priorMean.data() + priorMean.size())}};
}

SpeechNormalisationOptions readSpeechNormalisation(const Json& object, const JsonFields& fields,
                                                   const std::string& field, Eigen::VectorXd& priorMean,
                                                   Eigen::Index priorMeanSize) {
  fields.object(object, field);
  const auto number = [&](const char* key) {
    return fields.number(fields.member(object, key, field), JsonFields::dotted(field, key));
  };
  const SpeechNormalisationOptions options{.meanSeconds = number("mean_seconds"),
                                           .priorSeconds = number("prior_seconds"),
                                           .peakDecayDbPerSecond = number("peak_decay_db_per_second"),
                                           .levelUnitDb = number("level_unit_db")};
  try {
    options.check();
  } catch (const Error& error) {
    fields.fail(field, error.what());
  }
  const std::string meanField = JsonFields::dotted(field, "prior_mean");
  const Json& list = fields.array(fields.member(object, "prior_mean", field), meanField);
  if (list.empty() || (priorMeanSize >= 0 && static_cast<Eigen::Index>(list.size()) != priorMeanSize))
    fields.fail(meanField,
                priorMeanSize >= 0 ? "must hold " + std::to_string(priorMeanSize) + " numbers" : "must not be empty");
  priorMean.resize(static_cast<Eigen::Index>(list.size()));
  for (std::size_t i = 0; i < list.size(); ++i)
    priorMean[static_cast<Eigen::Index>(i)] = fields.number(list[i], JsonFields::indexed(meanField, i));
  return options;
}

}  // namespace th::features
