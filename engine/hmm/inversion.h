// Recovering the visual part of a joint audio-visual HMM's observations from the audio alone.
//
//   th::hmm::HmmInverter inverter(jointModel, {});          // blocks "audio" and "visual" in the model
//   th::hmm::InversionResult r = inverter.invert(audio);    // audio: d_a x T; r.visual: d_v x T
//   Eigen::MatrixXd quick = inverter.mmse(audio);           // non-iterative E[o_v | o_a]
//
// HMM inversion (Choi et al. 2001; Terissi & Gómez 2008, eq. 7): maximise P(O_a, O_v | λ) over O_v by EM. With
// γₜ(j,m) from forward-backward on the joint observations [o_a; o'_v] and each component's precision Φ = Σ⁻¹
// split into blocks [[Φᵃ, Φᵃᵛ], [Φᵛᵃ, Φᵛ]],
//   o'_vₜ = [Σⱼₘ γₜ(j,m) Φᵛⱼₘ]⁻¹ Σⱼₘ γₜ(j,m) [Φᵛⱼₘ μᵛⱼₘ − Φᵛᵃⱼₘ (o_aₜ − μᵃⱼₘ)],
// repeated until the joint log-likelihood stops rising (it never falls: each update maximises the EM auxiliary
// function). Diagonal covariance has Φᵛᵃ = 0 (eq. 8). The start is random, as the papers do, or the
// conditional mean under the audio-only marginal model (ours; converges in fewer iterations).
// MMSE: E[o_v | o_a] = Σⱼₘ γᵃₜ(j,m) [μᵛ + Σᵛᵃ (Σᵃ)⁻¹ (o_a − μᵃ)], γᵃ from the audio-only marginal model.
// Windowed (streaming) inversion runs EM on consecutive blocks of W frames; the forward variables at the end of
// one block start the next, so only the backward pass is truncated.
// Thread contract: an HmmInverter is immutable after construction; invert()/mmse() may run on many threads.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <random>
#include <string>
#include <vector>

#include "hmm/hmm_model.h"

namespace th::hmm {

enum class InversionStart { kConditionalMean, kRandom };

struct InversionOptions {
  std::string audioBlock = "audio";
  std::string visualBlock = "visual";
  int maxIterations = 100;
  double tolerance = 1e-6;  // stop when the joint log-likelihood per frame rises by less than this
  InversionStart start = InversionStart::kConditionalMean;
  unsigned seed = 1;     // for the random start
  int windowFrames = 0;  // 0: the whole sequence at once; else EM on consecutive blocks of this many frames
};

struct InversionResult {
  Eigen::MatrixXd visual;              // d_v x T
  std::vector<double> logLikelihoods;  // joint log P(O_a, O'_v) after each iteration (batch: whole sequence)
  int iterations = 0;                  // batch: EM iterations; windowed: the mean over windows (rounded)
};

class HmmInverter {
 public:
  HmmInverter(const HmmModel& jointModel, const InversionOptions& options);

  InversionResult invert(const Eigen::Ref<const Eigen::MatrixXd>& audio) const;
  // With windowFrames > 0, window by window as invert() (forward-backward within each window, the state
  // distribution carried from one to the next); else over the whole sequence.
  Eigen::MatrixXd mmse(const Eigen::Ref<const Eigen::MatrixXd>& audio) const;

  // The visual part's distribution given the audio, frame by frame: each component's conditional Gaussian
  // N(μᵛ + Σᵛᵃ(Σᵃ)⁻¹(o_a − μᵃ), (Φᵛ)⁻¹), weighted by its posterior under the audio-only model and moment-matched
  // to one Gaussian (the mixture's mean and covariance). The means are mmse()'s; the covariances say how sure
  // each frame is, for trajectory generation. Windowed as mmse().
  struct VisualDistribution {
    Eigen::MatrixXd mean;                     // d_v x T
    std::vector<Eigen::MatrixXd> covariance;  // T of d_v x d_v
  };
  VisualDistribution conditionalDistribution(const Eigen::Ref<const Eigen::MatrixXd>& audio) const;

