// libFuzzer target: arbitrary bytes through the same decoder that reads recordings from disk.
//
//   scripts/fuzz.sh                       # builds build-fuzz/ with clang and runs this for FUZZ_SECONDS
//
// Rejecting input with th::Error is the expected outcome for nearly every input; anything else that escapes
// (std::bad_alloc from a forged length, a crash, an ASan/UBSan report, a hang) is a finding. Accepted input
// must look like what the engine was promised: 16 kHz mono, finite samples.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "audio/audio_file.h"
#include "core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const th::audio::AudioClip clip = th::audio::decodeAudio(data, size, "fuzz-input");
    if (clip.sampleRateHz != th::audio::kEngineSampleRateHz || clip.samples.empty()) __builtin_trap();
    for (float sample : clip.samples) {
      if (!std::isfinite(sample)) __builtin_trap();
    }
  } catch (const th::Error&) {
    // A clean rejection.
  }
  return 0;
}
