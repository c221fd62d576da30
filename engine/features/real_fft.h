// A real-input FFT of fixed size (FFTW, single precision), with its own aligned buffers.
//
//   th::features::RealFft fft(1024);
//   std::copy(frame.begin(), frame.end(), fft.timeData());   // 1024 samples, zero-pad yourself
//   fft.forward();                                           // fft.spectrum(): 513 complex bins
//   fft.inverse();                                           // back to fft.timeData(), scaled by 1024
//
// Plans are made with FFTW_ESTIMATE so that results are the same on every run and every machine (MEASURE
// picks codelets by timing, which would make features differ run to run). Thread contract: plan creation
// is serialised internally; one instance per thread afterwards.
#pragma once

#include <complex>
#include <cstddef>

namespace th::features {

class RealFft {
 public:
  explicit RealFft(int size);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  int size() const { return size_; }
  int numBins() const { return size_ / 2 + 1; }
  float* timeData() { return time_; }
  std::complex<float>* spectrum() { return spectrum_; }

  void forward();  // timeData -> spectrum
  void inverse();  // spectrum -> timeData (unnormalised: multiplied by size())

 private:
  int size_;
  float* time_;
  std::complex<float>* spectrum_;
  void* forwardPlan_;
  void* inversePlan_;
};

}  // namespace th::features