  // One window of the windowed forms, as invert() and mmse() run them one after another. `carried`: the state
  // distribution at the window's first frame (null: the model's start, π); `next` receives the one for the
  // next window's first frame; `random` draws the random start. `iterations` and `logLikelihoods` (if not
  // null) receive the EM count and the joint log-likelihood of each iteration.
  Eigen::MatrixXd invertWindow(const Eigen::Ref<const Eigen::MatrixXd>& audio, const Eigen::VectorXd* carried,
                               Eigen::VectorXd& next, std::mt19937& random, int* iterations = nullptr,
                               std::vector<double>* logLikelihoods = nullptr) const;
  Eigen::MatrixXd mmseWindow(const Eigen::Ref<const Eigen::MatrixXd>& audio, const Eigen::VectorXd* carried,
                             Eigen::VectorXd& next) const;

  const HmmModel& audioModel() const { return audioModel_; }
  const InversionOptions& options() const { return options_; }
  int audioDimension() const { return audioSize_; }
  int visualDimension() const { return visualSize_; }

 private:
  struct Component {
    Eigen::MatrixXd visualPrecision;        // Φᵛ (d_v x d_v)
    Eigen::MatrixXd crossPrecision;         // Φᵛᵃ (d_v x d_a)
    Eigen::VectorXd visualTarget;           // Φᵛ μᵛ + Φᵛᵃ μᵃ: the update's constant part
    Eigen::MatrixXd regression;             // Σᵛᵃ (Σᵃ)⁻¹ (d_v x d_a), for the conditional mean
    Eigen::MatrixXd conditionalCovariance;  // (Φᵛ)⁻¹ = Σᵛ − Σᵛᵃ (Σᵃ)⁻¹ Σᵃᵛ
    Eigen::VectorXd visualMean;             // μᵛ
    Eigen::VectorXd audioMean;              // μᵃ
  };

  // One EM run over one stretch of audio; `carried` is the state distribution of its first frame (or null: π).
  // Returns the visual estimate and appends the joint log-likelihood of each iteration.
  Eigen::MatrixXd runEm(const Eigen::Ref<const Eigen::MatrixXd>& audio, Eigen::MatrixXd visual,
                        const Eigen::VectorXd* carried, std::vector<double>& logLikelihoods, int& iterations,
                        Eigen::VectorXd* lastFrameDistribution) const;
  // γₜ(j,m) of every component (rows: component index j*M+m) for joint or audio-only observations.
  Eigen::MatrixXd componentPosteriors(const HmmModel& model, const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                      const Eigen::VectorXd* carried, double* logLikelihood,
                                      Eigen::VectorXd* lastFrameDistribution) const;
  Eigen::VectorXd nextWindowStart(const Eigen::VectorXd& lastFrameDistribution) const;
  Eigen::MatrixXd conditionalMean(const Eigen::Ref<const Eigen::MatrixXd>& audio,
                                  const Eigen::MatrixXd& posteriors) const;

  HmmModel jointModel_;
  HmmModel audioModel_;
  InversionOptions options_;
  int audioBegin_ = 0;
  int audioSize_ = 0;
  int visualBegin_ = 0;
  int visualSize_ = 0;
  std::vector<Component> components_;  // index j * maxComponents + m
  int maxComponents_ = 0;
  Eigen::VectorXd visualMean_;  // for the random start: the model's overall visual mean and spread
  Eigen::VectorXd visualSpread_;
};

// The windowed inversion (or MMSE estimate) as a stream, for the live pipeline: audio frames go in one at a
// time, visual frames come out a window at a time, the same values as HmmInverter::invert() or mmse() with
// that window over the whole input. A window is decoded when its last frame arrives: the look-ahead is up to
// windowFrames - 1 frames. Ready frames are kept until taken, so memory does not grow with the stream.
// Thread contract: one thread per instance; the inverter is shared read-only and must outlive it.
class StreamingInverter {
 public:
  enum class Method { kInversion, kMmse };
  StreamingInverter(const HmmInverter& inverter, Method method, int windowFrames);

  void accept(const Eigen::Ref<const Eigen::VectorXd>& audioFrame);  // d_a values
  void finish();                                                     // decodes the last, partial window
  bool next(Eigen::VectorXd& visual);                                // the next visual frame (d_v), if one is ready
  int lastIterations() const { return lastIterations_; }             // EM iterations of the last window decoded
  int windowFrames() const { return windowFrames_; }

 private:
  void decode();

  const HmmInverter& inverter_;
  Method method_;
  int windowFrames_;
  Eigen::MatrixXd window_;  // d_a x windowFrames, filled up to `filled_`
  int filled_ = 0;
  Eigen::VectorXd carried_;
  bool first_ = true;
  std::mt19937 random_;
  std::deque<Eigen::VectorXd> ready_;
  int lastIterations_ = 0;
};

}  // namespace th::hmm
