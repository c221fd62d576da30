// Audio files made at test time (never committed): good files in any libsndfile format, rate and channel
// count, and the bad inputs every reader of recordings must reject with one line naming the file.
//
//   th::test::TemporaryFolder folder;
//   th::test::writeSoundFile(folder.path() / "a.flac", samples, 44100, 2, SF_FORMAT_FLAC | SF_FORMAT_PCM_16);
//   for (const th::test::BadInput& bad : th::test::makeBadInputs(folder.path())) { ... bad.path, bad.reason
//   ... }
//
// Shared by the engine's audio tests and the CLI tests. Thread contract: none needed (test set-up only).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/temporary_file.h"

namespace th::test {

// The engine's temporary folder (removed with everything in it on destruction).
using TemporaryFolder = th::TemporaryFolder;

// Writes interleaved float samples with libsndfile; `format` is SF_FORMAT_* (container | encoding).
// Throws std::runtime_error if libsndfile refuses.
void writeSoundFile(const std::filesystem::path& path, const std::vector<float>& interleaved, int sampleRateHz,
                    int channels, int format);

// A real recording as libsndfile decodes it (no resampling): the CMU ARCTIC prompt, 24 kHz mono 16-bit.
struct RawRecording {
  std::filesystem::path path;
  std::vector<float> samples;
  int sampleRateHz = 0;
};
RawRecording readArcticPrompt();

std::vector<char> readBytes(const std::filesystem::path& path);
void writeBytes(const std::filesystem::path& path, const std::vector<char>& bytes);

// sin(2 pi f t) sampled at rate, `amplitude` peak, starting at phase 0 at sample 0.
std::vector<float> sine(double frequencyHz, double amplitude, int sampleRateHz, size_t numSamples);

// One bad input: where it is, whether it is a file whose bytes can also be decoded from memory, and a piece
// of text the error message must contain (the reason).
struct BadInput {
  std::string name;  // a short identifier, usable as a test name
  std::filesystem::path path;
  bool hasBytes = true;  // false for a missing file and a directory
  std::string reason;
};
std::vector<BadInput> makeBadInputs(const std::filesystem::path& folder);

}  // namespace th::test
