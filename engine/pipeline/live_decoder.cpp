#include "pipeline/live_decoder.h"

#include <algorithm>
#include <string>
#include <utility>

#include "animation/animate.h"
#include "animation/fap_mapping.h"
#include "animation/prosody.h"
#include "core/error.h"

namespace th::pipeline {

LiveDecoder::LiveDecoder(const animation::HeadModel* head, const animation::MouthModel* mouth,
                         const LiveDecoderOptions& options)
    : head_(head),
      mouth_(mouth),
      options_(options),
      // The features animate() gives each model: the same extractor settings serve both (the energy's
      // normalisation does not touch the MFCCs).
      extractor_(animation::prosodyFeatureOptions(animation::kAnimationFramesPerSecond)),
      prosody_(animation::kAnimationFramesPerSecond, {}) {
  if (head == nullptr && mouth == nullptr) throw Error("live decoder: neither a head nor a mouth model");
  if (mouth != nullptr && !mouth->fapMap)
    throw Error("live decoder: the mouth model has no FAP map (a sweep model?); make one with `talkinghead train mouth`");
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
    mouthFaps_ = animation::mouthFapNumbers(*mouth->fapMap);
  }
  row_.resize(static_cast<std::size_t>(extractor_.layout().size()));
}

LiveDecoder::~LiveDecoder() = default;

void LiveDecoder::acceptWaveform(std::span<const float> samples16k) {
  extractor_.acceptWaveform(samples16k);
  pull();
}

void LiveDecoder::inputFinished() {
  extractor_.inputFinished();
  pull();
  if (headStream_) headStream_->finish();
  if (mouthStream_) mouthStream_->finish();
  pull();
}

void LiveDecoder::pull() {
  using features::FeatureLayout;
  const int numMfcc = extractor_.layout().numMfcc;
  Eigen::VectorXd mfcc(numMfcc);
  for (; featureFrames_ < extractor_.numFramesReady(); ++featureFrames_) {
    extractor_.getFrame(featureFrames_, row_);
    AnimationFrame frame;
    frame.index = featureFrames_;
    frame.timeSeconds = extractor_.frameTimeSeconds(featureFrames_);
    frame.f0Hz = row_[FeatureLayout::kF0Hz];
    frame.energy = row_[FeatureLayout::kEnergy];
    pending_.push_back(frame);
    if (headStream_) headStream_->acceptProsody(prosody_.accept(row_));
    if (mouthStream_) {
      for (int k = 0; k < numMfcc; ++k) mfcc[k] = row_[static_cast<std::size_t>(FeatureLayout::kMfccBegin + k)];
      mouthStream_->acceptMfcc(mfcc);
    }
  }
  if (headStream_)
    while (headTaken_ < headStream_->numReady()) rotations_.push_back(headStream_->rotation(headTaken_++));
  if (mouthStream_) {
    Eigen::VectorXd components;
    while (mouthStream_->next(components)) jaws_.push_back(animation::jawOpeningOf(*mouth_, components)[0]);
  }
}

bool LiveDecoder::next(AnimationFrame& frame) {
  if (pending_.empty() || (headStream_ && rotations_.empty()) || (mouthStream_ && jaws_.empty())) return false;
  frame = pending_.front();
  pending_.pop_front();
  if (headStream_) {
    frame.headDegrees = rotations_.front();
    rotations_.pop_front();
    const Eigen::MatrixXd faps = animation::headFaps(frame.headDegrees);
    for (std::size_t i = 0; i < animation::kHeadFaps.size(); ++i)
      frame.faps[static_cast<std::size_t>(animation::kHeadFaps[i])] = faps(static_cast<Eigen::Index>(i), 0);
  }
  if (mouthStream_) {
    frame.jawDegrees = jaws_.front();
    jaws_.pop_front();
    const Eigen::MatrixXd faps = animation::mouthFaps(*mouth_->fapMap, Eigen::RowVectorXd::Constant(1, frame.jawDegrees));
    for (std::size_t i = 0; i < mouthFaps_.size(); ++i)
      frame.faps[static_cast<std::size_t>(mouthFaps_[i])] = faps(static_cast<Eigen::Index>(i), 0);
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
  DecoderLookahead result;
  result.featuresMs = extractor_.lookahead().totalMs;
  result.headFrames = headStream_ ? headStream_->lookaheadFrames() : 0;
  result.mouthFrames = mouthStream_ ? mouthStream_->lookaheadFrames() : 0;
  result.totalMs = result.featuresMs +
                   1000.0 * std::max(result.headFrames, result.mouthFrames) / animation::kAnimationFramesPerSecond;
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
