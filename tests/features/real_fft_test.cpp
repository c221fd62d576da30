// The real FFT's two back ends (engine/features/real_fft.h): Eigen's, which the WebAssembly build uses, gives
// FFTW's spectrum and inverse to float precision, on speech and on a tone.
#include "features/real_fft.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "audio/audio_file.h"
#include "core/data_path.h"
#include "core/error.h"

namespace {

using th::features::FftBackend;
using th::features::RealFft;

// The largest difference between the two back ends' spectra of `signal`, over the spectrum's largest magnitude.
double spectrumDifference(const std::vector<float>& signal, int size) {
  RealFft fftw(size, FftBackend::kFftw), eigen(size, FftBackend::kEigen);
  for (RealFft* fft : {&fftw, &eigen}) {
    std::fill(fft->timeData(), fft->timeData() + size, 0.0F);
    std::copy_n(signal.begin(), std::min<int>(size, static_cast<int>(signal.size())), fft->timeData());
    fft->forward();
  }
  double largest = 0.0, difference = 0.0;
  for (int k = 0; k < fftw.numBins(); ++k) {
    largest = std::max(largest, static_cast<double>(std::abs(fftw.spectrum()[k])));
    difference = std::max(difference, static_cast<double>(std::abs(fftw.spectrum()[k] - eigen.spectrum()[k])));
  }
  return difference / largest;
}

TEST(RealFft, EigensSpectrumIsFftwsOnSpeechToFloatPrecision) {
  const std::vector<float> speech = th::audio::readAudioFile(th::sharedDataPath("beat2/2_scott_0_1_1.wav")).samples;
  for (const int size : {512, 1024}) {
    // 30 frames spread over the recording.
    for (std::size_t start = 16000; start + 1024 < speech.size() && start < 16000 * 31; start += 16000) {
      const std::vector<float> frame(speech.begin() + static_cast<std::ptrdiff_t>(start),
                                     speech.begin() + static_cast<std::ptrdiff_t>(start) + size);
      EXPECT_LT(spectrumDifference(frame, size), 1e-6) << "size " << size << ", sample " << start;
    }
  }
}

TEST(RealFft, EachBackEndFindsAToneAndInvertsToSizeTimesTheSignal) {
  constexpr int kSize = 768;  // 3 x 256: a mixed radix too
  for (const FftBackend backend : {FftBackend::kFftw, FftBackend::kEigen}) {
    RealFft fft(kSize, backend);
    std::vector<float> signal(kSize);
    for (int n = 0; n < kSize; ++n)
      signal[static_cast<std::size_t>(n)] = static_cast<float>(std::cos(2.0 * std::numbers::pi * 37.0 * n / kSize));
    std::copy(signal.begin(), signal.end(), fft.timeData());
    fft.forward();
    int peak = 0;
    for (int k = 1; k < fft.numBins(); ++k)
      if (std::abs(fft.spectrum()[k]) > std::abs(fft.spectrum()[peak])) peak = k;
    EXPECT_EQ(peak, 37);
    EXPECT_NEAR(std::abs(fft.spectrum()[37]), kSize / 2.0, 1e-3 * kSize);
    fft.inverse();
    for (int n = 0; n < kSize; ++n)
      ASSERT_NEAR(fft.timeData()[n], kSize * signal[static_cast<std::size_t>(n)], 1e-3) << "sample " << n;
  }
}

TEST(RealFft, RefusesASizeThatIsNotAMultipleOfFour) {
  EXPECT_THROW(RealFft(510), th::Error);
  EXPECT_THROW(RealFft(2, FftBackend::kEigen), th::Error);
}

}  // namespace
