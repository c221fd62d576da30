#include "audio/sinc_resampler.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace th::audio {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The modified Bessel function of the first kind, order 0, by its power series (the Kaiser window's; what
// std::cyl_bessel_i gives where the standard library has it, which the WebAssembly build's does not).
double besselI0(double x) {
  double sum = 1.0, term = 1.0;
  const double quarterSquare = 0.25 * x * x;
  for (int k = 1; k < 200 && term > 1e-17 * sum; ++k) {
    term *= quarterSquare / (static_cast<double>(k) * static_cast<double>(k));
    sum += term;
  }
  return sum;
}

}  // namespace

SincResampler::SincResampler(double inputRateHz, double outputRateHz, const SincResamplerOptions& options)
    : inputRateHz_(inputRateHz), outputRateHz_(outputRateHz), maxBlock_(options.maxBlock) {
  const auto valid = [](double rate) { return std::isfinite(rate) && rate >= 1.0 && rate <= 1e6; };
  if (!valid(inputRateHz) || !valid(outputRateHz))
    throw Error("resampler: sample rates must be 1 Hz to 1 MHz (not " + std::to_string(inputRateHz) + " to " +
                std::to_string(outputRateHz) + ")");
  if (!(options.passband > 0.0 && options.passband < 1.0) || options.zeroCrossings < 1 || options.phasesPerSample < 1 ||
      options.maxBlock < 1 || !(options.kaiserBeta >= 0.0))
    throw Error("resampler: options out of range");
  step_ = inputRateHz / outputRateHz;
  cutoff_ = 0.5 * (1.0 + options.passband) * std::min(1.0, outputRateHz / inputRateHz);
  halfWidth_ = options.zeroCrossings / cutoff_;
  phases_ = options.phasesPerSample;
  const auto entries = static_cast<std::size_t>(std::ceil(halfWidth_ * phases_)) + 2;
  table_.resize(entries);
  const double norm = besselI0(options.kaiserBeta);
  for (std::size_t j = 0; j < entries; ++j) {
    const double d = static_cast<double>(j) / phases_;
    const double r = d / halfWidth_;
    if (r >= 1.0) {
      table_[j] = 0.0f;
      continue;
    }
    const double x = cutoff_ * d;
    const double sinc = x == 0.0 ? 1.0 : std::sin(kPi * x) / (kPi * x);
    const double window = besselI0(options.kaiserBeta * std::sqrt(1.0 - r * r)) / norm;
    table_[j] = static_cast<float>(cutoff_ * sinc * window);
  }
  // Room for a block and the filter's reach on both sides, with a sample to spare at each end.
  buffer_.resize(maxBlock_ + 2 * static_cast<std::size_t>(std::ceil(halfWidth_ + step_)) + 4);
}

std::size_t SincResampler::maxOutput(std::size_t inputCount) const {
  return static_cast<std::size_t>(std::ceil((static_cast<double>(inputCount) + 2.0 * halfWidth_ + 2.0) / step_)) + 2;
}

float SincResampler::sample(double position) const {
  const auto first = static_cast<std::int64_t>(std::ceil(position - halfWidth_));
  const auto last = static_cast<std::int64_t>(std::floor(position + halfWidth_));
  const std::int64_t from = std::max<std::int64_t>(first, std::max<std::int64_t>(bufferStart_, 0));
  const std::int64_t to = std::min<std::int64_t>(last, bufferStart_ + static_cast<std::int64_t>(buffered_) - 1);
  double sum = 0.0;
  for (std::int64_t k = from; k <= to; ++k) {
    const double at = std::abs(position - static_cast<double>(k)) * phases_;
    const auto j = static_cast<std::size_t>(at);
    const double fraction = at - static_cast<double>(j);
    const double h = table_[j] + fraction * (table_[j + 1] - table_[j]);
    sum += h * buffer_[static_cast<std::size_t>(k - bufferStart_)];
  }
  return static_cast<float>(sum);
}

std::size_t SincResampler::emitUpTo(std::int64_t due, std::span<float> output) {
  std::size_t written = 0;
  while (emitted_ < due && written < output.size()) {
    output[written++] = sample(static_cast<double>(emitted_) * step_);
    ++emitted_;
  }
  return written;
}

std::size_t SincResampler::process(std::span<const float> input, std::span<float> output) {
  if (finished_) throw Error("resampler: input after the end");
  std::size_t written = 0;
  while (!input.empty()) {
    const std::size_t piece = std::min(input.size(), maxBlock_);
    // Drop the samples no output still due reaches back to.
    const auto needed = static_cast<std::int64_t>(std::ceil(static_cast<double>(emitted_) * step_ - halfWidth_)) - 1;
    if (needed > bufferStart_) {
      const std::int64_t drop = std::min<std::int64_t>(needed - bufferStart_, static_cast<std::int64_t>(buffered_));
      std::copy(buffer_.begin() + drop, buffer_.begin() + static_cast<std::ptrdiff_t>(buffered_), buffer_.begin());
      buffered_ -= static_cast<std::size_t>(drop);
      bufferStart_ += drop;
    }
    std::copy(input.begin(), input.begin() + static_cast<std::ptrdiff_t>(piece),
              buffer_.begin() + static_cast<std::ptrdiff_t>(buffered_));
    buffered_ += piece;
    received_ += static_cast<std::int64_t>(piece);
    input = input.subspan(piece);
    // Output n is decided once the input reaches past n * step + halfWidth.
    const double reach = static_cast<double>(received_ - 1) - halfWidth_;
    const auto due = reach < 0.0 ? 0 : static_cast<std::int64_t>(std::floor(reach / step_)) + 1;
    written += emitUpTo(due, output.subspan(written));
  }
  return written;
}

std::size_t SincResampler::finish(std::span<float> output) {
  finished_ = true;
  const auto total = static_cast<std::int64_t>(std::llround(static_cast<double>(received_) / step_));
  return emitUpTo(total, output);
}

std::vector<float> sincResample(std::span<const float> input, double inputRateHz, double outputRateHz) {
  SincResampler resampler(inputRateHz, outputRateHz);
  std::vector<float> output(resampler.maxOutput(input.size()) + resampler.maxOutput(0));
  std::size_t n = resampler.process(input, output);
  n += resampler.finish(std::span<float>(output).subspan(n));
  output.resize(n);
  return output;
}

}  // namespace th::audio
