#include "features/online_features.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "features/context.h"

namespace th::features {

void FeatureOptions::check() const {
  if (!(framesPerSecond >= 10.0 && framesPerSecond <= 200.0)) {
    throw Error("features: frame rate must be between 10 and 200 frames per second");
  }
  if (deltaHalfWidth < 1 || deltaHalfWidth > 10) throw Error("features: delta half-width must be 1..10 frames");
  if (contextFrames < 0 || contextFrames > 20) throw Error("features: context must be 0..20 frames");
  if (mfcc.numCoefficients < 1 || mfcc.numCoefficients > 40) throw Error("features: MFCC count must be 1..40");
  if (!(runningNormSeconds > 0)) throw Error("features: running normalisation time constant must be positive");
}

std::vector<std::string> FeatureLayout::columnNames() const {
  std::vector<std::string> mfccNames;
  for (int k = 1; k <= numMfcc; ++k) {
    mfccNames.push_back("mfcc" + std::to_string(hasC0 && k == numMfcc ? 0 : k));
  }
  std::vector<std::string> names = {"f0_hz", "energy", "d_f0", "d_energy"};
  names.insert(names.end(), mfccNames.begin(), mfccNames.end());
  for (int offset = -contextFrames; offset <= contextFrames; ++offset) {
    const std::string suffix = offset < 0 ? "_m" + std::to_string(-offset) : "_p" + std::to_string(offset);
    for (const auto& name : mfccNames) names.push_back("ctx_" + name + suffix);
  }
  return names;
}

OnlineFeatureExtractor::OnlineFeatureExtractor(const FeatureOptions& options)
    : options_((options.check(), options)),
      pitch_(options.pitch, kSampleRateHz),
      mfcc_(options.mfcc, kSampleRateHz),
      rightContextFrames_(std::max(options.deltaHalfWidth, options.contextFrames)) {
  layout_.numMfcc = mfcc_.numOutputs();
  layout_.hasC0 = options.mfcc.includeC0;
  layout_.contextFrames = options.contextFrames;
  window_.resize(static_cast<size_t>(mfcc_.windowLength()));
  // Squared Hamming weights, normalised to sum to 1, so the level is a weighted mean square.
  energyWeights_.resize(window_.size());
  double sum = 0.0;
  for (size_t n = 0; n < window_.size(); ++n) {
    const double w = 0.54 - 0.46 * std::cos(2.0 * 3.14159265358979323846 * static_cast<double>(n) /
                                            static_cast<double>(window_.size() - 1));
    energyWeights_[n] = static_cast<float>(w * w);
    sum += w * w;
  }
  for (float& weight : energyWeights_) weight = static_cast<float>(weight / sum);
}

long long OnlineFeatureExtractor::frameCentreSample(long long frame) const {
  return std::llround(static_cast<double>(frame) * kSampleRateHz / options_.framesPerSecond);
}

long long OnlineFeatureExtractor::totalFramesForSamples(long long numSamples) const {
  if (numSamples <= 0) return 0;
  // Frames whose time lies inside the signal: i / fps <= (n - 1) / fs.
  return static_cast<long long>(
             std::floor(static_cast<double>(numSamples - 1) * options_.framesPerSecond / kSampleRateHz + 1e-9)) +
         1;
}

int OnlineFeatureExtractor::pitchFrameFor(long long frame) const {
  return static_cast<int>(std::llround(static_cast<double>(frameCentreSample(frame)) / pitch_.hopSamples()));
}

void OnlineFeatureExtractor::acceptWaveform(std::span<const float> samples) {
  if (finished_) throw Error("features: acceptWaveform after inputFinished");
  if (options_.trackPitch) pitch_.acceptWaveform(samples);
  history_.append(samples);
  computeAvailableBaseFrames();
}

void OnlineFeatureExtractor::inputFinished() {
  if (finished_) return;
  finished_ = true;
  if (options_.trackPitch) pitch_.inputFinished();
  computeAvailableBaseFrames();
  if (options_.energyNormalisation == EnergyNormalisation::kUtterance) normaliseUtterance();
}

void OnlineFeatureExtractor::computeAvailableBaseFrames() {
  const long long half = mfcc_.windowLength() / 2;
  const long long total = totalFramesForSamples(history_.size());
  const int numMfcc = layout_.numMfcc;
  std::vector<float> coefficients(static_cast<size_t>(numMfcc));
  for (long long frame = static_cast<long long>(f0Hz_.size()); frame < total; ++frame) {
    const long long centre = frameCentreSample(frame);
    if (!finished_ && centre - half + mfcc_.windowLength() > history_.size()) break;
    if (options_.trackPitch) {
      int pitchFrame = pitchFrameFor(frame);
      if (pitchFrame >= pitch_.numFramesReady()) {
        if (!finished_) break;
        pitchFrame = pitch_.numFramesReady() - 1;  // the last frame's centre can round past the tracker's end
      }
      f0Hz_.push_back(pitchFrame >= 0 ? pitch_.frame(pitchFrame).f0Hz : 0.0f);
    } else {
      f0Hz_.push_back(0.0f);
    }

    history_.copy(centre - half, window_);
    mfcc_.compute(window_, coefficients);
    for (const float c : coefficients) mfccRows_.push_back(c);

    // Level in dB re full scale, Hamming-weighted over the MFCC window.
    double weighted = 0.0;
    for (size_t n = 0; n < window_.size(); ++n) {
      weighted += static_cast<double>(energyWeights_[n]) * window_[n] * window_[n];
    }
    // Floor at -140 dB: below any real recording (16-bit dither is near -100 dB) but finite for digital zeros.
    // Pauses are floored at energyRangeDb below the loudest frame so far: digital silence would otherwise sit
    // at -140 dB and dominate the normalisation statistics.
    double levelDb = 10.0 * std::log10(weighted + 1e-14);
    loudestDb_ = std::max(loudestDb_, levelDb);
    levelDb = std::max(levelDb, loudestDb_ - options_.energyRangeDb);
    energyDb_.push_back(static_cast<float>(levelDb));

    switch (options_.energyNormalisation) {
      case EnergyNormalisation::kRunning: {
        // Exponentially weighted mean/variance; the first frames average everything seen so far.
        const double count = static_cast<double>(energyDb_.size());
        const double alpha = std::max(1.0 / count, 1.0 / (options_.runningNormSeconds * options_.framesPerSecond));
        const double delta = levelDb - runningMean_;
        runningMean_ += alpha * delta;
        runningVariance_ = (1.0 - alpha) * (runningVariance_ + alpha * delta * delta);
        energy_.push_back(static_cast<float>((levelDb - runningMean_) / std::sqrt(std::max(runningVariance_, 1.0))));
        break;
      }
      case EnergyNormalisation::kNone:
        energy_.push_back(static_cast<float>(levelDb));
        break;
      case EnergyNormalisation::kUtterance:
        energy_.push_back(0.0f);  // filled in by normaliseUtterance()
        break;
    }
  }
  // Drop samples that no future frame needs.
  history_.forgetBefore(frameCentreSample(static_cast<long long>(f0Hz_.size())) - half);
}

void OnlineFeatureExtractor::normaliseUtterance() {
  if (energyDb_.empty()) return;
  double mean = 0.0;
  for (size_t i = 0; i < energyDb_.size(); ++i) mean += energyDb_[i];
  mean /= static_cast<double>(energyDb_.size());
  double variance = 0.0;
  for (size_t i = 0; i < energyDb_.size(); ++i) variance += (energyDb_[i] - mean) * (energyDb_[i] - mean);
  variance /= static_cast<double>(energyDb_.size());
  const double scale = 1.0 / std::sqrt(std::max(variance, 1.0));
  for (size_t i = 0; i < energyDb_.size(); ++i) energy_[i] = static_cast<float>((energyDb_[i] - mean) * scale);
}

int OnlineFeatureExtractor::numFramesReady() const {
  const auto computed = static_cast<long long>(f0Hz_.size());
  if (finished_) return static_cast<int>(computed);
  if (options_.energyNormalisation == EnergyNormalisation::kUtterance) return 0;
  return static_cast<int>(std::max<long long>(0, computed - rightContextFrames_));
}

bool OnlineFeatureExtractor::isLastFrame(int frame) const {
  return finished_ && frame == static_cast<int>(f0Hz_.size()) - 1;
}

void OnlineFeatureExtractor::getMfcc(int frame, std::span<float> mfcc) const {
  const auto numMfcc = static_cast<size_t>(layout_.numMfcc);
  for (size_t k = 0; k < numMfcc; ++k) mfcc[k] = mfccRows_[static_cast<size_t>(frame) * numMfcc + k];
}

void OnlineFeatureExtractor::forgetBefore(int frame) {
  if (options_.energyNormalisation == EnergyNormalisation::kUtterance)
    throw Error("features: frames cannot be forgotten with utterance normalisation");
  // getFrame(i) reads frames i - max(delta, context) .. i + max(delta, context).
  const int margin = std::max(options_.deltaHalfWidth, options_.contextFrames);
  const auto keepFrom = static_cast<size_t>(std::max(0, frame - margin));
  f0Hz_.forgetBefore(keepFrom);
  energyDb_.forgetBefore(keepFrom);
  energy_.forgetBefore(keepFrom);
  mfccRows_.forgetBefore(keepFrom * static_cast<size_t>(layout_.numMfcc));
  // New frames read the pitch frame nearest their centre (at the very end, the tracker's last): a few before
  // the next frame's are kept, none earlier.
  pitch_.forgetBefore(std::max(0, pitchFrameFor(static_cast<long long>(f0Hz_.size())) - 8));
}

float OnlineFeatureExtractor::getEnergy(int frame) const {
  return energy_[static_cast<size_t>(frame)];
}

float OnlineFeatureExtractor::getLevelDb(int frame) const {
  return energyDb_[static_cast<size_t>(frame)];
}

void OnlineFeatureExtractor::getFrame(int frame, std::span<float> row) const {
  const int count = static_cast<int>(f0Hz_.size());
  const auto at = [count](int i) { return static_cast<size_t>(std::clamp(i, 0, count - 1)); };
  const auto i = static_cast<size_t>(frame);
  row[FeatureLayout::kF0Hz] = f0Hz_[i];
  row[FeatureLayout::kEnergy] = energy_[i];

  // Regression deltas (HTK): d = sum_n n (c[t+n] - c[t-n]) / (2 sum_n n^2), edges replicated.
  // F0 is undefined where unvoiced: an unvoiced frame has d_f0 = 0, and unvoiced neighbours count as
  // equal to the centre frame, so a voicing boundary does not look like a jump to or from 0 Hz.
  const int width = options_.deltaHalfWidth;
  double denominator = 0.0;
  double deltaF0 = 0.0;
  double deltaEnergy = 0.0;
  const float centreF0 = f0Hz_[i];
  for (int n = 1; n <= width; ++n) {
    denominator += 2.0 * n * n;
    deltaEnergy += n * (static_cast<double>(energy_[at(frame + n)]) - energy_[at(frame - n)]);
    const float after = f0Hz_[at(frame + n)] > 0.0f ? f0Hz_[at(frame + n)] : centreF0;
    const float before = f0Hz_[at(frame - n)] > 0.0f ? f0Hz_[at(frame - n)] : centreF0;
    deltaF0 += n * (static_cast<double>(after) - before);
  }
  row[FeatureLayout::kDeltaF0] = centreF0 > 0.0f ? static_cast<float>(deltaF0 / denominator) : 0.0f;
  row[FeatureLayout::kDeltaEnergy] = static_cast<float>(deltaEnergy / denominator);

  const auto numMfcc = static_cast<size_t>(layout_.numMfcc);
  for (size_t k = 0; k < numMfcc; ++k) row[FeatureLayout::kMfccBegin + k] = mfccRows_[i * numMfcc + k];
  size_t column = static_cast<size_t>(layout_.contextBegin());
  for (int offset = -layout_.contextFrames; offset <= layout_.contextFrames; ++offset) {
    const auto source = static_cast<size_t>(contextSource(frame, offset, count)) * numMfcc;
    for (size_t k = 0; k < numMfcc; ++k) row[column + k] = mfccRows_[source + k];
    column += numMfcc;
  }
}

FeatureLookahead OnlineFeatureExtractor::lookahead() const {
  const double frameMs = 1000.0 / options_.framesPerSecond;
  const double sampleMs = 1000.0 / kSampleRateHz;
  FeatureLookahead result{};
  // F0 of frame i comes from the pitch frame nearest its time, up to half a pitch hop later.
  result.f0Ms = options_.trackPitch ? (pitch_.lookaheadSamples() + pitch_.hopSamples() / 2.0) * sampleMs : 0.0;
  result.mfccMs = (mfcc_.windowLength() - mfcc_.windowLength() / 2) * sampleMs;
  result.energyMs = result.mfccMs;
  const double base = std::max(result.f0Ms, result.mfccMs);
  result.deltasMs = options_.deltaHalfWidth * frameMs + base;
  result.contextMs = options_.contextFrames * frameMs + result.mfccMs;
  result.totalMs = rightContextFrames_ * frameMs + base;
  result.totalFrames = static_cast<int>(std::ceil(result.totalMs / frameMs - 1e-9));
  return result;
}

FeatureOptions batchFeatureOptions() {
  FeatureOptions options;
  options.energyNormalisation = EnergyNormalisation::kUtterance;
  return options;
}

FeatureMatrix computeFeatures(std::span<const float> samples16k, const FeatureOptions& options) {
  OnlineFeatureExtractor extractor(options);
  extractor.acceptWaveform(samples16k);
  extractor.inputFinished();
  FeatureMatrix matrix;
  matrix.layout = extractor.layout();
  matrix.framesPerSecond = options.framesPerSecond;
  const int width = matrix.layout.size();
  matrix.values.resize(static_cast<size_t>(extractor.numFramesReady()) * static_cast<size_t>(width));
  for (int frame = 0; frame < extractor.numFramesReady(); ++frame) {
    extractor.getFrame(frame, {matrix.values.data() + static_cast<size_t>(frame) * width, static_cast<size_t>(width)});
    matrix.levelDb.push_back(extractor.getLevelDb(frame));
  }
  return matrix;
}

}  // namespace th::features
