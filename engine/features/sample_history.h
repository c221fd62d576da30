// The tail of an audio stream that a frame-based stage still needs, addressed by absolute sample index.
//
//   th::features::SampleHistory history;
//   history.append(chunk);
//   history.copy(frameStart, window);          // samples before 0 or past the end read as 0 (zero padding)
//   history.forgetBefore(oldestStillNeeded);   // memory stays bounded on endless streams
//
// Thread contract: one thread per instance.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

namespace th::features {

class SampleHistory {
 public:
  void append(std::span<const float> samples) {
    samples_.insert(samples_.end(), samples.begin(), samples.end());
    size_ += static_cast<long long>(samples.size());
  }

  // Samples received so far (including those forgotten).
  long long size() const { return size_; }

  // Fills `out` with samples [start, start + out.size()), zeros outside [0, size()).
  void copy(long long start, std::span<float> out) const {
    const long long length = static_cast<long long>(out.size());
    if (start >= offset_ && start + length <= size_) {
      std::copy_n(samples_.begin() + (start - offset_), length, out.begin());
      return;
    }
    for (long long n = 0; n < length; ++n) {
      const long long index = start + n;
      out[static_cast<size_t>(n)] = index >= 0 && index < size_ ? samples_[static_cast<size_t>(index - offset_)] : 0.0f;
    }
  }

  // Drops samples before `index` once enough have piled up (so the cost is amortised).
  void forgetBefore(long long index) {
    const long long removable = std::min(index - offset_, static_cast<long long>(samples_.size()));
    if (removable > kMinimumToForget) {
      samples_.erase(samples_.begin(), samples_.begin() + removable);
      offset_ += removable;
    }
  }

 private:
  static constexpr long long kMinimumToForget = 8192;
  std::vector<float> samples_;
  long long offset_ = 0;  // stream index of samples_[0]
  long long size_ = 0;
};

}  // namespace th::features
