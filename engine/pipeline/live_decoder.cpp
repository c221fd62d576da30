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
    headStage_ = std::make_unique<animation::HeadStage>(*head, options.head);
  }
  if (mouth != nullptr) {
    if (options.mouth.windowFrames < 1)
      throw Error("live decoder: the mouth needs an inversion window of at least one frame, not " +
                  std::to_string(options.mouth.windowFrames));
    mouthStage_ = std::make_unique<animation::MouthStage>(*mouth, options.mouth);
    mouthFaps_ = animation::mouthFapNumbers(*mouth);
  }
  if (articulation != nullptr) {
    options.articulation.check();
    if (options.articulationLagFrames < 0) throw Error("live decoder: the articulation's lag must be >= 0 frames");
    if (mouth != nullptr && articulation->openingGradient.size() == 0)
      throw Error("live decoder: the articulation has no opening gradient to close the lips with");
    articulation_ = articulation;
    networkExtractor_ = std::make_unique<features::OnlineFeatureExtractor>(animation::subframeFeatureOptions());
    networkStage_ = std::make_unique<animation::MouthNetworkStage>(*articulation);
    networkVisemes_ = std::make_unique<animation::ArticulationVisemeStage>(*articulation, options.articulation,
                                                                           options.articulationLagFrames);
    visemes_ = networkVisemes_.get();
  } else if (visemes != nullptr) {
    speechVisemes_ = std::make_unique<animation::VisemeStage>(*visemes, options.visemeLagFrames);
    visemes_ = speechVisemes_.get();
  }
  headDelayFrames_ = lookahead().headDelayFrames;
  row_.resize(static_cast<std::size_t>(prosodyExtractor_.layout().size()));
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
  // Each stage's last frames, in the order they feed one another.
  if (networkStage_) {
    networkStage_->inputFinished();
    pull();
  }
  if (headStage_) headStage_->inputFinished();
  if (mouthStage_) mouthStage_->inputFinished();
  if (speechVisemes_) speechVisemes_->inputFinished();
  if (networkVisemes_) networkVisemes_->inputFinished();
  pull();
  finished_ = true;
}

namespace {

void readSpeechFrame(const features::OnlineFeatureExtractor& extractor, int frame, std::vector<float>& mfcc,
                     animation::SpeechFrame& out) {
  mfcc.resize(static_cast<std::size_t>(extractor.layout().numMfcc));
  extractor.getMfcc(frame, mfcc);
  out.mfcc.resize(static_cast<Eigen::Index>(mfcc.size()));
  for (Eigen::Index k = 0; k < out.mfcc.size(); ++k) out.mfcc[k] = mfcc[static_cast<std::size_t>(k)];
  out.levelDb = extractor.getLevelDb(frame);
}

}  // namespace

// Each stage is fed the frames of its source it has not had yet; next() reads what the stages have decided.
void LiveDecoder::pull() {
  for (; prosodyRows_ < prosodyExtractor_.numFramesReady(); ++prosodyRows_) {
    if (!headStage_) continue;  // the rows are read when shown
    prosodyExtractor_.getFrame(prosodyRows_, row_);
    headStage_->accept({.prosody = prosody_.accept(row_), .voiced = animation::isVoiced(row_)});
  }
  if (networkStage_) {
    for (; subframes_ < networkExtractor_->numBaseFramesReady(); ++subframes_) {
      readSpeechFrame(*networkExtractor_, subframes_, mfcc_, speech_);
      networkStage_->accept(speech_);
    }
    networkExtractor_->forgetBefore(subframes_);
    for (; networkFrames_ < networkStage_->numFramesReady(); ++networkFrames_) {
      networkStage_->getFrame(networkFrames_, heard_);
      networkVisemes_->accept(heard_);
    }
    networkStage_->forgetBefore(networkFrames_);
  }
  if (readsMouthExtractor()) {
    for (; mfccFrames_ < mouthExtractor_.numBaseFramesReady(); ++mfccFrames_) {
      readSpeechFrame(mouthExtractor_, mfccFrames_, mfcc_, speech_);
      if (mouthStage_) mouthStage_->accept(speech_);
      if (speechVisemes_) speechVisemes_->accept(speech_);
    }
    // With a mouth, next() reads each frame's energy from here; without, nothing reads these frames again.
    if (!mouthStage_) mouthExtractor_.forgetBefore(mfccFrames_);
  }
}

