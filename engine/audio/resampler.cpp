#include "audio/resampler.h"

#include <soxr.h>

#include <cmath>
#include <string>

#include "core/error.h"

namespace th::audio {

void Resampler::SoxrDeleter::operator()(soxr* handle) const {
  soxr_delete(handle);
}

Resampler::Resampler(double inputRateHz, double outputRateHz) : inputRateHz_(inputRateHz), outputRateHz_(outputRateHz) {
  if (!(inputRateHz > 0) || !(outputRateHz > 0)) {
    throw Error("resampler: sample rates must be positive");
  }
  soxr_error_t error = nullptr;
  const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT32_I, SOXR_FLOAT32_I);
  const soxr_quality_spec_t quality = soxr_quality_spec(SOXR_HQ, 0);
  handle_.reset(soxr_create(inputRateHz, outputRateHz, 1, &error, &io, &quality, nullptr));
  if (error != nullptr || !handle_) {
    throw Error(std::string("resampler: soxr_create failed: ") + (error ? error : "unknown error"));
  }
}

Resampler::~Resampler() = default;

void Resampler::drain(const float* input, size_t inputLength, std::vector<float>& output) {
  // Ask for what the ratio predicts plus slack; loop while soxr keeps producing (it buffers internally).
  const size_t expected =
      static_cast<size_t>(std::ceil(static_cast<double>(inputLength) * outputRateHz_ / inputRateHz_)) + 64;
  for (;;) {
    const size_t start = output.size();
    output.resize(start + expected);
    size_t produced = 0;
    size_t consumed = 0;
    const soxr_error_t error =
        soxr_process(handle_.get(), input, inputLength, &consumed, output.data() + start, expected, &produced);
    output.resize(start + produced);
    if (error != nullptr) throw Error(std::string("resampler: ") + error);
    input = input ? input + consumed : nullptr;
    inputLength -= consumed;
    if (produced < expected && inputLength == 0) break;
  }
}

void Resampler::process(std::span<const float> input, std::vector<float>& output) {
  if (input.empty()) return;
  drain(input.data(), input.size(), output);
}

void Resampler::finish(std::vector<float>& output) {
  drain(nullptr, 0, output);
}

std::vector<float> resample(std::span<const float> input, double inputRateHz, double outputRateHz) {
  if (inputRateHz == outputRateHz) return {input.begin(), input.end()};
  Resampler resampler(inputRateHz, outputRateHz);
  std::vector<float> output;
  output.reserve(static_cast<size_t>(static_cast<double>(input.size()) * outputRateHz / inputRateHz) + 256);
  resampler.process(input, output);
  resampler.finish(output);
  // soxr delivers round(n * ratio) samples in total; trim any rounding surplus so lengths are predictable.
  const auto wanted = static_cast<size_t>(std::llround(static_cast<double>(input.size()) * outputRateHz / inputRateHz));
  if (output.size() > wanted) output.resize(wanted);
  return output;
}

}  // namespace th::audio
