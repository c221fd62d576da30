// A real-input FFT of fixed size (single precision), with its own buffers.
//
//   th::features::RealFft fft(1024);
//   std::copy(frame.begin(), frame.end(), fft.timeData());   // 1024 samples, zero-pad yourself
//   fft.forward();                                           // fft.spectrum(): 513 complex bins
//   fft.inverse();                                           // back to fft.timeData(), scaled by 1024
//
// Two back ends, one interface. Natively FFTW, with plans made with FFTW_ESTIMATE so that results are the same
// on every run and every machine (MEASURE picks codelets by timing). In the WebAssembly build (web/), where
// FFTW does not build, Eigen's FFT module (its kissfft, header-only); natively it is there too, to be checked
// against FFTW (tests/features). FFTW stays the native default for speed: with Eigen's the features run 243
// times faster than real time on one core instead of 577 (bench/features_bench, the pitch tracker's two
// 1024-point transforms every 5 ms being most of it), under the 500 they must keep.
// Thread contract: FFTW's plan creation is serialised internally; one instance per thread afterwards.
#pragma once

#include <complex>
#include <memory>

namespace th::features {

enum class FftBackend { kFftw, kEigen };

#ifdef TALKINGHEAD_WITHOUT_FFTW
inline constexpr FftBackend kDefaultFftBackend = FftBackend::kEigen;
#else
inline constexpr FftBackend kDefaultFftBackend = FftBackend::kFftw;
#endif

class RealFft {
 public:
  // size: a multiple of 4. Throws th::Error for another size, or a back end this build lacks.
  explicit RealFft(int size, FftBackend backend = kDefaultFftBackend);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  int size() const { return size_; }
  int numBins() const { return size_ / 2 + 1; }
  float* timeData() { return time_; }
  std::complex<float>* spectrum() { return spectrum_; }

  void forward();  // timeData -> spectrum
  void inverse();  // spectrum -> timeData (unnormalised: multiplied by size())

  class Transform;  // a back end's plans and buffers

 private:
  int size_;
  std::unique_ptr<Transform> transform_;
  float* time_ = nullptr;                    // owned by transform_
  std::complex<float>* spectrum_ = nullptr;  // owned by transform_
};

}  // namespace th::features
