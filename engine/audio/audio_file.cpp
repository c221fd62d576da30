#include "audio/audio_file.h"

#include <sndfile.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

#include "audio/resampler.h"
#include "core/error.h"

namespace th::audio {
namespace {

struct SndfileCloser {
  void operator()(SNDFILE* file) const { sf_close(file); }
};
using SndfileHandle = std::unique_ptr<SNDFILE, SndfileCloser>;

// libsndfile's virtual I/O over a byte buffer, so that files and memory share one decoder path.
struct MemoryStream {
  const unsigned char* data;
  sf_count_t size;
  sf_count_t position;
};

sf_count_t memoryLength(void* user) {
  return static_cast<MemoryStream*>(user)->size;
}
sf_count_t memorySeek(sf_count_t offset, int whence, void* user) {
  auto* stream = static_cast<MemoryStream*>(user);
  sf_count_t base = 0;
  if (whence == SEEK_CUR) {
    base = stream->position;
  } else if (whence == SEEK_END) {
    base = stream->size;
  } else if (whence != SEEK_SET) {
    return -1;
  }
  // Offsets come from headers and can be anything (libsndfile skips a chunk by its claimed size): compare
  // before adding, so that a forged size cannot overflow the position.
  if (offset < -base || offset > stream->size - base) return -1;
  stream->position = base + offset;
  return stream->position;
}
sf_count_t memoryRead(void* destination, sf_count_t count, void* user) {
  auto* stream = static_cast<MemoryStream*>(user);
  const sf_count_t available = stream->size - stream->position;
  const sf_count_t taken = count < available ? count : available;
  if (taken > 0) std::memcpy(destination, stream->data + stream->position, static_cast<size_t>(taken));
  stream->position += taken;
  return taken;
}
sf_count_t memoryWrite(const void*, sf_count_t, void*) {
  return 0;
}
sf_count_t memoryTell(void* user) {
  return static_cast<MemoryStream*>(user)->position;
}

// libsndfile reads a WAV, AIFF, AU or W64 file whose audio chunk claims more bytes than the file holds as if
// it were complete: it shrinks the chunk to fit and says so only in its log, as "data : 161040 (should be
// 80498)" ("SSND : ..." in AIFF, "Data Size : ..." in AU; W64 only corrects its outer "riff" size). A cut-off
// download must not pass as a short recording, so those lines count, as do the log's explicit "truncated"
// warnings. Not every "should be" means lost audio: an outer RIFF size 8 bytes too large is a common writer
// bug (the file's size instead of the size after the 8-byte chunk header), a PEAK chunk can be stale, and a
// length of 2^31 - 1 or 2^32 - 1 bytes is the placeholder of a WAV written to a pipe, complete but of
// unknown length.
bool logReportsTruncation(SNDFILE* file) {
  char log[8192] = {};
  sf_command(file, SFC_GET_LOG_INFO, log, sizeof(log));
  constexpr unsigned long long kUnknownLengthPlaceholder = 0x7FFFF000ULL;  // and anything above it
  constexpr unsigned long long kRiffSizeSlackBytes = 8;
  std::istringstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    std::string lower = line;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower.find("truncated") != std::string::npos) return true;

    // "<label> : <claimed> (should be <present>)"
    const size_t colon = line.find(" : ");
    const size_t shouldBe = line.find("(should be ");
    if (colon == std::string::npos || shouldBe == std::string::npos || shouldBe < colon) continue;
    const size_t labelBegin = line.find_first_not_of(' ');
    if (labelBegin >= colon) continue;
    std::string label = line.substr(labelBegin, colon - labelBegin);
    label.erase(label.find_last_not_of(' ') + 1);
    unsigned long long claimedBytes = 0;
    unsigned long long presentBytes = 0;
    if (std::sscanf(line.c_str() + colon + 3, "%llu", &claimedBytes) != 1 ||
        std::sscanf(line.c_str() + shouldBe + 11, "%llu", &presentBytes) != 1) {
      continue;  // e.g. "(should be >= 12)": a malformed header, not a short one
    }
    if (claimedBytes >= kUnknownLengthPlaceholder) continue;
    const bool audioChunk = label == "data" || label == "SSND" || label == "Data Size";
    const bool outerChunk = label == "riff" || label == "FORM";  // W64, AIFF
    if ((audioChunk || outerChunk) && claimedBytes > presentBytes) return true;
    if (label == "RIFF" && claimedBytes > presentBytes + kRiffSizeSlackBytes) return true;
  }
  return false;
}

