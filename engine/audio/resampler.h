// Streaming sample-rate conversion of mono float audio with libsoxr (high quality, linear phase).
//
//   th::audio::Resampler resampler(44100, 16000);
//   std::vector<float> out;
//   resampler.process(chunk, out);      // appends converted samples, any chunk size
//   resampler.finish(out);              // flushes the filter tail at end of input
//
// The output is aligned with the input (soxr compensates its own filter delay), so sample n of the output
// is at time n / outputRateHz. Thread contract: one thread per instance; set-up may throw th::Error.
// process() appends to a std::vector and may grow it: call it from a worker thread, not an audio callback.
#pragma once

#include <memory>
#include <span>
#include <vector>

struct soxr;

namespace th::audio {

class Resampler {
 public:
  Resampler(double inputRateHz, double outputRateHz);
  ~Resampler();
  Resampler(const Resampler&) = delete;
  Resampler& operator=(const Resampler&) = delete;

  void process(std::span<const float> input, std::vector<float>& output);
  void finish(std::vector<float>& output);

  double inputRateHz() const { return inputRateHz_; }
  double outputRateHz() const { return outputRateHz_; }

 private:
  void drain(const float* input, size_t inputLength, std::vector<float>& output);

  double inputRateHz_;
  double outputRateHz_;
  struct SoxrDeleter {
    void operator()(soxr* handle) const;
  };
  std::unique_ptr<soxr, SoxrDeleter> handle_;
};

// Whole-buffer convenience: the same streaming object, fed once and flushed.
std::vector<float> resample(std::span<const float> input, double inputRateHz, double outputRateHz);

}  // namespace th::audio
