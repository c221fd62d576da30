// A 16-bit PCM WAV file's samples as floats, for the library's tests that link only libtalkinghead (the engine's
// readers are inside it, not exported). Empty for anything else.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace th::test {

inline std::vector<float> readWavSamples(const std::string& path, double& rateHz) {
  std::ifstream file(path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  std::vector<float> samples;
  if (bytes.size() < 12 || std::memcmp(bytes.data(), "RIFF", 4) != 0) return samples;
  for (std::size_t at = 12; at + 8 <= bytes.size();) {
    const std::uint32_t size = u32(at + 4);
    if (std::memcmp(bytes.data() + at, "fmt ", 4) == 0) rateHz = u32(at + 12);
    if (std::memcmp(bytes.data() + at, "data", 4) == 0) {
      const std::size_t count = std::min<std::size_t>(size, bytes.size() - at - 8) / 2;
      for (std::size_t i = 0; i < count; ++i) {
        std::int16_t v = 0;
        std::memcpy(&v, bytes.data() + at + 8 + 2 * i, 2);
        samples.push_back(static_cast<float>(v) / 32768.0f);
      }
      return samples;
    }
    at += 8 + size + (size & 1);
  }
  return samples;
}

}  // namespace th::test