constexpr float kMaxSampleMagnitude = 1e6f;

AudioClip decodeOpened(SNDFILE* file, const SF_INFO& info, const std::string& name, const AudioReadOptions& options) {
  if (info.channels <= 0) throw Error(name + ": no audio channels");
  if (info.samplerate < options.minInputRateHz || info.samplerate > options.maxInputRateHz) {
    throw Error(name + ": sample rate " + std::to_string(info.samplerate) + " Hz is outside the supported " +
                std::to_string(options.minInputRateHz) + "-" + std::to_string(options.maxInputRateHz) + " Hz");
  }
  if (info.frames <= 0) throw Error(name + ": contains no samples");
  // An Ogg stream whose final page is missing has no known length; libsndfile says so with SF_COUNT_MAX.
  if (info.frames == SF_COUNT_MAX) throw Error(name + ": truncated (the stream's final page is missing)");
  if (logReportsTruncation(file))
    throw Error(name + ": truncated (the header promises more audio than the file holds)");
  // Guard against absurd headers: 24 hours at the maximum rate is far beyond any real use.
  const sf_count_t maxFrames = static_cast<sf_count_t>(options.maxInputRateHz) * 3600 * 24;
  if (info.frames > maxFrames) throw Error(name + ": header claims an implausible length");

  const auto channels = static_cast<size_t>(info.channels);
  std::vector<float> interleaved;
  std::vector<float> mono;
  // Reserve by the header only up to a minute: a header's claim costs nothing to forge (a few bytes of FLAC
  // can promise hours), so the vector grows with what is actually decoded beyond that.
  const sf_count_t maxReservedFrames = static_cast<sf_count_t>(info.samplerate) * 60;
  mono.reserve(static_cast<size_t>(std::min(info.frames, maxReservedFrames)));
  constexpr sf_count_t kBlockFrames = 8192;
  interleaved.resize(static_cast<size_t>(kBlockFrames) * channels);
  sf_count_t total = 0;
  for (;;) {
    const sf_count_t got = sf_readf_float(file, interleaved.data(), kBlockFrames);
    if (got <= 0) break;
    for (sf_count_t f = 0; f < got; ++f) {
      double sum = 0.0;
      for (size_t c = 0; c < channels; ++c) {
        const float value = interleaved[static_cast<size_t>(f) * channels + c];
        if (!std::isfinite(value)) {
          throw Error(name + ": sample " + std::to_string(total + f) + " is not a finite number (NaN or infinity)");
        }
        // Float files may exceed full scale (some even hold 16-bit integer values), but a sample 120 dB over
        // it is corrupt data, and resampling such values overflows to infinity.
        if (std::abs(value) > kMaxSampleMagnitude) {
          char level[32];
          std::snprintf(level, sizeof(level), "%g", static_cast<double>(value));
          throw Error(name + ": sample " + std::to_string(total + f) + " is " + level +
                      ", more than 120 dB above full scale (corrupt data?)");
        }
        sum += static_cast<double>(value);
      }
      mono.push_back(static_cast<float>(sum / static_cast<double>(channels)));
    }
    total += got;
  }
  if (sf_error(file) != SF_ERR_NO_ERROR) throw Error(name + ": read error: " + sf_strerror(file));
  if (total == 0) throw Error(name + ": contains no samples");
  if (total < info.frames) {
    throw Error(name + ": truncated (" + std::to_string(total) + " of " + std::to_string(info.frames) +
                " sample frames could be read)");
  }

  AudioClip clip;
  clip.sourceRateHz = info.samplerate;
  clip.sourceChannels = info.channels;
  clip.sampleRateHz = options.outputRateHz > 0 ? options.outputRateHz : info.samplerate;
  clip.samples =
      info.samplerate == clip.sampleRateHz ? std::move(mono) : resample(mono, info.samplerate, clip.sampleRateHz);
  // A sample or two at a higher rate can round to nothing at the output rate: as empty as no samples at all.
  if (clip.samples.empty()) {
    throw Error(name + ": too short (" + std::to_string(total) + " sample frames at " +
                std::to_string(info.samplerate) + " Hz make no sample at " + std::to_string(clip.sampleRateHz) +
                " Hz)");
  }
  return clip;
}

