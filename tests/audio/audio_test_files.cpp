#include "audio_test_files.h"

#include <sndfile.h>
#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "core/data_path.h"

namespace th::test {
namespace fs = std::filesystem;

namespace {
struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};
using SndfileHandle = std::unique_ptr<SNDFILE, SndfileCloser>;
}  // namespace

void writeSoundFile(const fs::path& path, const std::vector<float>& interleaved, int sampleRateHz, int channels,
                    int format) {
  SF_INFO info{};
  info.samplerate = sampleRateHz;
  info.channels = channels;
  info.format = format;
  SndfileHandle file(sf_open(path.c_str(), SFM_WRITE, &info));
  if (!file) throw std::runtime_error(path.string() + ": libsndfile cannot write: " + sf_strerror(nullptr));
  const auto frames = static_cast<sf_count_t>(interleaved.size() / static_cast<size_t>(channels));
  if (frames == 0) return;
  sf_count_t written = 0;
  if ((format & SF_FORMAT_SUBMASK) == SF_FORMAT_PCM_16) {
    // libsndfile writes floats to 16-bit PCM scaled by 32767 but reads them back scaled by 1/32768;
    // quantising with the reader's factor ourselves makes 16-bit samples survive a round trip bit for bit.
    std::vector<short> quantised(interleaved.size());
    for (size_t n = 0; n < interleaved.size(); ++n) {
      quantised[n] = static_cast<short>(std::lround(std::clamp(interleaved[n] * 32768.0, -32768.0, 32767.0)));
    }
    written = sf_writef_short(file.get(), quantised.data(), frames);
  } else {
    written = sf_writef_float(file.get(), interleaved.data(), frames);
  }
  if (written != frames) throw std::runtime_error(path.string() + ": short write: " + sf_strerror(file.get()));
}

RawRecording readArcticPrompt() {
  RawRecording recording;
  recording.path = sharedDataPath("speech/arctic/arctic_a0001.wav");
  SF_INFO info{};
  SndfileHandle file(sf_open(recording.path.c_str(), SFM_READ, &info));
  if (!file || info.channels != 1) throw std::runtime_error(recording.path.string() + ": cannot read as mono");
  recording.sampleRateHz = info.samplerate;
  recording.samples.resize(static_cast<size_t>(info.frames));
  if (sf_readf_float(file.get(), recording.samples.data(), info.frames) != info.frames) {
    throw std::runtime_error(recording.path.string() + ": short read");
  }
  return recording;
}

std::vector<char> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

std::vector<float> sine(double frequencyHz, double amplitude, int sampleRateHz, size_t numSamples) {
  std::vector<float> samples(numSamples);
  for (size_t n = 0; n < numSamples; ++n) {
    samples[n] = static_cast<float>(
        amplitude * std::sin(2.0 * std::numbers::pi * frequencyHz * static_cast<double>(n) / sampleRateHz));
  }
  return samples;
}

std::vector<BadInput> makeBadInputs(const fs::path& folder) {
  std::vector<BadInput> inputs;
  inputs.push_back({"missing", folder / "missing.wav", false, "no such file"});

  inputs.push_back({"directory", folder / "folder.wav", false, "is a directory"});
  fs::create_directory(inputs.back().path);

  inputs.push_back({"text_renamed_wav", folder / "notes.wav", true, "not a readable audio file"});
  const std::string text = "These are my notes, not a recording.\n";
  writeBytes(inputs.back().path, std::vector<char>(text.begin(), text.end()));

  // MPEG-looking bytes: libsndfile would hand them to mpg123, which writes warnings of its own to stderr.
  inputs.push_back({"mp3_like", folder / "song.wav", true, "not a readable audio file"});
  {
    std::vector<char> bytes = {'I', 'D', '3', 3, 0, 0, 0, 0, 0, 0};
    for (int frame = 0; frame < 64; ++frame) {
      bytes.push_back(static_cast<char>(0xFF));
      bytes.push_back(static_cast<char>(0xFB));
      for (int n = 0; n < 100; ++n) bytes.push_back(static_cast<char>((frame * 31 + n * 17) & 0xFF));
    }
    writeBytes(inputs.back().path, bytes);
  }

  inputs.push_back({"zero_bytes", folder / "empty.wav", true, "empty file (0 bytes)"});
  writeBytes(inputs.back().path, {});

  // A valid 44-byte header whose data chunk is empty: libsndfile opens it and reports 0 frames.
  inputs.push_back({"zero_frames", folder / "zero_frames.wav", true, "contains no samples"});
  writeSoundFile(inputs.back().path, {}, 16000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16);

  // A real recording cut in half, header unchanged: what an interrupted copy or download leaves.
  inputs.push_back({"truncated", folder / "truncated.wav", true, "truncated"});
  {
    std::vector<char> bytes = readBytes(readArcticPrompt().path);
    bytes.resize(bytes.size() / 2);
    writeBytes(inputs.back().path, bytes);
  }

  std::vector<float> speechLike = sine(220.0, 0.5, 16000, 16000);
  inputs.push_back({"float_nan", folder / "nan.wav", true, "not a finite number"});
  speechLike[8000] = std::numeric_limits<float>::quiet_NaN();
  writeSoundFile(inputs.back().path, speechLike, 16000, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT);

  inputs.push_back({"float_inf", folder / "inf.wav", true, "not a finite number"});
  speechLike[8000] = std::numeric_limits<float>::infinity();
  writeSoundFile(inputs.back().path, speechLike, 16000, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT);

  // Finite but absurd: 3e38 is a valid float, 650 dB above full scale; resampled, it overflows to infinity.
  inputs.push_back({"float_huge", folder / "huge.wav", true, "above full scale"});
  speechLike[8000] = 3e38f;
  writeSoundFile(inputs.back().path, speechLike, 44100, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT);

  inputs.push_back({"rate_2khz", folder / "rate_2000.wav", true, "sample rate 2000 Hz"});
  writeSoundFile(inputs.back().path, sine(220.0, 0.5, 2000, 2000), 2000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16);

  inputs.push_back({"rate_192khz", folder / "rate_192000.wav", true, "sample rate 192000 Hz"});
  writeSoundFile(inputs.back().path, sine(220.0, 0.5, 192000, 19200), 192000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16);
  return inputs;
}

}  // namespace th::test
