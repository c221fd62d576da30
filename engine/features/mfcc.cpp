#include "features/mfcc.h"

#include <cmath>
#include <numbers>

#include "core/error.h"

namespace th::features {
namespace {
double hzToMel(double hz) {
  return 1127.01048 * std::log(1.0 + hz / 700.0);
}
}  // namespace

MfccComputer::MfccComputer(const MfccOptions& options, int sampleRateHz)
    : options_(options),
      windowLength_(static_cast<int>(std::lround(options.windowMs * 1e-3 * sampleRateHz))),
      fft_(options.fftSize) {
  if (windowLength_ < 2 || windowLength_ > options.fftSize) {
    throw Error("MFCC: the window (" + std::to_string(windowLength_) + " samples) must fit the FFT size (" +
                std::to_string(options.fftSize) + ")");
  }
  if (options.numCoefficients < 1 || options.numCoefficients >= options.numMelBands) {
    throw Error("MFCC: need 1 <= coefficients < mel bands");
  }
  hamming_.resize(static_cast<size_t>(windowLength_));
  for (int n = 0; n < windowLength_; ++n) {
    hamming_[static_cast<size_t>(n)] =
        static_cast<float>(0.54 - 0.46 * std::cos(2.0 * std::numbers::pi * n / (windowLength_ - 1)));
  }

  // Filterbank as SPTK lays it out: boundaries b_c = (c+1)/(M+1) * mel(Nyquist), c = 0..M. A bin whose mel
  // value lies in (b_{c-1}, b_c] gives weight w = (b_c - mel)/spacing to channel c and 1 - w to channel c+1
  // (channels numbered 1..M; channel M+1 is dropped).
  const int numBands = options.numMelBands;
  const int half = options.fftSize / 2;
  const double maxMel = hzToMel(sampleRateHz / 2.0);
  const double spacing = maxMel / (numBands + 1);
  lowerChannel_.assign(static_cast<size_t>(half), 0);
  lowerWeight_.assign(static_cast<size_t>(half), 0.0);
  if (!(options.frequencyWarp >= 0.5 && options.frequencyWarp <= 2.0))
    throw Error("MFCC: the frequency warp must be in [0.5, 2]");
  // VTLP's warp: α·f up to a boundary, then the line to the Nyquist frequency (Jaitly & Hinton 2013, with their
  // upper boundary of 4.8 kHz at 8 kHz scaled to the Nyquist frequency).
  const double nyquist = sampleRateHz / 2.0;
  const double alpha = options.frequencyWarp;
  const double boundary = 0.6 * nyquist * std::min(alpha, 1.0) / alpha;
  const auto warp = [&](double hz) {
    if (alpha == 1.0) return hz;
    if (hz <= boundary) return alpha * hz;
    return nyquist - (nyquist - alpha * boundary) / (nyquist - boundary) * (nyquist - hz);
  };
  int channel = 0;
  for (int k = 1; k < half; ++k) {
    const double mel = hzToMel(warp(static_cast<double>(k) * sampleRateHz / options.fftSize));
    while (channel <= numBands && (channel + 1) * spacing < mel) ++channel;
    lowerChannel_[static_cast<size_t>(k)] = channel;
    lowerWeight_[static_cast<size_t>(k)] = ((channel + 1) * spacing - mel) / spacing;
  }

  // Orthonormal DCT-II for c1..cN (what SPTK's FFT-based dct() works out to). SPTK's c0 (its -0 output) is
  // not the DCT's row 0 but sqrt(2/M) times the sum of the log channels, i.e. sqrt(2) times the orthonormal
  // c0; we follow SPTK so that c0 can be checked against it too.
  const int numRows = options.numCoefficients + 1;
  dctBasis_.resize(static_cast<size_t>(numRows * numBands));
  for (int k = 0; k < numRows; ++k) {
    const double scale = std::sqrt(2.0 / numBands);
    for (int j = 0; j < numBands; ++j) {
      dctBasis_[static_cast<size_t>(k * numBands + j)] = scale * std::cos(std::numbers::pi * k * (j + 0.5) / numBands);
    }
  }
  lifterGain_.assign(static_cast<size_t>(numRows), 1.0);
  if (options.lifter > 0) {
    for (int k = 0; k < numRows; ++k) {
      lifterGain_[static_cast<size_t>(k)] =
          1.0 + options.lifter / 2.0 * std::sin(std::numbers::pi * k / options.lifter);
    }
  }
  bands_.resize(static_cast<size_t>(numBands + 2));
}

void MfccComputer::compute(std::span<const float> window, std::span<float> coefficients) {
  constexpr double kInt16Scale = 32768.0;
  const auto alpha = static_cast<float>(options_.preEmphasis);
  float* time = fft_.timeData();
  // Pre-emphasis runs backwards so it can work in place on the window copy.
  for (int n = 0; n < windowLength_; ++n) time[n] = static_cast<float>(window[static_cast<size_t>(n)] * kInt16Scale);
  for (int n = windowLength_ - 1; n >= 1; --n) time[n] -= alpha * time[n - 1];
  time[0] *= 1.0f - alpha;
  for (int n = 0; n < windowLength_; ++n) time[n] *= hamming_[static_cast<size_t>(n)];
  for (int n = windowLength_; n < fft_.size(); ++n) time[n] = 0.0f;
  fft_.forward();

  const int numBands = options_.numMelBands;
  std::fill(bands_.begin(), bands_.end(), 0.0);
  const std::complex<float>* spectrum = fft_.spectrum();
  for (int k = 1; k < fft_.size() / 2; ++k) {
    const double magnitude = std::abs(spectrum[k]);
    const int channel = lowerChannel_[static_cast<size_t>(k)];
    const double weight = lowerWeight_[static_cast<size_t>(k)];
    if (channel > 0) bands_[static_cast<size_t>(channel)] += magnitude * weight;
    if (channel <= numBands) bands_[static_cast<size_t>(channel + 1)] += magnitude * (1.0 - weight);
  }
  for (int j = 1; j <= numBands; ++j) {
    bands_[static_cast<size_t>(j)] = std::log(std::max(bands_[static_cast<size_t>(j)], options_.filterbankFloor));
  }

  auto cepstrum = [&](int k) {
    double sum = 0.0;
    for (int j = 0; j < numBands; ++j)
      sum += dctBasis_[static_cast<size_t>(k * numBands + j)] * bands_[static_cast<size_t>(j + 1)];
    return sum * lifterGain_[static_cast<size_t>(k)];
  };
  for (int k = 1; k <= options_.numCoefficients; ++k) {
    coefficients[static_cast<size_t>(k - 1)] = static_cast<float>(cepstrum(k));
  }
  if (options_.includeC0) coefficients[static_cast<size_t>(options_.numCoefficients)] = static_cast<float>(cepstrum(0));
}

}  // namespace th::features
