// Reading recordings from disk: WAV, FLAC, OGG (anything libsndfile reads), any rate from 8 to 96 kHz, any
// number of channels, converted to the engine's internal format (16 kHz mono float in [-1, 1]).
//
//   th::audio::AudioClip clip = th::audio::readAudioFile("speech.flac");
//   // clip.samples at clip.sampleRateHz == 16000
//
// Float files can go beyond [-1, 1] and are passed on as they are, up to 120 dB over full scale.
// Bad input throws th::Error with one line "PATH: what is wrong" (missing, not audio, empty, truncated,
// no samples, NaN/inf or absurdly large samples, unsupported rate). Thread contract: no shared state; call
// from any thread.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace th::audio {

inline constexpr int kEngineSampleRateHz = 16000;

struct AudioReadOptions {
  int outputRateHz = kEngineSampleRateHz;  // 0 keeps the file's own rate
  int minInputRateHz = 8000;
  int maxInputRateHz = 96000;
};

struct AudioClip {
  std::vector<float> samples;  // mono, at sampleRateHz
  int sampleRateHz = 0;
  int sourceRateHz = 0;  // what the file had before conversion
  int sourceChannels = 0;
  double durationSeconds() const { return sampleRateHz > 0 ? static_cast<double>(samples.size()) / sampleRateHz : 0.0; }
};

// Reads, validates, downmixes (channel mean) and resamples to options.outputRateHz with libsoxr.
AudioClip readAudioFile(const std::filesystem::path& path, const AudioReadOptions& options = {});

// The same validation and decoding, from bytes in memory (used by the fuzzer; `name` appears in errors).
AudioClip decodeAudio(const void* data, size_t size, const std::string& name, const AudioReadOptions& options = {});

// Writes 16-bit PCM WAV (mono). Used by tests and tools; written to a temporary name, then renamed.
void writeWav16(const std::filesystem::path& path, const std::vector<float>& samples, int sampleRateHz);

}  // namespace th::audio
