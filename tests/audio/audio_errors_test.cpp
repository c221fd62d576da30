// Bad recordings: each must be rejected with a th::Error of exactly one line, "PATH: reason", both from disk
// (readAudioFile) and from memory (decodeAudio). Nothing here may crash, hang or come back as audio.
#include <gtest/gtest.h>
#include <sndfile.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "audio_test_files.h"
#include "core/error.h"

namespace {

using th::test::BadInput;

class BadAudioTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    const auto inputs = th::test::makeBadInputs(folder_.path());
    const auto found =
        std::find_if(inputs.begin(), inputs.end(), [&](const BadInput& b) { return b.name == GetParam(); });
    ASSERT_NE(found, inputs.end()) << "no bad input called " << GetParam();
    input_ = *found;
  }

  th::test::TemporaryFolder folder_;
  BadInput input_;
};

// Runs `read`, which must throw th::Error; returns its message ("" if it did not throw).
template <typename Read>
std::string errorMessage(Read read) {
  try {
    const th::audio::AudioClip clip = read();
    ADD_FAILURE() << "accepted as " << clip.samples.size() << " samples at " << clip.sampleRateHz << " Hz";
  } catch (const th::Error& e) {
    return e.what();
  }
  return "";
}

void expectOneLineNaming(const std::string& message, const std::string& name, const std::string& reason) {
  EXPECT_EQ(message.rfind(name + ": ", 0), 0u) << "does not start with the name: " << message;
  EXPECT_NE(message.find(reason), std::string::npos) << "does not say \"" << reason << "\": " << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "more than one line: " << message;
  EXPECT_GT(message.size(), name.size() + 2 + 5) << "no reason given: " << message;
}

TEST_P(BadAudioTest, ReadingTheFileThrowsOneLineNamingPathAndReason) {
  const std::string message = errorMessage([&] { return th::audio::readAudioFile(input_.path); });
  expectOneLineNaming(message, input_.path.string(), input_.reason);
}

// The same inputs less the two that have no bytes (a missing file, a directory), decoded from memory.
class BadAudioBytesTest : public BadAudioTest {};

TEST_P(BadAudioBytesTest, DecodingTheBytesFromMemoryThrowsTheSame) {
  ASSERT_TRUE(input_.hasBytes);
  const std::vector<char> bytes = th::test::readBytes(input_.path);
  const std::string name = "memory:" + input_.name;
  const std::string message = errorMessage([&] { return th::audio::decodeAudio(bytes.data(), bytes.size(), name); });
  expectOneLineNaming(message, name, input_.reason);
}

INSTANTIATE_TEST_SUITE_P(Inputs, BadAudioTest,
                         ::testing::Values("missing", "directory", "text_renamed_wav", "mp3_like", "zero_bytes",
                                           "zero_frames", "truncated", "float_nan", "float_inf", "float_huge",
                                           "rate_2khz", "rate_192khz"),
                         [](const auto& testInfo) { return testInfo.param; });
INSTANTIATE_TEST_SUITE_P(Inputs, BadAudioBytesTest,
                         ::testing::Values("text_renamed_wav", "mp3_like", "zero_bytes", "zero_frames", "truncated",
                                           "float_nan", "float_inf", "float_huge", "rate_2khz", "rate_192khz"),
                         [](const auto& testInfo) { return testInfo.param; });

// The truncated file is a real recording cut in half: the first half decodes fine, so only the header's
// promise of twice as much audio gives it away (libsndfile shrinks the length to fit and mentions it only
// in its log). Reading it as a short recording would be the bug. Every container libsndfile writes, cut.
struct CutCase {
  const char* fileName;
  int format;
};

class TruncatedAudioTest : public ::testing::TestWithParam<CutCase> {};