std::size_t LiveDecoder::framesHeld() const {
  std::size_t held = prosodyExtractor_.framesHeld() + mouthExtractor_.framesHeld();
  if (networkExtractor_) held += networkExtractor_->framesHeld() / animation::kSubframesPerFrame;
  if (headStage_) held += headStage_->framesHeld();
  if (mouthStage_) held += mouthStage_->framesHeld();
  if (networkStage_) held += networkStage_->framesHeld();
  if (visemes_) held += visemes_->framesHeld();
  return held;
}

bool LiveDecoder::next(AnimationFrame& frame) {
  const int shown = nextIndex_ - headDelayFrames_;  // the prosody frame this frame shows
  const int decided = headStage_ ? headStage_->numFramesReady() : prosodyRows_;
  if (mouthStage_) {
    if (mouthStage_->numFramesReady() <= nextIndex_) return false;
    if (shown >= decided && !finished_) return false;  // its head is not decided yet
    // With the articulation, its lips wait for its class.
    if (networkStage_ && !finished_ && visemes_->numFramesReady() <= nextIndex_) return false;
  } else if (shown >= decided) {
    return false;  // the head alone sets the pace
  }
  frame = AnimationFrame{};
  frame.index = nextIndex_;
  frame.timeSeconds = nextIndex_ / animation::kAnimationFramesPerSecond;
  frame.prosodyIndex = shown;
  frame.headStates = headStage_ ? std::min(headStage_->numStates(), AnimationFrame::kMaxHeadStates) : 0;
  // Until its head is decided (the first frames, when the head is shown late), a frame's head is at rest.
  Eigen::Vector3d headDegrees = options_.head.restPose;  // pitch, yaw, roll relative to the mean pose
  if (shown >= 0 && shown < decided) {
    prosodyExtractor_.getFrame(shown, row_);
    frame.f0Hz = row_[features::FeatureLayout::kF0Hz];
    frame.energy = row_[features::FeatureLayout::kEnergy];
    frame.levelDb = prosodyExtractor_.getLevelDb(shown);
    if (headStage_) {
      headStage_->getFrame(shown, head_);
      headDegrees = head_.rotationDegrees;
      const Eigen::VectorXd& posterior = head_.filteredPosterior;
      for (Eigen::Index k = 0; k < std::min<Eigen::Index>(posterior.size(), AnimationFrame::kMaxHeadStates); ++k)
        frame.headPosterior[static_cast<std::size_t>(k)] = static_cast<float>(posterior[k]);
    }
  }
  if (headStage_) {
    const Eigen::MatrixXd faps = animation::headFaps(headDegrees);
    for (std::size_t i = 0; i < animation::kHeadFaps.size(); ++i)
      frame.faps[static_cast<std::size_t>(animation::kHeadFaps[i])] = faps(static_cast<Eigen::Index>(i), 0);
  }
  // The newest visemes decided by this frame's time (a frame or two behind it, unless it waited for them).
  int visemesShown = -1;
  if (visemes_) {
    visemesShown = std::min(visemes_->numFramesReady() - 1, frame.index);
    if (visemesShown >= 0) {
      visemes_->getFrame(visemesShown, visemeFrame_);
      frame.visemeIndex = visemesShown;
      frame.mouthClass = visemeFrame_.mouthClass;
      for (int c = 0; c < face::kNumMouthClasses; ++c)
        frame.visemeProbabilities[static_cast<std::size_t>(c)] = static_cast<float>(visemeFrame_.probabilities[c]);
      visemes_->forgetBefore(visemesShown);  // shown again until newer ones are decided
    }
  }
  if (mouthStage_) {
    mouthStage_->getFrame(nextIndex_, mouthFrame_);
    Eigen::MatrixXd faps = animation::mouthFapsOf(*mouth_, mouthFrame_.components);
    if (networkStage_ && visemesShown == frame.index) {
      animation::blendPhoneMouth(*articulation_, visemeFrame_.probabilities, mouthFaps_, faps, options_.articulation);
      animation::articulateLips(*articulation_, {frame.mouthClass}, mouthFaps_, faps, options_.articulation);
    }
    frame.energy = mouthExtractor_.getEnergy(nextIndex_);
    frame.levelDb = mouthExtractor_.getLevelDb(nextIndex_);
    const Eigen::VectorXd& posterior = mouthFrame_.posterior;
    for (Eigen::Index k = 0; k < std::min<Eigen::Index>(posterior.size(), AnimationFrame::kMaxMouthStates); ++k)
      frame.mouthPosterior[static_cast<std::size_t>(k)] = static_cast<float>(posterior[k]);
    frame.mouthStates = std::min(mouthStage_->numStates(), AnimationFrame::kMaxMouthStates);
    for (std::size_t i = 0; i < mouthFaps_.size(); ++i)
      frame.faps[static_cast<std::size_t>(mouthFaps_[i])] = faps(static_cast<Eigen::Index>(i), 0);
  }
  ++nextIndex_;
  // What no later frame reads is freed: memory stays bounded however long the stream.
  const int nextShown = std::min(nextIndex_ - headDelayFrames_, decided);
  prosodyExtractor_.forgetBefore(nextShown);
  if (headStage_) headStage_->forgetBefore(nextShown);
  if (mouthStage_) {
    mouthStage_->forgetBefore(nextIndex_);
    mouthExtractor_.forgetBefore(nextIndex_);
  }
  return true;
}

