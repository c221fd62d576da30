// Speaker-, microphone- and level-independent speech features for the mouth, computed causally so that a live
// stream and a whole file give the same frames (one frame in, one frame out, no look-ahead).
//
//   th::features::OnlineSpeechNormaliser normaliser({}, 30.0, priorMean);   // priorMean: c1..cN of training speech
//   Eigen::VectorXd out(normaliser.outputDimension());
//   normaliser.accept(levelDb, mfcc, out);   // per frame: [c1..cN − running mean, (level − peak) / unit]
//
// - Cepstral mean normalisation (CMN): a fixed spectral tilt — a microphone's response, a room, the shape of
//   one voice — adds a constant to every cepstral coefficient; removing the running mean takes it out. The mean
//   starts at the training speech's mean (the prior, weighing as priorSeconds of frames) and then follows the
//   stream with an exponential window of meanSeconds, as Kaldi's online CMN does with its global prior.
// - Level: the frame's level in dB minus a peak that follows the loudest recent frames (it rises at once and
//   falls by peakDecayDbPerSecond), in units of levelUnitDb. A gain changes the level and the peak alike, so
//   the input's level cancels: the same speech at −20 dB gives the same values (tests/features). The peak
//   starts at the first frame's level.
// MFCCs c1..cN carry no level (that is c0), so the output depends on the input's level only where the
// filterbank's floor is reached, in near-silence.
// Thread contract: one thread per instance.
#pragma once

#include <Eigen/Core>
#include <string>

#include "core/json_reading.h"

namespace th::features {

struct SpeechNormalisationOptions {
  double meanSeconds = 10.0;          // the running cepstral mean's time constant
  double priorSeconds = 3.0;          // the prior mean's weight at the start, in seconds of frames
  double peakDecayDbPerSecond = 2.0;  // how fast the level's reference peak falls
  double levelUnitDb = 10.0;          // the relative level's unit

  void check() const;  // throws th::Error naming the bad option
};

class OnlineSpeechNormaliser {
 public:
  // priorMean: the mean c1..cN of the training speech (its size sets N).
  OnlineSpeechNormaliser(const SpeechNormalisationOptions& options, double framesPerSecond,
                         const Eigen::VectorXd& priorMean);

  int numMfcc() const { return static_cast<int>(priorMean_.size()); }
  int outputDimension() const { return numMfcc() + 1; }  // c1..cN, then the level (row numMfcc())

  // One frame's level (dB re full scale) and c1..cN in; its normalised values out (outputDimension()).
  void accept(double levelDb, const Eigen::Ref<const Eigen::VectorXd>& mfcc, Eigen::Ref<Eigen::VectorXd> out);
  void reset();  // back to the state before the first frame

 private:
  SpeechNormalisationOptions options_;
  double framesPerSecond_;
  Eigen::VectorXd priorMean_;
  Eigen::VectorXd mean_;
  double count_ = 0.0;
  double peakDb_ = 0.0;
  bool started_ = false;
};

// The batch path: the same object over a whole recording. levelDb: 1 x T; mfcc: N x T. Returns (N + 1) x T.
Eigen::MatrixXd normaliseSpeech(const SpeechNormalisationOptions& options, double framesPerSecond,
                                const Eigen::VectorXd& priorMean, const Eigen::RowVectorXd& levelDb,
                                const Eigen::MatrixXd& mfcc);

// The options and the prior mean as a model file keeps them: {"mean_seconds", "prior_seconds",
// "peak_decay_db_per_second", "level_unit_db", "prior_mean": [...]}; and back, checked (errors name the file and
// the field; priorMeanSize < 0: any size).
Json speechNormalisationJson(const SpeechNormalisationOptions& options, const Eigen::VectorXd& priorMean);
SpeechNormalisationOptions readSpeechNormalisation(const Json& object, const JsonFields& fields,
                                                   const std::string& field, Eigen::VectorXd& priorMean,
                                                   Eigen::Index priorMeanSize = -1);

}  // namespace th::features
