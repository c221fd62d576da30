// Writes the fuzzer's seed corpus: short pieces of real recordings in every container and encoding the
// reader meets in practice, so that fuzzing starts from inputs that reach deep into each decoder.
//
//   make_audio_seeds DATA_DIR OUT_DIR
//
// Made at build time from ../shared/data; nothing binary is committed. Plain libsndfile, no engine code, so
// the seeds do not depend on the code under test.
#include <sndfile.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Source {
  std::vector<float> samples;  // mono
  int sampleRateHz = 0;
};

bool readMono(const fs::path& path, double seconds, Source& source) {
  SF_INFO info{};
  SNDFILE* file = sf_open(path.c_str(), SFM_READ, &info);
  if (file == nullptr) return false;
  const auto frames = std::min<sf_count_t>(info.frames, static_cast<sf_count_t>(seconds * info.samplerate));
  std::vector<float> interleaved(static_cast<size_t>(frames * info.channels));
  const sf_count_t got = sf_readf_float(file, interleaved.data(), frames);
  sf_close(file);
  source.sampleRateHz = info.samplerate;
  source.samples.assign(static_cast<size_t>(got), 0.0f);
  for (sf_count_t f = 0; f < got; ++f)
    source.samples[static_cast<size_t>(f)] = interleaved[static_cast<size_t>(f * info.channels)];
  return got > 0;
}

// Writes `source` with `channels` copies (each a little quieter, so the channels differ), at its own rate.
bool write(const fs::path& path, const Source& source, int channels, int format) {
  SF_INFO info{};
  info.samplerate = source.sampleRateHz;
  info.channels = channels;
  info.format = format;
  SNDFILE* file = sf_open(path.c_str(), SFM_WRITE, &info);
  if (file == nullptr) {
    std::fprintf(stderr, "make_audio_seeds: %s: %s\n", path.c_str(), sf_strerror(nullptr));
    return false;
  }
  std::vector<float> interleaved;
  for (float sample : source.samples) {
    for (int c = 0; c < channels; ++c) interleaved.push_back(sample * (1.0f - 0.1f * static_cast<float>(c)));
  }
  const auto frames = static_cast<sf_count_t>(source.samples.size());
  const bool ok = sf_writef_float(file, interleaved.data(), frames) == frames;
  sf_close(file);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: make_audio_seeds DATA_DIR OUT_DIR\n");
    return 2;
  }
  const fs::path data = argv[1];
  const fs::path out = argv[2];
  fs::create_directories(out);
  Source arctic, fda, beat;
  // 24 kHz mono 16-bit; 20 kHz mono 16-bit; 16 kHz mono float.
  if (!readMono(data / "speech/arctic/arctic_a0001.wav", 0.5, arctic) ||
      !readMono(data / "speech/fda-ue/sb001.wav", 0.25, fda) ||
      !readMono(data / "beat2/2_scott_0_1_1.wav", 0.1, beat)) {
    std::fprintf(stderr, "make_audio_seeds: cannot read the recordings under %s\n", data.c_str());
    return 1;
  }
  Source shortArctic = arctic;
  shortArctic.samples.resize(shortArctic.samples.size() / 10);  // 50 ms: small seeds keep the fuzzer fast

  struct Seed {
    const char* name;
    const Source* source;
    int channels;
    int format;
  };
  const Seed seeds[] = {
      {"arctic_pcm16.wav", &arctic, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16},
      {"arctic.flac", &arctic, 1, SF_FORMAT_FLAC | SF_FORMAT_PCM_16},
      {"arctic.ogg", &arctic, 1, SF_FORMAT_OGG | SF_FORMAT_VORBIS},
      {"fda_stereo_pcm16.wav", &fda, 2, SF_FORMAT_WAV | SF_FORMAT_PCM_16},
      {"beat_float.wav", &beat, 1, SF_FORMAT_WAV | SF_FORMAT_FLOAT},
      {"short_6ch_pcm24.wav", &shortArctic, 6, SF_FORMAT_WAVEX | SF_FORMAT_PCM_24},
      {"short_u8.wav", &shortArctic, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_U8},
      {"short_ulaw.wav", &shortArctic, 1, SF_FORMAT_WAV | SF_FORMAT_ULAW},
      {"short_imaadpcm.wav", &shortArctic, 1, SF_FORMAT_WAV | SF_FORMAT_IMA_ADPCM},
      {"short_stereo.flac", &shortArctic, 2, SF_FORMAT_FLAC | SF_FORMAT_PCM_24},
      {"short.aiff", &shortArctic, 1, SF_FORMAT_AIFF | SF_FORMAT_PCM_16},
      {"short.au", &shortArctic, 1, SF_FORMAT_AU | SF_FORMAT_PCM_16},
      {"short.w64", &shortArctic, 1, SF_FORMAT_W64 | SF_FORMAT_PCM_16},
      {"short.caf", &shortArctic, 1, SF_FORMAT_CAF | SF_FORMAT_PCM_16},
      {"short_double.wav", &shortArctic, 1, SF_FORMAT_WAV | SF_FORMAT_DOUBLE},
  };
  int failures = 0;
  for (const Seed& seed : seeds) failures += write(out / seed.name, *seed.source, seed.channels, seed.format) ? 0 : 1;
  return failures == 0 ? 0 : 1;
}