std::vector<int> LiveDecoder::fapNumbers() const {
  std::vector<int> numbers = mouthFaps_;
  if (headStage_) numbers.insert(numbers.end(), animation::kHeadFaps.begin(), animation::kHeadFaps.end());
  std::sort(numbers.begin(), numbers.end());
  return numbers;
}

DecoderLookahead LiveDecoder::lookahead() const {
  constexpr double kFrameMs = 1000.0 / animation::kAnimationFramesPerSecond;
  DecoderLookahead result;
  result.featuresMs = prosodyExtractor_.lookahead().totalMs;
  result.mouthFeaturesMs = mouthExtractor_.lookahead().mfccMs;  // its base frames: no deltas to wait for
  result.headFrames = headStage_ ? headStage_->latencyFrames() : 0;
  result.mouthFrames = mouthStage_ ? mouthStage_->latencyFrames() : 0;
  result.headMs = result.featuresMs + result.headFrames * kFrameMs;
  result.mouthMs = mouthStage_ ? result.mouthFeaturesMs + result.mouthFrames * kFrameMs : 0.0;
  if (networkStage_) {
    result.articulationMs = networkExtractor_->lookahead().mfccMs +
                            1000.0 * networkStage_->latencyFrames() / animation::kSubframesPerSecond +
                            networkVisemes_->latencyFrames() * kFrameMs;
    if (mouthStage_) result.mouthMs = std::max(result.mouthMs, result.articulationMs);
  }
  if (mouthStage_ && !options_.waitForHead) {
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

namespace {

class ModelDecoder final : public FrameDecoder {
 public:
  ModelDecoder(std::shared_ptr<const AnimationModels> models, const LiveDecoderOptions& options)
      : models_(std::move(models)),
        decoder_(models_->head.get(), models_->mouth.get(), options, models_->visemes.get(),
                 models_->articulation.get()) {}
  void acceptWaveform(std::span<const float> samples16k) override { decoder_.acceptWaveform(samples16k); }
  void inputFinished() override { decoder_.inputFinished(); }
  bool next(AnimationFrame& frame) override { return decoder_.next(frame); }
  const LiveDecoder& decoder() const { return decoder_; }

 private:
  std::shared_ptr<const AnimationModels> models_;  // declared first: alive while decoder_ is
  LiveDecoder decoder_;
};

}  // namespace

StreamDecoder makeStreamDecoder(std::shared_ptr<const AnimationModels> models, const LiveDecoderOptions& options,
                                double inputRateHz) {
  if (!models) throw Error("stream decoder: no models");
  auto decoder = std::make_unique<ModelDecoder>(std::move(models), options);
  StreamDecoder made;
  made.lookahead = decoder->decoder().lookahead();
  made.fapNumbers = decoder->decoder().fapNumbers();
  if (inputRateHz == features::OnlineFeatureExtractor::kSampleRateHz)
    made.decoder = std::move(decoder);
  else
    made.decoder = std::make_unique<ResamplingDecoder>(std::move(decoder), inputRateHz);
  return made;
}

}  // namespace th::pipeline
