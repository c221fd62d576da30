// libFuzzer target: arbitrary bytes through th::formats::readAnimation, as each of its three formats.
//
//   CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DTALKINGHEAD_FUZZ=ON -DTALKINGHEAD_WERROR=OFF
//   ninja -C build-fuzz animation_file_fuzzer && build-fuzz/fuzz/animation_file_fuzzer CORPUS -max_len=16384
//
// The first byte picks the format (its value mod 3: .csv, .json, .fap) and the rest is the file, written to a
// temporary folder because the reader takes a path. Rejecting input with th::Error is the expected outcome
// for nearly every input; anything else that escapes, a crash, an ASan/UBSan report or a hang is a finding.
// An accepted animation must also write back in its own format and read back the same: the same FAPs, values
// and frame rate (from CSV, which derives the rate from rounded times again, the same within the spacing
// tolerance).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/temporary_file.h"
#include "formats/animation_format.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const th::TemporaryFolder folder;
  static const char* const kExtensions[] = {".csv", ".json", ".fap"};
  const std::string extension = kExtensions[data[0] % 3];
  const auto input = folder.path() / ("input" + extension);
  {
    std::ofstream out(input, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  th::face::FapTrack animation;
  try {
    animation = th::formats::readAnimation(input);
  } catch (const th::Error&) {
    return 0;  // a clean rejection
  }
  try {
    const auto output = folder.path() / ("output" + extension);
    th::formats::writeAnimation(output, animation);
    const th::face::FapTrack again = th::formats::readAnimation(output);
    const bool sameShape = again.faps == animation.faps && again.values.rows() == animation.values.rows() &&
                           again.values.cols() == animation.values.cols();
    if (!sameShape || again.values != animation.values) __builtin_trap();
    const double rateChange = std::abs(again.framesPerSecond - animation.framesPerSecond);
    if (extension == ".csv" ? !(rateChange <= 1e-4 * animation.framesPerSecond) : rateChange != 0) {
      __builtin_trap();
    }
  } catch (const th::Error&) {
    __builtin_trap();  // the writer refused, or the reader its output: they disagree on what is valid
  }
  return 0;
}
