#include "features/real_fft.h"

#include <fftw3.h>

#include <mutex>

#include "core/error.h"

namespace th::features {
namespace {
std::mutex& planMutex() {
  static std::mutex mutex;  // FFTW's planner is not thread-safe; execution is.
  return mutex;
}
}  // namespace

RealFft::RealFft(int size) : size_(size) {
  if (size < 2 || size % 2 != 0) throw Error("RealFft: size must be even and at least 2");
  std::lock_guard lock(planMutex());
  time_ = fftwf_alloc_real(static_cast<size_t>(size));
  spectrum_ = reinterpret_cast<std::complex<float>*>(fftwf_alloc_complex(static_cast<size_t>(numBins())));
  auto* spectrum = reinterpret_cast<fftwf_complex*>(spectrum_);
  forwardPlan_ = fftwf_plan_dft_r2c_1d(size, time_, spectrum, FFTW_ESTIMATE);
  inversePlan_ = fftwf_plan_dft_c2r_1d(size, spectrum, time_, FFTW_ESTIMATE);
  if (!forwardPlan_ || !inversePlan_) throw Error("RealFft: FFTW could not make a plan");
}

RealFft::~RealFft() {
  std::lock_guard lock(planMutex());
  fftwf_destroy_plan(static_cast<fftwf_plan>(forwardPlan_));
  fftwf_destroy_plan(static_cast<fftwf_plan>(inversePlan_));
  fftwf_free(time_);
  fftwf_free(spectrum_);
}

void RealFft::forward() {
  fftwf_execute(static_cast<fftwf_plan>(forwardPlan_));
}
void RealFft::inverse() {
  fftwf_execute(static_cast<fftwf_plan>(inversePlan_));
}

}  // namespace th::features
