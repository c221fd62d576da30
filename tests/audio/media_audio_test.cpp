// Reading the sound of a video with FFmpeg: GRID's MPEG clips come out as 16 kHz mono of the right length and
// level, files libsndfile also reads come out sample for sample the same, and bad files give one-line errors.
#include "audio/media_audio.h"

#include <gtest/gtest.h>
#include <sndfile.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "audio_test_files.h"
#include "core/data_path.h"
#include "core/error.h"

namespace {

using th::audio::AudioClip;
using th::audio::kEngineSampleRateHz;
using th::audio::readAudioFile;
using th::audio::readMediaAudio;

double rms(const std::vector<float>& x) {
  double sum = 0.0;
  for (float v : x) sum += static_cast<double>(v) * v;
  return x.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(x.size()));
}

bool allFinite(const std::vector<float>& x) {
  return std::all_of(x.begin(), x.end(), [](float v) { return std::isfinite(v); });
}

// The message of the th::Error that `read` throws ("" if it returns a clip instead).
template <typename Read>
std::string errorMessage(Read read) {
  try {
    const AudioClip clip = read();
    ADD_FAILURE() << "accepted as " << clip.samples.size() << " samples at " << clip.sampleRateHz << " Hz";
  } catch (const th::Error& e) {
    return e.what();
  }
  return "";
}

void expectOneLineNaming(const std::string& message, const std::filesystem::path& path, const std::string& reason) {
  EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << "does not start with the path: " << message;
  EXPECT_NE(message.find(reason), std::string::npos) << "does not say \"" << reason << "\": " << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "more than one line: " << message;
}

TEST(MediaAudio, GridClipIsThreeSecondsOf16kHzMonoSpeech) {
  const auto path = th::sharedDataPath("grid/s1/bbal7s.mpg");
  const AudioClip clip = readMediaAudio(path);
  std::printf("  %s: %zu samples at %d Hz (source %d Hz, %d channel(s)), %.3f s, RMS %.4f\n", path.filename().c_str(),
              clip.samples.size(), clip.sampleRateHz, clip.sourceRateHz, clip.sourceChannels, clip.durationSeconds(),
              rms(clip.samples));
  EXPECT_EQ(clip.sampleRateHz, kEngineSampleRateHz);
  EXPECT_EQ(clip.sourceRateHz, 44100);
  EXPECT_GE(clip.sourceChannels, 1);
  EXPECT_NEAR(clip.durationSeconds(), 3.0, 0.1);
  EXPECT_TRUE(allFinite(clip.samples));
  // A spoken sentence, not silence (digital silence is 0, a quiet room about 0.001).
  EXPECT_GT(rms(clip.samples), 0.01);
  const float peak = *std::max_element(clip.samples.begin(), clip.samples.end(),
                                       [](float a, float b) { return std::abs(a) < std::abs(b); });
  EXPECT_LE(std::abs(peak), 1.0f);

  // Keeping the source rate: the same length in seconds, at 44.1 kHz.
  th::audio::AudioReadOptions keep;
  keep.outputRateHz = 0;
  const AudioClip native = readMediaAudio(path, keep);
  EXPECT_EQ(native.sampleRateHz, 44100);
  EXPECT_NEAR(native.durationSeconds(), clip.durationSeconds(), 1e-3);
}

// The beat2 recording is 32-bit float WAV at 16 kHz: no resampling, so any difference is in the decoding.
TEST(MediaAudio, FloatWavEqualsLibsndfileSampleForSample) {
  const auto path = th::sharedDataPath("beat2/2_scott_0_1_1.wav");
  const AudioClip viaSndfile = readAudioFile(path);
  const AudioClip viaFfmpeg = readMediaAudio(path);
  ASSERT_EQ(viaFfmpeg.samples.size(), viaSndfile.samples.size());
  EXPECT_EQ(viaFfmpeg.sampleRateHz, viaSndfile.sampleRateHz);
  EXPECT_EQ(viaFfmpeg.sourceRateHz, viaSndfile.sourceRateHz);
  EXPECT_EQ(viaFfmpeg.sourceChannels, viaSndfile.sourceChannels);
  float worst = 0.0f;
  for (size_t n = 0; n < viaSndfile.samples.size(); ++n) {
    worst = std::max(worst, std::abs(viaFfmpeg.samples[n] - viaSndfile.samples[n]));
  }
  std::printf("  %zu samples, largest difference %g\n", viaSndfile.samples.size(), static_cast<double>(worst));
  EXPECT_LE(worst, 1e-4f);
  EXPECT_GT(rms(viaSndfile.samples), 0.001);  // not a comparison of two silences
}