TEST_P(TruncatedAudioTest, HalfARealRecordingIsNotMistakenForAShortOne) {
  th::test::TemporaryFolder folder;
  const auto arctic = th::test::readArcticPrompt();
  const auto path = folder.path() / GetParam().fileName;
  th::test::writeSoundFile(path, arctic.samples, arctic.sampleRateHz, 1, GetParam().format);
  const std::vector<char> bytes = th::test::readBytes(path);
  ASSERT_NO_THROW(th::audio::decodeAudio(bytes.data(), bytes.size(), "whole"));
  for (size_t keep : {bytes.size() / 2, bytes.size() - 2}) {
    const std::vector<char> cut(bytes.begin(), bytes.begin() + static_cast<long>(keep));
    const std::string message = errorMessage([&] { return th::audio::decodeAudio(cut.data(), cut.size(), "cut"); });
    EXPECT_EQ(message.rfind("cut: truncated", 0), 0u) << keep << " of " << bytes.size() << " bytes: " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(Containers, TruncatedAudioTest,
                         ::testing::Values(CutCase{"pcm16.wav", SF_FORMAT_WAV | SF_FORMAT_PCM_16},
                                           CutCase{"float.wav", SF_FORMAT_WAV | SF_FORMAT_FLOAT},
                                           CutCase{"pcm16.aiff", SF_FORMAT_AIFF | SF_FORMAT_PCM_16},
                                           CutCase{"pcm16.w64", SF_FORMAT_W64 | SF_FORMAT_PCM_16},
                                           CutCase{"pcm16.au", SF_FORMAT_AU | SF_FORMAT_PCM_16},
                                           CutCase{"pcm16.flac", SF_FORMAT_FLAC | SF_FORMAT_PCM_16}),
                         [](const auto& testInfo) {
                           std::string name = testInfo.param.fileName;
                           name[name.find('.')] = '_';
                           return name;
                         });

// Ogg Vorbis cut in half: libsndfile cannot find the final page and reports an unknown length.
TEST(TruncatedAudio, OggWithoutItsFinalPageIsTruncated) {
  th::test::TemporaryFolder folder;
  const auto arctic = th::test::readArcticPrompt();
  const auto path = folder.path() / "speech.ogg";
  th::test::writeSoundFile(path, arctic.samples, arctic.sampleRateHz, 1, SF_FORMAT_OGG | SF_FORMAT_VORBIS);
  std::vector<char> bytes = th::test::readBytes(path);
  bytes.resize(bytes.size() / 2);
  const std::string message = errorMessage([&] { return th::audio::decodeAudio(bytes.data(), bytes.size(), "cut"); });
  EXPECT_EQ(message.rfind("cut: truncated", 0), 0u) << message;
}

// One frame at 48 kHz is a third of a sample at 16 kHz: nothing is left, which must not pass as audio.
// (Found by the fuzzer, which asserts that accepted input is never empty.)
TEST(ShortAudio, FewerSamplesThanOneOutputSampleIsRejected) {
  th::test::TemporaryFolder folder;
  const auto path = folder.path() / "one_frame.wav";
  th::test::writeSoundFile(path, {0.5f}, 48000, 1, SF_FORMAT_WAV | SF_FORMAT_PCM_16);
  const std::string message = errorMessage([&] { return th::audio::readAudioFile(path); });
  expectOneLineNaming(message, path.string(), "too short");
}

// Header quirks that do not lose audio must not be called truncation: the whole recording comes back.
class WavHeaderQuirkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bytes_ = th::test::readBytes(th::test::readArcticPrompt().path);
    // The ARCTIC file is the canonical 44-byte layout: RIFF size at byte 4, data size at byte 40.
    ASSERT_EQ(std::string(bytes_.data() + 36, 4), "data");
    expected_ = th::audio::decodeAudio(bytes_.data(), bytes_.size(), "original").samples;
  }
  void setSize(size_t offset, uint32_t value) {
    for (size_t i = 0; i < 4; ++i) bytes_[offset + i] = static_cast<char>((value >> (8 * i)) & 0xFF);
  }
  void expectWholeRecording() {
    const auto clip = th::audio::decodeAudio(bytes_.data(), bytes_.size(), "quirk");
    EXPECT_EQ(clip.samples, expected_);
  }
  std::vector<char> bytes_;
  std::vector<float> expected_;
};

TEST_F(WavHeaderQuirkTest, RiffSizeCountingItsOwnHeader) {
  setSize(4, static_cast<uint32_t>(bytes_.size()));  // 8 too many: a common writer bug
  expectWholeRecording();
}

TEST_F(WavHeaderQuirkTest, StreamedWavWithPlaceholderSizes) {
  for (uint32_t placeholder : {0xFFFFFFFFu, 0x7FFFFFFFu}) {
    setSize(4, placeholder);
    setSize(40, placeholder);
    expectWholeRecording();
  }
}

TEST_F(WavHeaderQuirkTest, TrailingBytesAfterTheDataChunk) {
  bytes_.insert(bytes_.end(), 100, 'x');
  expectWholeRecording();
}

}  // namespace
