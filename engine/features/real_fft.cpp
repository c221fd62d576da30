#include "features/real_fft.h"

#include <algorithm>
#include <unsupported/Eigen/FFT>
#include <vector>

#ifndef TALKINGHEAD_WITHOUT_FFTW
#include <fftw3.h>

#include <mutex>
#endif

#include "core/error.h"

namespace th::features {

class RealFft::Transform {
 public:
  virtual ~Transform() = default;
  virtual float* time() = 0;
  virtual std::complex<float>* spectrum() = 0;
  virtual void forward() = 0;
  virtual void inverse() = 0;
};

namespace {

// Eigen's FFT module, kissfft underneath: for a size that is a multiple of 4, a complex transform of half the
// size and a twiddle pass (its real-input path).
class EigenTransform final : public RealFft::Transform {
 public:
  explicit EigenTransform(int size)
      : size_(size), time_(static_cast<std::size_t>(size), 0.0F), spectrum_(static_cast<std::size_t>(size / 2 + 1)) {
    fft_.SetFlag(Eigen::FFT<float>::HalfSpectrum);
    fft_.SetFlag(Eigen::FFT<float>::Unscaled);
    // Its plans, twiddles and work buffers are made on first use: make them here, not in a streaming call.
    forward();
    inverse();
    std::fill(time_.begin(), time_.end(), 0.0F);
    std::fill(spectrum_.begin(), spectrum_.end(), std::complex<float>{});
  }
  float* time() override { return time_.data(); }
  std::complex<float>* spectrum() override { return spectrum_.data(); }
  void forward() override { fft_.fwd(spectrum_.data(), time_.data(), size_); }
  void inverse() override { fft_.inv(time_.data(), spectrum_.data(), size_); }

 private:
  int size_;
  Eigen::FFT<float> fft_;
  std::vector<float> time_;
  std::vector<std::complex<float>> spectrum_;
};

#ifndef TALKINGHEAD_WITHOUT_FFTW
std::mutex& planMutex() {
  static std::mutex mutex;  // FFTW's planner is not thread-safe; execution is.
  return mutex;
}

class FftwTransform final : public RealFft::Transform {
 public:
  explicit FftwTransform(int size) {
    std::lock_guard lock(planMutex());
    time_ = fftwf_alloc_real(static_cast<size_t>(size));
    spectrum_ = reinterpret_cast<std::complex<float>*>(fftwf_alloc_complex(static_cast<size_t>(size / 2 + 1)));
    auto* spectrum = reinterpret_cast<fftwf_complex*>(spectrum_);
    forwardPlan_ = fftwf_plan_dft_r2c_1d(size, time_, spectrum, FFTW_ESTIMATE);
    inversePlan_ = fftwf_plan_dft_c2r_1d(size, spectrum, time_, FFTW_ESTIMATE);
    if (forwardPlan_ == nullptr || inversePlan_ == nullptr) {
      release();
      throw Error("RealFft: FFTW could not make a plan");
    }
  }
  ~FftwTransform() override {
    std::lock_guard lock(planMutex());
    release();
  }
  float* time() override { return time_; }
  std::complex<float>* spectrum() override { return spectrum_; }
  void forward() override { fftwf_execute(forwardPlan_); }
  void inverse() override { fftwf_execute(inversePlan_); }

 private:
  void release() {
    if (forwardPlan_ != nullptr) fftwf_destroy_plan(forwardPlan_);
    if (inversePlan_ != nullptr) fftwf_destroy_plan(inversePlan_);
    fftwf_free(time_);
    fftwf_free(spectrum_);
  }
  float* time_ = nullptr;
  std::complex<float>* spectrum_ = nullptr;
  fftwf_plan forwardPlan_ = nullptr;
  fftwf_plan inversePlan_ = nullptr;
};
#endif

}  // namespace

RealFft::RealFft(int size, FftBackend backend) : size_(size) {
  if (size < 4 || size % 4 != 0) throw Error("RealFft: the size must be a multiple of 4");
  if (backend == FftBackend::kEigen) {
    transform_ = std::make_unique<EigenTransform>(size);
  } else {
#ifndef TALKINGHEAD_WITHOUT_FFTW
    transform_ = std::make_unique<FftwTransform>(size);
#else
    throw Error("RealFft: this build has no FFTW");
#endif
  }
  time_ = transform_->time();
  spectrum_ = transform_->spectrum();
}

RealFft::~RealFft() = default;

void RealFft::forward() {
  transform_->forward();
}
void RealFft::inverse() {
  transform_->inverse();
}

}  // namespace th::features