// The containers we read, by their first bytes. Anything else is refused before libsndfile sees it: given
// unknown bytes, libsndfile may hand them to its MPEG decoder (mpg123), which prints its own warnings on
// stderr and so breaks the one-line error a bad file must get. MP3 input is therefore not supported.
void checkContainer(const unsigned char* head, size_t size, const std::string& name) {
  static constexpr std::array<std::string_view, 9> kMagics = {"RIFF", "RIFX", "RF64", "BW64", "riff",
                                                              "fLaC", "OggS", "FORM", ".snd"};
  const std::string_view start(reinterpret_cast<const char*>(head), std::min<size_t>(size, 4));
  for (std::string_view magic : kMagics) {
    if (start == magic) return;
  }
  if (start == "caff") return;
  throw Error(name +
              ": not a readable audio file (its first bytes are not those of WAV, FLAC, OGG, AIFF, AU, "
              "W64 or CAF)");
}

}  // namespace

AudioClip decodeAudio(const void* data, size_t size, const std::string& name, const AudioReadOptions& options) {
  if (size == 0) throw Error(name + ": empty file (0 bytes)");
  checkContainer(static_cast<const unsigned char*>(data), size, name);
  MemoryStream stream{static_cast<const unsigned char*>(data), static_cast<sf_count_t>(size), 0};
  SF_VIRTUAL_IO io{memoryLength, memorySeek, memoryRead, memoryWrite, memoryTell};
  SF_INFO info{};
  SndfileHandle file(sf_open_virtual(&io, SFM_READ, &info, &stream));
  if (!file) {
    throw Error(name + ": not a readable audio file (libsndfile: " + sf_strerror(nullptr) + ")");
  }
  return decodeOpened(file.get(), info, name, options);
}

AudioClip readAudioFile(const std::filesystem::path& path, const AudioReadOptions& options) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw fileError(path, "no such file");
  if (std::filesystem::is_directory(status)) throw fileError(path, "is a directory, not an audio file");
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw fileError(path, "cannot read: " + error.message());
  if (size == 0) throw fileError(path, "empty file (0 bytes)");
  {
    std::array<unsigned char, 4> head{};
    std::ifstream in(path, std::ios::binary);
    if (!in) throw fileError(path, "cannot be opened for reading");
    in.read(reinterpret_cast<char*>(head.data()), head.size());
    checkContainer(head.data(), static_cast<size_t>(in.gcount()), path.string());
  }

  SF_INFO info{};
  SndfileHandle file(sf_open(path.c_str(), SFM_READ, &info));
  if (!file) {
    throw fileError(path, std::string("not a readable audio file (libsndfile: ") + sf_strerror(nullptr) + ")");
  }
  return decodeOpened(file.get(), info, path.string(), options);
}

void writeWav16(const std::filesystem::path& path, const std::vector<float>& samples, int sampleRateHz) {
  const std::filesystem::path temporary = path.string() + ".partial";
  SF_INFO info{};
  info.samplerate = sampleRateHz;
  info.channels = 1;
  info.format = SF_FORMAT_WAV | SF_FORMAT_PCM_16;
  // libsndfile scales floats by 32767 when it writes 16-bit PCM but by 1/32768 when it reads it, so a read
  // and write round trip through sf_writef_float shrinks the signal and moves samples off their grid.
  // Quantising with the reader's factor (and clipping) here gives 16-bit samples back bit for bit.
  std::vector<short> quantised(samples.size());
  for (size_t n = 0; n < samples.size(); ++n) {
    double scaled = static_cast<double>(samples[n]) * 32768.0;
    if (std::isnan(scaled)) scaled = 0.0;
    quantised[n] = static_cast<short>(std::lround(std::clamp(scaled, -32768.0, 32767.0)));
  }
  {
    SndfileHandle file(sf_open(temporary.c_str(), SFM_WRITE, &info));
    if (!file) throw fileError(path, std::string("cannot write: ") + sf_strerror(nullptr));
    const auto written = sf_writef_short(file.get(), quantised.data(), static_cast<sf_count_t>(quantised.size()));
    if (written != static_cast<sf_count_t>(samples.size())) {
      file.reset();
      std::filesystem::remove(temporary);
      throw fileError(path, "write failed");
    }
  }
  std::filesystem::rename(temporary, path);
}

}  // namespace th::audio