// Synthetic files in the sample formats FFmpeg's decoders hand out (u8, s16, s32, flt, dbl), multichannel
// and at rates that need resampling: both readers mix the same way and share the soxr resampler, so the
// results are equal in length and value.
struct FormatCase {
  const char* fileName;
  int format;
  int sampleRateHz;
  int channels;
};

void PrintTo(const FormatCase& c, std::ostream* out) {
  *out << c.fileName;
}

class MediaAudioAgreement : public ::testing::TestWithParam<FormatCase> {};

TEST_P(MediaAudioAgreement, EqualsLibsndfileAfterDownmixAndResampling) {
  const FormatCase& c = GetParam();
  th::test::TemporaryFolder folder;
  const auto path = folder.path() / c.fileName;
  const size_t frames = static_cast<size_t>(c.sampleRateHz) / 2;  // 0.5 s
  std::vector<float> interleaved(frames * static_cast<size_t>(c.channels));
  for (int ch = 0; ch < c.channels; ++ch) {
    const auto tone = th::test::sine(220.0 * (ch + 1), 0.4, c.sampleRateHz, frames);
    for (size_t n = 0; n < frames; ++n)
      interleaved[n * static_cast<size_t>(c.channels) + static_cast<size_t>(ch)] = tone[n];
  }
  th::test::writeSoundFile(path, interleaved, c.sampleRateHz, c.channels, c.format);

  const AudioClip viaSndfile = readAudioFile(path);
  const AudioClip viaFfmpeg = readMediaAudio(path);
  EXPECT_EQ(viaFfmpeg.sourceRateHz, c.sampleRateHz);
  EXPECT_EQ(viaFfmpeg.sourceChannels, c.channels);
  EXPECT_EQ(viaFfmpeg.sampleRateHz, kEngineSampleRateHz);
  ASSERT_EQ(viaFfmpeg.samples.size(), viaSndfile.samples.size());
  float worst = 0.0f;
  for (size_t n = 0; n < viaSndfile.samples.size(); ++n) {
    worst = std::max(worst, std::abs(viaFfmpeg.samples[n] - viaSndfile.samples[n]));
  }
  EXPECT_LE(worst, 1e-4f) << c.fileName;
  EXPECT_NEAR(rms(viaFfmpeg.samples), 0.4 / std::sqrt(2.0) / std::sqrt(static_cast<double>(c.channels)), 0.02)
      << "mono is the channel mean of tones at different pitches";
}

INSTANTIATE_TEST_SUITE_P(
    Formats, MediaAudioAgreement,
    ::testing::Values(FormatCase{"u8_mono_8k.wav", SF_FORMAT_WAV | SF_FORMAT_PCM_U8, 8000, 1},
                      FormatCase{"s16_stereo_44k.wav", SF_FORMAT_WAV | SF_FORMAT_PCM_16, 44100, 2},
                      FormatCase{"s24_stereo_48k.flac", SF_FORMAT_FLAC | SF_FORMAT_PCM_24, 48000, 2},
                      FormatCase{"s32_3ch_22k.wav", SF_FORMAT_WAV | SF_FORMAT_PCM_32, 22050, 3},
                      FormatCase{"float_stereo_32k.wav", SF_FORMAT_WAV | SF_FORMAT_FLOAT, 32000, 2},
                      FormatCase{"double_mono_96k.wav", SF_FORMAT_WAV | SF_FORMAT_DOUBLE, 96000, 1}),
    [](const auto& testInfo) {
      std::string name = testInfo.param.fileName;
      name[name.find('.')] = '_';
      return name;
    });

TEST(MediaAudio, EveryGridSampleDecodes) {
  std::vector<std::filesystem::path> clips;
  for (const auto& entry : std::filesystem::directory_iterator(th::sharedDataPath("grid/samples"))) {
    if (entry.path().extension() == ".mpg") clips.push_back(entry.path());
  }
  std::sort(clips.begin(), clips.end());
  ASSERT_GE(clips.size(), 10u);
  for (const auto& path : clips) {
    SCOPED_TRACE(path.string());
    AudioClip clip;
    ASSERT_NO_THROW(clip = readMediaAudio(path));
    std::printf("  %-22s %.3f s, source %d Hz x %d, RMS %.4f\n", path.filename().c_str(), clip.durationSeconds(),
                clip.sourceRateHz, clip.sourceChannels, rms(clip.samples));
    EXPECT_EQ(clip.sampleRateHz, kEngineSampleRateHz);
    EXPECT_GE(clip.durationSeconds(), 1.0);
    EXPECT_TRUE(allFinite(clip.samples));
    EXPECT_GT(rms(clip.samples), 0.001);
  }
}

