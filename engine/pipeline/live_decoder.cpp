#include "pipeline/live_decoder.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "animation/fap_mapping.h"
#include "animation/prosody.h"
#include "core/error.h"
#include "pipeline/offline.h"

namespace th::pipeline {

namespace {

features::FeatureOptions prosodyOptions(const LiveDecoderOptions& options) {
  features::FeatureOptions result = animation::prosodyFeatureOptions(animation::kAnimationFramesPerSecond);
  result.pitch.minF0Hz = options.minF0Hz;
  result.pitch.maxF0Hz = options.maxF0Hz;
  return result;
}

features::FeatureOptions mouthFeatureOptions() {
  // As the prosody extractor, minus the pitch tracker: the same MFCCs and energy, without its decision lag.
  features::FeatureOptions options = animation::prosodyFeatureOptions(animation::kAnimationFramesPerSecond);
  options.trackPitch = false;
  return options;
}

}  // namespace

LiveDecoder::LiveDecoder(const animation::HeadModel* head, const animation::MouthModel* mouth,
                         const LiveDecoderOptions& options, const animation::VisemeModel* visemes,
                         const animation::MouthNetwork* articulation)
    : mouth_(mouth),
      options_(options),
      // The features animate() gives each model: the prosody settings serve both (the energy's normalisation
      // does not touch the MFCCs).
      prosodyExtractor_(prosodyOptions(options)),
      mouthExtractor_(mouthFeatureOptions()),
      prosody_(animation::kAnimationFramesPerSecond, {}) {
  if (head == nullptr && mouth == nullptr) throw Error("live decoder: neither a head nor a mouth model");
  if (mouth != nullptr && !animation::drivesFaps(*mouth))
    throw Error(
        "live decoder: the mouth model drives no FAPs (a sweep model?); make one with `talkinghead train mouth`");
  if (head != nullptr) {
    if (options.head.maxLagFrames < 0)
      throw Error("live decoder: the head decoder needs a bounded lag (maxLagFrames >= 0), not batch decoding");
    headStream_ = std::make_unique<animation::HeadSynthesiser>(*head, options.head);
  }
  if (mouth != nullptr) {
    if (options.mouth.windowFrames < 1)
      throw Error("live decoder: the mouth needs an inversion window of at least one frame, not " +
                  std::to_string(options.mouth.windowFrames));
    mouthStream_ = std::make_unique<animation::MouthSynthesiser>(*mouth, options.mouth);
    mouthFaps_ = animation::mouthFapNumbers(*mouth);
  }
  if (articulation != nullptr) {
    options.articulation.check();
    if (options.articulationLagFrames < 0) throw Error("live decoder: the articulation's lag must be >= 0 frames");
    if (mouth != nullptr && articulation->openingGradient.size() == 0)
      throw Error("live decoder: the articulation has no opening gradient to close the lips with");
    articulation_ = articulation;
    networkExtractor_ = std::make_unique<features::OnlineFeatureExtractor>(animation::subframeFeatureOptions());
    networkStream_ = std::make_unique<animation::MouthNetworkStream>(*articulation);
    articulationClasses_ = animation::classHmm(articulation->sequence, options.articulation.minHoldFrames);
    logPriors_ = articulation->classPriors.array().max(1e-12).log().matrix();
    visemeStream_ = std::make_unique<animation::VisemeStream>(articulationClasses_, options.articulation.minHoldFrames,
                                                              options.articulationLagFrames);
  } else if (visemes != nullptr) {
    visemeStream_ = std::make_unique<animation::VisemeStream>(*visemes, options.visemeLagFrames);
  }
  headDelayFrames_ = lookahead().headDelayFrames;
  row_.resize(static_cast<std::size_t>(prosodyExtractor_.layout().size()));
  mfccRow_.resize(static_cast<std::size_t>(mouthExtractor_.layout().numMfcc));
}

LiveDecoder::~LiveDecoder() = default;

void LiveDecoder::acceptWaveform(std::span<const float> samples16k) {
  prosodyExtractor_.acceptWaveform(samples16k);
  if (readsMouthExtractor()) mouthExtractor_.acceptWaveform(samples16k);
  if (networkExtractor_) networkExtractor_->acceptWaveform(samples16k);
  pull();
}

void LiveDecoder::inputFinished() {
  prosodyExtractor_.inputFinished();
  if (readsMouthExtractor()) mouthExtractor_.inputFinished();
  if (networkExtractor_) networkExtractor_->inputFinished();
  pull();
  if (networkStream_) {
    networkStream_->finish();
    pull();
  }
  if (headStream_) headStream_->finish();
  if (mouthStream_) mouthStream_->finish();
  if (visemeStream_) visemeStream_->finish();
  pull();
  finished_ = true;
}

void LiveDecoder::pull() {
  using features::FeatureLayout;
  for (; prosodyRows_ < prosodyExtractor_.numFramesReady(); ++prosodyRows_) {
    prosodyExtractor_.getFrame(prosodyRows_, row_);
    prosodyFrames_.push_back({.f0Hz = row_[FeatureLayout::kF0Hz],
                              .energy = row_[FeatureLayout::kEnergy],
                              .levelDb = prosodyExtractor_.getLevelDb(prosodyRows_)});
    if (headStream_) {
      headStream_->acceptProsody(prosody_.accept(row_), animation::isVoiced(row_));
      const Eigen::VectorXd& posterior = headStream_->filteredPosterior();
      for (Eigen::Index k = 0; k < std::min<Eigen::Index>(posterior.size(), AnimationFrame::kMaxHeadStates); ++k)
        prosodyFrames_.back().posterior[static_cast<std::size_t>(k)] = static_cast<float>(posterior[k]);
    }
  }
  if (headStream_)
    for (; headTaken_ < headStream_->numReady(); ++headTaken_)
      prosodyFrames_[static_cast<std::size_t>(headTaken_ - prosodyBase_)].headDegrees =
          headStream_->rotation(headTaken_);
  if (networkStream_) {
    std::vector<float> row(animation::kNetworkMfcc);
    Eigen::VectorXd mfcc(animation::kNetworkMfcc);
    for (; subframesTaken_ < networkExtractor_->numBaseFramesReady(); ++subframesTaken_) {
      networkExtractor_->getMfcc(subframesTaken_, row);
      for (Eigen::Index k = 0; k < mfcc.size(); ++k) mfcc[k] = row[static_cast<std::size_t>(k)];
      networkStream_->accept(networkExtractor_->getLevelDb(subframesTaken_), mfcc);
    }
    networkExtractor_->forgetBefore(subframesTaken_);
    animation::MouthNetworkFrame heard;
    while (networkStream_->next(heard))
      visemeStream_->acceptEvidence(options_.articulation.evidenceScale *
                                    (heard.classes.array().max(1e-12).log().matrix() - logPriors_));
  }
  if (readsMouthExtractor()) {
    Eigen::VectorXd mfcc(static_cast<Eigen::Index>(mfccRow_.size()));
    for (; mfccFrames_ < mouthExtractor_.numBaseFramesReady(); ++mfccFrames_) {
      mouthExtractor_.getMfcc(mfccFrames_, mfccRow_);
      for (Eigen::Index k = 0; k < mfcc.size(); ++k) mfcc[k] = mfccRow_[static_cast<std::size_t>(k)];
      const double levelDb = mouthExtractor_.getLevelDb(mfccFrames_);
      if (mouthStream_) mouthStream_->acceptFrame(levelDb, mfcc);
      if (visemeStream_ && !networkStream_) visemeStream_->accept(levelDb, mfcc);
    }
  }
  if (visemeStream_) {
    VisemeDecision decision;
    while (visemeStream_->next(decision.frame)) {
      decision.index = visemesDecided_++;
      visemeFrames_.push_back(decision);
    }
    // Without a mouth, nothing else reads the MFCC extractor's frames again.
    if (!mouthStream_) mouthExtractor_.forgetBefore(mfccFrames_);
  }
  if (mouthStream_) {
    Eigen::VectorXd components;
    while (mouthStream_->next(components)) {
      const auto frame = static_cast<int>(static_cast<int>(mouthFrames_.size()) + nextIndex_);
      mouthFrames_.push_back({.energy = mouthExtractor_.getEnergy(frame),
                              .levelDb = mouthExtractor_.getLevelDb(frame),
                              .posterior = {},
                              .faps = animation::mouthFapsOf(*mouth_, components).col(0)});
      const Eigen::VectorXd& posterior = mouthStream_->posterior();
      for (Eigen::Index k = 0; k < std::min<Eigen::Index>(posterior.size(), AnimationFrame::kMaxMouthStates); ++k)
        mouthFrames_.back().posterior[static_cast<std::size_t>(k)] = static_cast<float>(posterior[k]);
    }
    // The energies of frames the mouth has not given yet are still to be read; nothing older is.
    mouthExtractor_.forgetBefore(nextIndex_ + static_cast<int>(mouthFrames_.size()));
  }
  // What has been taken is not read again: memory stays bounded however long the stream.
  prosodyExtractor_.forgetBefore(prosodyRows_);
  if (headStream_) headStream_->forgetBefore(headTaken_);
}

std::size_t LiveDecoder::framesHeld() const {
  const std::size_t subframes = networkStream_ ? networkExtractor_->framesHeld() + networkStream_->subframesHeld() : 0;
  return prosodyExtractor_.framesHeld() + mouthExtractor_.framesHeld() + (headStream_ ? headStream_->framesHeld() : 0) +
         prosodyFrames_.size() + mouthFrames_.size() + visemeFrames_.size() + subframes / animation::kSubframesPerFrame;
}

bool LiveDecoder::next(AnimationFrame& frame) {
  const int shown = nextIndex_ - headDelayFrames_;  // the prosody frame this frame shows
  const int decided = headStream_ ? headTaken_ : prosodyRows_;
  if (mouthStream_) {
    if (mouthFrames_.empty()) return false;
    if (shown >= decided && !finished_) return false;  // its head is not decided yet
    // With the articulation, its lips wait for its class.
    if (networkStream_ && !finished_ && (visemeFrames_.empty() || visemeFrames_.back().index < nextIndex_))
      return false;
  } else if (shown >= decided) {
    return false;  // the head alone sets the pace
  }
  frame = AnimationFrame{};
  frame.index = nextIndex_;
  frame.timeSeconds = nextIndex_ / animation::kAnimationFramesPerSecond;
  frame.prosodyIndex = shown;
  frame.headStates = headStream_ ? std::min(headStream_->numStates(), AnimationFrame::kMaxHeadStates) : 0;
  if (shown >= 0 && shown < decided) {
    const ProsodyFrame& prosody = prosodyFrames_[static_cast<std::size_t>(shown - prosodyBase_)];
    frame.f0Hz = prosody.f0Hz;
    frame.energy = prosody.energy;
    frame.levelDb = prosody.levelDb;
    frame.headPosterior = prosody.posterior;
    frame.headDegrees = prosody.headDegrees;
  }
  if (headStream_) {
    const Eigen::MatrixXd faps = animation::headFaps(frame.headDegrees);
    for (std::size_t i = 0; i < animation::kHeadFaps.size(); ++i)
      frame.faps[static_cast<std::size_t>(animation::kHeadFaps[i])] = faps(static_cast<Eigen::Index>(i), 0);
  }
  if (visemeStream_) {
    while (!visemeFrames_.empty() && visemeFrames_.front().index <= frame.index) {
      shownVisemes_ = std::move(visemeFrames_.front());
      visemeFrames_.pop_front();
    }
    if (shownVisemes_.index >= 0) {
      frame.visemeIndex = shownVisemes_.index;
      frame.mouthClass = shownVisemes_.frame.mouthClass;
      for (int c = 0; c < face::kNumMouthClasses; ++c)
        frame.visemeProbabilities[static_cast<std::size_t>(c)] =
            static_cast<float>(shownVisemes_.frame.probabilities[c]);
    }
  }
  if (mouthStream_) {
    MouthFrame mouth = std::move(mouthFrames_.front());
    mouthFrames_.pop_front();
    if (networkStream_ && shownVisemes_.index == frame.index) {
      Eigen::MatrixXd faps = mouth.faps;
      animation::articulateLips(*articulation_, {frame.mouthClass}, mouthFaps_, faps, options_.articulation);
      mouth.faps = faps.col(0);
    }
    frame.energy = mouth.energy;
    frame.levelDb = mouth.levelDb;
    frame.mouthPosterior = mouth.posterior;
    frame.mouthStates = std::min(mouthStream_->numStates(), AnimationFrame::kMaxMouthStates);
    for (std::size_t i = 0; i < mouthFaps_.size(); ++i)
      frame.faps[static_cast<std::size_t>(mouthFaps_[i])] = mouth.faps[static_cast<Eigen::Index>(i)];
  }
  ++nextIndex_;
  // Prosody frames before the next frame's are not needed again.
  while (prosodyBase_ < std::min(nextIndex_ - headDelayFrames_, decided)) {
    prosodyFrames_.pop_front();
    ++prosodyBase_;
  }
  return true;
}

std::vector<int> LiveDecoder::fapNumbers() const {
  std::vector<int> numbers = mouthFaps_;
  if (headStream_) numbers.insert(numbers.end(), animation::kHeadFaps.begin(), animation::kHeadFaps.end());
  std::sort(numbers.begin(), numbers.end());
  return numbers;
}

DecoderLookahead LiveDecoder::lookahead() const {
  constexpr double kFrameMs = 1000.0 / animation::kAnimationFramesPerSecond;
  DecoderLookahead result;
  result.featuresMs = prosodyExtractor_.lookahead().totalMs;
  result.mouthFeaturesMs = mouthExtractor_.lookahead().mfccMs;  // its base frames: no deltas to wait for
  result.headFrames = headStream_ ? headStream_->lookaheadFrames() : 0;
  result.mouthFrames = mouthStream_ ? mouthStream_->lookaheadFrames() : 0;
  result.headMs = result.featuresMs + result.headFrames * kFrameMs;
  result.mouthMs = mouthStream_ ? result.mouthFeaturesMs + result.mouthFrames * kFrameMs : 0.0;
  if (networkStream_) {
    result.articulationMs = networkExtractor_->lookahead().mfccMs +
                            1000.0 * articulation_->futureSubframes / animation::kSubframesPerSecond +
                            options_.articulationLagFrames * kFrameMs;
    if (mouthStream_) result.mouthMs = std::max(result.mouthMs, result.articulationMs);
  }
  if (mouthStream_ && !options_.waitForHead) {
    result.headDelayFrames =
        std::max(0, static_cast<int>(std::ceil((result.headMs - result.mouthMs) / kFrameMs - 1e-9)));
    result.totalMs = std::max(result.mouthMs, result.headMs - result.headDelayFrames * kFrameMs);
  } else {
    result.totalMs = std::max(result.headMs, result.mouthMs);
  }
  return result;
}

ResamplingDecoder::ResamplingDecoder(std::unique_ptr<FrameDecoder> inner, double inputRateHz)
    : inner_(std::move(inner)),
      resampler_(std::make_unique<audio::Resampler>(inputRateHz, features::OnlineFeatureExtractor::kSampleRateHz)) {
  if (!inner_) throw Error("resampling decoder: no decoder");
}

ResamplingDecoder::~ResamplingDecoder() = default;

void ResamplingDecoder::acceptWaveform(std::span<const float> samples) {
  converted_.clear();
  resampler_->process(samples, converted_);
  inner_->acceptWaveform(converted_);
}

void ResamplingDecoder::inputFinished() {
  converted_.clear();
  resampler_->finish(converted_);
  inner_->acceptWaveform(converted_);
  inner_->inputFinished();
}

}  // namespace th::pipeline
