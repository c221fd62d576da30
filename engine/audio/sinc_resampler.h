// Streaming sample-rate conversion of mono float audio with a Kaiser-windowed sinc filter, in the engine's own
// code: what the WebAssembly build resamples with (web/), where libsoxr (audio/resampler.h, the native
// converter) is not built. Allocation-free once made, so that an AudioWorklet's process() can call it.
//
//   th::audio::SincResampler resampler(48000, 16000);
//   std::array<float, 4096> out;
//   const std::size_t n = resampler.process(block, out);   // at most resampler.maxOutput(block.size())
//   ...
//   const std::size_t last = resampler.finish(out);         // the filter's tail at the end of the input
//
// As soxr's converter, the output is aligned with the input: output sample n is the input's value at time
// n / outputRateHz (the filter is centred, its delay compensated), and a whole input of N samples gives
// round(N * outputRate / inputRate) samples. The filter passes up to `passband` of the lower rate's Nyquist
// frequency and stops above it (the cut-off midway between the passband's edge and Nyquist).
//
// Thread contract: one thread per instance; the constructor may throw th::Error, nothing else throws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace th::audio {

struct SincResamplerOptions {
  double passband = 0.94;       // of the lower rate's Nyquist frequency, passed whole
  int zeroCrossings = 32;       // of the sinc on each side: the filter's length (and look-ahead) in cut-off periods
  double kaiserBeta = 8.0;      // the window's: about 80 dB of stop-band attenuation
  int phasesPerSample = 512;    // the filter's table resolution (linear interpolation between entries)
  std::size_t maxBlock = 8192;  // the largest input a call to process() takes at once (larger ones go in pieces)
};

class SincResampler {
 public:
  // Rates from 1 Hz to 1 MHz, in any ratio; throws th::Error for others.
  SincResampler(double inputRateHz, double outputRateHz, const SincResamplerOptions& options = {});

  // Converts `input`, writes the output samples now decided into `output` and returns their count;
  // `output` must hold maxOutput(input.size()).
  std::size_t process(std::span<const float> input, std::span<float> output);
  // The input ended: the samples still due (their filter reaching past the end sees silence).
  std::size_t finish(std::span<float> output);
  // The most samples process() writes for `inputCount` samples in, and finish() at most.
  std::size_t maxOutput(std::size_t inputCount) const;

  double inputRateHz() const { return inputRateHz_; }
  double outputRateHz() const { return outputRateHz_; }
  // How far past an output sample's time the input must reach before it is written.
  double lookaheadSeconds() const { return halfWidth_ / inputRateHz_; }

 private:
  float sample(double position) const;  // the filtered input at `position` (input samples from the start)
  std::size_t emitUpTo(std::int64_t availableEnd, std::span<float> output);

  double inputRateHz_;
  double outputRateHz_;
  double step_;       // input samples per output sample
  double cutoff_;     // cycles per input sample, times two (1 = the input's Nyquist frequency)
  double halfWidth_;  // the filter's half length, in input samples
  int phases_;
  std::vector<float> table_;  // the filter at distances 0, 1/phases, ... halfWidth_ (+ guard)
  // The input kept: samples [bufferStart_, bufferStart_ + buffered_) of the whole stream.
  std::vector<float> buffer_;
  std::size_t buffered_ = 0;
  std::int64_t bufferStart_ = 0;
  std::int64_t received_ = 0;  // input samples in all
  std::int64_t emitted_ = 0;   // output samples in all
  std::size_t maxBlock_;
  bool finished_ = false;
};

// A whole buffer converted: the same object, fed once and finished.
std::vector<float> sincResample(std::span<const float> input, double inputRateHz, double outputRateHz);

}  // namespace th::audio