TEST(MediaAudio, MissingFileDirectoryEmptyAndTextAreOneLineErrors) {
  th::test::TemporaryFolder folder;
  const auto missing = folder.path() / "missing.mpg";
  expectOneLineNaming(errorMessage([&] { return readMediaAudio(missing); }), missing, "no such file");
  expectOneLineNaming(errorMessage([&] { return readMediaAudio(folder.path()); }), folder.path(), "directory");

  const auto empty = folder.path() / "empty.mpg";
  std::ofstream(empty).close();
  expectOneLineNaming(errorMessage([&] { return readMediaAudio(empty); }), empty, "empty file");

  const auto text = folder.path() / "notes.mpg";
  std::ofstream(text) << "These are the notes for the recording session, not a video.\nSpeaker 1, take 2.\n";
  expectOneLineNaming(errorMessage([&] { return readMediaAudio(text); }), text, "not a readable media file");
}

// The bad recordings every reader must refuse (made by audio_test_files): FFmpeg reads them its own way, but
// the reasons that do not depend on the decoder (no samples, NaN, infinity, 120 dB over full scale, rate out
// of range) are the same as readAudioFile's. A WAV cut in half and noise behind MP3 sync bytes are an error
// or a clip, never a crash.
TEST(MediaAudio, BadRecordingsAreOneLineErrors) {
  th::test::TemporaryFolder folder;
  for (const th::test::BadInput& bad : th::test::makeBadInputs(folder.path())) {
    SCOPED_TRACE(bad.name);
    if (bad.name == "truncated" || bad.name == "mp3_like") {
      try {
        const AudioClip clip = readMediaAudio(bad.path);
        std::printf("  %-16s a %.3f s clip\n", bad.name.c_str(), clip.durationSeconds());
        EXPECT_TRUE(allFinite(clip.samples));
      } catch (const th::Error& e) {
        std::printf("  %-16s %s\n", bad.name.c_str(), e.what());
        expectOneLineNaming(e.what(), bad.path, "");
      }
      continue;
    }
    const std::string reason = bad.name == "text_renamed_wav" ? "not a readable media file" : bad.reason;
    expectOneLineNaming(errorMessage([&] { return readMediaAudio(bad.path); }), bad.path, reason);
  }
}

// A YUV4MPEG2 stream is a real video container (FFmpeg's y4m demuxer) that cannot hold sound: plain text
// header, then raw frames, so it can be written here without an encoder.
TEST(MediaAudio, VideoWithoutSoundHasNoAudioStream) {
  th::test::TemporaryFolder folder;
  const auto path = folder.path() / "silent_film.y4m";
  {
    std::ofstream out(path, std::ios::binary);
    out << "YUV4MPEG2 W16 H16 F25:1 Ip A1:1 C420jpeg\n";
    const std::string picture(16 * 16 * 3 / 2, '\x80');
    for (int frame = 0; frame < 5; ++frame) out << "FRAME\n" << picture;
  }
  expectOneLineNaming(errorMessage([&] { return readMediaAudio(path); }), path, "has no audio stream");
}

// Cut-off downloads: the first 2 000 bytes, then cuts through the middle and end of the stream. Each must
// give a one-line error or a shorter clip of finite samples; none may crash or hang.
TEST(MediaAudio, TruncatedGridClipIsAnErrorOrAShorterClip) {
  const auto source = th::sharedDataPath("grid/s1/bbal7s.mpg");
  const std::vector<char> bytes = th::test::readBytes(source);
  const double fullSeconds = readMediaAudio(source).durationSeconds();
  th::test::TemporaryFolder folder;
  for (size_t keep : {size_t{2000}, size_t{20000}, bytes.size() / 3, bytes.size() / 2, bytes.size() - 1000}) {
    const auto path = folder.path() / ("cut_" + std::to_string(keep) + ".mpg");
    th::test::writeBytes(path, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(keep)));
    try {
      const AudioClip clip = readMediaAudio(path);
      std::printf("  %zu of %zu bytes: a %.3f s clip\n", keep, bytes.size(), clip.durationSeconds());
      EXPECT_LT(clip.durationSeconds(), fullSeconds) << keep << " bytes";
      EXPECT_TRUE(allFinite(clip.samples)) << keep << " bytes";
    } catch (const th::Error& e) {
      const std::string message = e.what();
      std::printf("  %zu of %zu bytes: %s\n", keep, bytes.size(), message.c_str());
      expectOneLineNaming(message, path, "");
      EXPECT_GT(message.size(), path.string().size() + 8) << "no reason given: " << message;
    }
  }
}

}  // namespace
