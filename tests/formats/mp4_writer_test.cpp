// MP4 export: files read back with FFmpeg's own demuxer and decoders have H.264 (High, yuv420p) video and AAC
// audio that both start at 0 and end together when ceil(seconds * fps) frames are written, frames in order,
// the sound at the right time (AAC priming skipped), the colours converted as tagged (BT.709 for HD, BT.601
// below, limited range); unequal lengths, tiny files and bottom-up frames work; nothing is left behind by an
// unfinished writer, a killed process or a failed start, an old target survives until success, and bad use
// gives one-line errors naming the target.
#include "formats/mp4_writer.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/pixdesc.h>
}

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/ffmpeg_support.h"
#include "core/temporary_file.h"
#include "support/files.h"

namespace th::formats {
namespace {

using th::test::expectFileError;
using th::test::listFolder;
using th::test::readText;

namespace fs = std::filesystem;

const int kEndOfFile = AVERROR_EOF;
const int kTryAgain = AVERROR(EAGAIN);
const std::int64_t kNoTimestamp = AV_NOPTS_VALUE;

// The MP4 file's top-level boxes, in order.
std::vector<std::string> topLevelBoxes(const fs::path& path) {
  const std::string bytes = readText(path);
  std::vector<std::string> boxes;
  std::size_t at = 0;
  while (at + 8 <= bytes.size()) {
    std::uint64_t size = 0;
    for (std::size_t i = 0; i < 4; ++i) size = size << 8 | static_cast<unsigned char>(bytes[at + i]);
    boxes.push_back(bytes.substr(at + 4, 4));
    if (size == 1 && at + 16 <= bytes.size()) {  // 64-bit size
      size = 0;
      for (std::size_t i = 8; i < 16; ++i) size = size << 8 | static_cast<unsigned char>(bytes[at + i]);
    }
    if (size < 8) break;
    at += size;
  }
  return boxes;
}

// ---- synthetic input ----

// An RGB24 frame whose every pixel is `value` (grey) — frame f of a clip gets its own grey to check order.
std::vector<std::uint8_t> greyFrame(int width, int height, std::uint8_t value) {
  return std::vector<std::uint8_t>(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3, value);
}

std::uint8_t greyOf(int frame) {
  return static_cast<std::uint8_t>(40 + (frame * 23) % 180);
}

// Silence with a 1 kHz tone burst from onsetSeconds on (to find where the sound lands in the file).
std::vector<float> toneAfter(double seconds, double onsetSeconds, int rateHz) {
  const auto count = static_cast<std::size_t>(std::llround(seconds * rateHz));
  std::vector<float> samples(count, 0.0F);
  for (std::size_t n = 0; n < count; ++n) {
    const double t = static_cast<double>(n) / rateHz;
    if (t >= onsetSeconds) samples[n] = static_cast<float>(0.5 * std::sin(2.0 * std::numbers::pi * 1000.0 * t));
  }
  return samples;
}

// ---- reading a file back ----

struct FormatCloser {
  void operator()(AVFormatContext* context) const { avformat_close_input(&context); }
};

struct StreamInfo {
  bool present = false;
  AVCodecID codec = AV_CODEC_ID_NONE;
  int width = 0;
  int height = 0;
  int format = -1;  // pixel or sample format
  int profile = -1;
  int sampleRateHz = 0;
  int channels = 0;
  AVColorRange range = AVCOL_RANGE_UNSPECIFIED;
  AVColorSpace matrix = AVCOL_SPC_UNSPECIFIED;
  AVColorPrimaries primaries = AVCOL_PRI_UNSPECIFIED;
  AVColorTransferCharacteristic transfer = AVCOL_TRC_UNSPECIFIED;
  double startSeconds = -1.0;
  double durationSeconds = -1.0;
  int packets = 0;
  double firstPacketPtsSeconds = 0.0;
};

struct DecodedFile {
  StreamInfo video;
  StreamInfo audio;
  double durationSeconds = 0.0;
  std::vector<double> frameTimes;               // decoded frames' timestamps, in display order
  std::vector<std::vector<std::uint8_t>> luma;  // Y plane of each decoded frame (width x height, packed)
  std::vector<std::vector<std::uint8_t>> chromaU;
  std::vector<std::vector<std::uint8_t>> chromaV;
  std::vector<float> audioSamples;  // decoded, priming skipped as the file declares it
  double firstAudioFrameSeconds = -1.0;
};

void describe(const AVStream& stream, StreamInfo& info) {
  const AVCodecParameters& par = *stream.codecpar;
  info.present = true;
  info.codec = par.codec_id;
  info.width = par.width;
  info.height = par.height;
  info.format = par.format;
  info.profile = par.profile;
  info.sampleRateHz = par.sample_rate;
  info.channels = par.ch_layout.nb_channels;
  info.range = par.color_range;
  info.matrix = par.color_space;
  info.primaries = par.color_primaries;
  info.transfer = par.color_trc;
  info.startSeconds =
      stream.start_time == kNoTimestamp ? -1.0 : static_cast<double>(stream.start_time) * av_q2d(stream.time_base);
  info.durationSeconds =
      stream.duration == kNoTimestamp ? -1.0 : static_cast<double>(stream.duration) * av_q2d(stream.time_base);
}

class Decoder {
 public:
  Decoder(const AVStream& stream) {
    const AVCodec* decoder = avcodec_find_decoder(stream.codecpar->codec_id);
    if (decoder == nullptr) throw Error("no decoder");
    codec_.reset(avcodec_alloc_context3(decoder));
    avcodec_parameters_to_context(codec_.get(), stream.codecpar);
    codec_->pkt_timebase = stream.time_base;
    if (avcodec_open2(codec_.get(), decoder, nullptr) < 0) throw Error("cannot open decoder");
    frame_.reset(av_frame_alloc());
  }
  // Sends a packet (nullptr: flush) and hands every frame that comes out to `take`.
  void decode(const AVPacket* packet, const std::function<void(const AVFrame&)>& take) {
    if (avcodec_send_packet(codec_.get(), packet) < 0) throw Error("decoding failed");
    for (;;) {
      const int result = avcodec_receive_frame(codec_.get(), frame_.get());
      if (result == kTryAgain || result == kEndOfFile) return;
      if (result < 0) throw Error("decoding failed");
      take(*frame_);
      av_frame_unref(frame_.get());
    }
  }

 private:
  ffmpeg::CodecHandle codec_;
  ffmpeg::FrameHandle frame_;
};

DecodedFile readBack(const fs::path& path) {
  DecodedFile file;
  AVFormatContext* raw = nullptr;
  if (avformat_open_input(&raw, path.c_str(), nullptr, nullptr) < 0) throw Error("cannot open " + path.string());
  std::unique_ptr<AVFormatContext, FormatCloser> format(raw);
  if (avformat_find_stream_info(format.get(), nullptr) < 0) throw Error("no stream info");
  file.durationSeconds = static_cast<double>(format->duration) / AV_TIME_BASE;
  int videoIndex = -1;
  int audioIndex = -1;
  for (unsigned s = 0; s < format->nb_streams; ++s) {
    const AVStream& stream = *format->streams[s];
    if (stream.codecpar->codec_type == AVMEDIA_TYPE_VIDEO) {
      videoIndex = static_cast<int>(s);
      describe(stream, file.video);
    } else if (stream.codecpar->codec_type == AVMEDIA_TYPE_AUDIO) {
      audioIndex = static_cast<int>(s);
      describe(stream, file.audio);
    }
  }
  if (videoIndex < 0 || audioIndex < 0) return file;
  const AVStream& videoStream = *format->streams[videoIndex];
  const AVStream& audioStream = *format->streams[audioIndex];
  Decoder video(videoStream);
  Decoder audio(audioStream);
  const auto takePicture = [&](const AVFrame& frame) {
    file.frameTimes.push_back(static_cast<double>(frame.best_effort_timestamp) * av_q2d(videoStream.time_base));
    const auto plane = [&](int index, int width, int height) {
      std::vector<std::uint8_t> pixels;
      for (int y = 0; y < height; ++y) {
        const std::uint8_t* row = frame.data[index] + static_cast<std::ptrdiff_t>(y) * frame.linesize[index];
        pixels.insert(pixels.end(), row, row + width);
      }
      return pixels;
    };
    file.luma.push_back(plane(0, frame.width, frame.height));
    file.chromaU.push_back(plane(1, frame.width / 2, frame.height / 2));
    file.chromaV.push_back(plane(2, frame.width / 2, frame.height / 2));
  };
  const auto takeSound = [&](const AVFrame& frame) {
    if (file.firstAudioFrameSeconds < 0.0)
      file.firstAudioFrameSeconds = static_cast<double>(frame.best_effort_timestamp) * av_q2d(audioStream.time_base);
    const auto* samples = reinterpret_cast<const float*>(frame.extended_data[0]);  // fltp mono
    file.audioSamples.insert(file.audioSamples.end(), samples, samples + frame.nb_samples);
  };
  ffmpeg::PacketHandle packet(av_packet_alloc());
  while (av_read_frame(format.get(), packet.get()) >= 0) {
    if (packet->stream_index == videoIndex) {
      StreamInfo& info = file.video;
      if (info.packets++ == 0)
        info.firstPacketPtsSeconds = static_cast<double>(packet->pts) * av_q2d(videoStream.time_base);
      video.decode(packet.get(), takePicture);
    } else if (packet->stream_index == audioIndex) {
      StreamInfo& info = file.audio;
      if (info.packets++ == 0)
        info.firstPacketPtsSeconds = static_cast<double>(packet->pts) * av_q2d(audioStream.time_base);
      audio.decode(packet.get(), takeSound);
    }
    av_packet_unref(packet.get());
  }
  video.decode(nullptr, takePicture);
  audio.decode(nullptr, takeSound);
  return file;
}

double mean(const std::vector<std::uint8_t>& values) {
  double sum = 0.0;
  for (const std::uint8_t v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

// Index of the first sample whose magnitude reaches `level`, or -1.
long firstLoudSample(const std::vector<float>& samples, float level) {
  for (std::size_t n = 0; n < samples.size(); ++n) {
    if (std::abs(samples[n]) >= level) return static_cast<long>(n);
  }
  return -1;
}

Mp4Options smallOptions() {
  Mp4Options options;
  options.width = 160;
  options.height = 120;
  options.threads = 2;
  return options;
}

// Writes `frames` grey frames (frame f is greyOf(f)) and `audio`, with audio and video interleaved in chunks.
void writeClip(const fs::path& path, const Mp4Options& options, int frames, const std::vector<float>& audio) {
  Mp4Writer writer(path, options);
  const std::size_t chunk = audio.size() / static_cast<std::size_t>(std::max(frames, 1)) + 1;
  std::size_t given = 0;
  for (int f = 0; f < frames; ++f) {
    const std::vector<std::uint8_t> rgb = greyFrame(options.width, options.height, greyOf(f));
    writer.addVideoFrame(rgb.data(), options.width * 3);
    const std::size_t count = std::min(chunk, audio.size() - given);
    writer.addAudio(std::span<const float>(audio).subspan(given, count));
    given += count;
  }
  writer.addAudio(std::span<const float>(audio).subspan(given));
  EXPECT_EQ(writer.framesWritten(), frames);
  writer.finish();
}

// ---- the file ----

TEST(Mp4Writer, WritesH264AndAacThatStartTogetherAndEndTogether) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "talk.mp4";
  const Mp4Options options = smallOptions();
  const double seconds = 1.234;
  const std::vector<float> audio = toneAfter(seconds, 0.5, options.audioSampleRateHz);
  const auto frames = static_cast<int>(videoFramesFor(audio.size(), options.audioSampleRateHz, 30.0));
  ASSERT_EQ(frames, 38);  // ceil(1.234 * 30)
  writeClip(path, options, frames, audio);
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"talk.mp4"});                  // no temporary file left
  EXPECT_EQ(topLevelBoxes(path), (std::vector<std::string>{"ftyp", "moov", "free", "mdat"}));  // faststart

  const DecodedFile file = readBack(path);
  ASSERT_TRUE(file.video.present);
  ASSERT_TRUE(file.audio.present);
  EXPECT_EQ(file.video.codec, AV_CODEC_ID_H264);
  EXPECT_EQ(file.video.width, 160);
  EXPECT_EQ(file.video.height, 120);
  EXPECT_EQ(file.video.format, AV_PIX_FMT_YUV420P);
  EXPECT_EQ(file.video.profile, FF_PROFILE_H264_HIGH);
  EXPECT_EQ(file.audio.codec, AV_CODEC_ID_AAC);
  EXPECT_EQ(file.audio.sampleRateHz, 48000);
  EXPECT_EQ(file.audio.channels, 1);

  // Both start at 0; the video lasts its frames, the audio (padded to it) as long, within one frame.
  const double frame = 1.0 / 30.0;
  EXPECT_NEAR(file.video.startSeconds, 0.0, 1e-9);
  EXPECT_NEAR(file.audio.startSeconds, 0.0, 1e-9);
  EXPECT_NEAR(file.video.durationSeconds, frames * frame, 1e-6);
  EXPECT_NEAR(file.audio.durationSeconds, file.video.durationSeconds, frame);
  EXPECT_NEAR(file.audio.durationSeconds, file.video.durationSeconds, 1.0 / 48000 + 1e-9);
  EXPECT_GE(file.audio.durationSeconds, seconds);
  EXPECT_NEAR(file.durationSeconds, frames * frame, 0.01);

  // Every frame, in order, at its time.
  EXPECT_EQ(file.video.packets, frames);
  ASSERT_EQ(static_cast<int>(file.luma.size()), frames);
  for (int f = 0; f < frames; ++f) {
    EXPECT_NEAR(file.frameTimes[static_cast<std::size_t>(f)], f * frame, 1e-6) << "frame " << f;
    // Grey g in full range is 16 + g * 219 / 255 in limited range.
    EXPECT_NEAR(mean(file.luma[static_cast<std::size_t>(f)]), 16.0 + greyOf(f) * 219.0 / 255.0, 1.5) << "frame " << f;
  }

  // The sound: the tone starts 0.5 s into the decoded audio (the 1024 priming samples are skipped), and the
  // decoded audio is as long as the stream says.
  // The AAC encoder's 1024 priming samples are in the file, before 0 (the edit list skips them).
  EXPECT_NEAR(file.audio.firstPacketPtsSeconds, -1024.0 / 48000, 1e-9);
  EXPECT_NEAR(file.firstAudioFrameSeconds, 0.0, 1e-9);
  const long onset = firstLoudSample(file.audioSamples, 0.1F);
  ASSERT_GE(onset, 0);
  EXPECT_NEAR(static_cast<double>(onset) / 48000.0, 0.5, 0.001);
  EXPECT_NEAR(static_cast<double>(file.audioSamples.size()) / 48000.0, file.audio.durationSeconds, 1024.0 / 48000);
}

// Pure colours decode to the values the tagged matrix gives: Y of red is 63 with BT.709, 81 with BT.601.
void checkColours(int width, int height, AVColorSpace matrix, double redLuma) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "colours.mp4";
  Mp4Options options = smallOptions();
  options.width = width;
  options.height = height;
  // Three vertical bands: white, black, red.
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* pixel =
          &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3];
      const int band = x * 3 / width;
      pixel[0] = band == 1 ? 0 : 255;
      pixel[1] = band == 0 ? 255 : 0;
      pixel[2] = band == 0 ? 255 : 0;
    }
  }
  {
    Mp4Writer writer(path, options);
    writer.addVideoFrame(rgb.data(), width * 3);
    writer.addVideoFrame(rgb.data(), width * 3);
    writer.finish();
  }
  const DecodedFile file = readBack(path);
  EXPECT_EQ(file.video.range, AVCOL_RANGE_MPEG);
  EXPECT_EQ(file.video.matrix, matrix);
  EXPECT_EQ(file.video.primaries, AVCOL_PRI_BT709);
  EXPECT_EQ(file.video.transfer, AVCOL_TRC_BT709);
  ASSERT_EQ(file.luma.size(), 2u);
  const auto at = [&](const std::vector<std::uint8_t>& plane, int planeWidth, int x, int y) {
    return static_cast<double>(
        plane[static_cast<std::size_t>(y) * static_cast<std::size_t>(planeWidth) + static_cast<std::size_t>(x)]);
  };
  const int y = height / 2;
  EXPECT_NEAR(at(file.luma[0], width, width / 6, y), 235.0, 2.0) << "white";
  EXPECT_NEAR(at(file.luma[0], width, width / 2, y), 16.0, 2.0) << "black";
  EXPECT_NEAR(at(file.luma[0], width, width * 5 / 6, y), redLuma, 2.0) << "red";
  EXPECT_NEAR(at(file.chromaV[0], width / 2, width * 5 / 12, y / 2), 240.0, 3.0) << "red's Cr";
  EXPECT_NEAR(at(file.chromaU[0], width / 2, width / 12, y / 2), 128.0, 2.0) << "white's Cb";
}

TEST(Mp4Writer, HdIsConvertedAndTaggedAsBt709LimitedRange) {
  checkColours(1280, 720, AVCOL_SPC_BT709, 16.0 + 219.0 * 0.2126);
}

TEST(Mp4Writer, SdIsConvertedAndTaggedAsBt601LimitedRange) {
  checkColours(160, 120, AVCOL_SPC_SMPTE170M, 16.0 + 219.0 * 0.299);
}

TEST(Mp4Writer, TakesPaddedRowsAndBottomUpFrames) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "rows.mp4";
  const Mp4Options options = smallOptions();
  const int row = options.width * 3;
  // Top half white, bottom half black, stored bottom-up with 16 bytes of padding per row.
  const int stride = row + 16;
  std::vector<std::uint8_t> bottomUp(static_cast<std::size_t>(stride) * static_cast<std::size_t>(options.height), 7);
  for (int storedRow = 0; storedRow < options.height; ++storedRow) {
    const int imageRow = options.height - 1 - storedRow;
    std::fill_n(bottomUp.begin() + static_cast<std::ptrdiff_t>(storedRow) * stride, row,
                imageRow < options.height / 2 ? 255 : 0);
  }
  {
    Mp4Writer writer(path, options);
    // Top row first through a negative stride, then the same buffer top-down as a span (upside down).
    writer.addVideoFrame(bottomUp.data() + static_cast<std::ptrdiff_t>(options.height - 1) * stride, -stride);
    writer.addVideoFrame(std::span<const std::uint8_t>(bottomUp), stride);
    writer.finish();
  }
  const DecodedFile file = readBack(path);
  ASSERT_EQ(file.luma.size(), 2u);
  const auto luma = [&](std::size_t frame, int y) {
    return file.luma[frame][static_cast<std::size_t>(y) * static_cast<std::size_t>(options.width) + 80];
  };
  EXPECT_NEAR(luma(0, 10), 235, 2);
  EXPECT_NEAR(luma(0, options.height - 10), 16, 2);
  EXPECT_NEAR(luma(1, 10), 16, 2);
  EXPECT_NEAR(luma(1, options.height - 10), 235, 2);
}

TEST(Mp4Writer, TakesYCbCrPlanesAsTheyAre) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "planes.mp4";
  const Mp4Options options = smallOptions();
  const int w = options.width;
  const int h = options.height;
  // Left half Y 60, right half Y 200; Cb 90 on top, Cr 170 throughout; rows padded to check the strides.
  const int yStride = w + 8;
  const int cStride = w / 2 + 4;
  std::vector<std::uint8_t> y(static_cast<std::size_t>(yStride * h)), cb(static_cast<std::size_t>(cStride * h / 2)),
      cr(cb.size(), 170);
  for (int row = 0; row < h; ++row)
    for (int x = 0; x < w; ++x) y[static_cast<std::size_t>(row * yStride + x)] = x < w / 2 ? 60 : 200;
  for (int row = 0; row < h / 2; ++row)
    for (int x = 0; x < w / 2; ++x) cb[static_cast<std::size_t>(row * cStride + x)] = row < h / 4 ? 90 : 128;
  {
    Mp4Writer writer(path, options);
    EXPECT_EQ(writer.usesBt709(), h >= 720);
    writer.addVideoFrame(Yuv420Planes{y.data(), yStride, cb.data(), cr.data(), cStride});
    writer.addVideoFrame(Yuv420Planes{y.data(), yStride, cb.data(), cr.data(), cStride});
    EXPECT_THROW(writer.addVideoFrame(Yuv420Planes{y.data(), w - 1, cb.data(), cr.data(), cStride}), Error);
  }
  {
    Mp4Writer writer(path, options);
    writer.addVideoFrame(Yuv420Planes{y.data(), yStride, cb.data(), cr.data(), cStride});
    writer.addVideoFrame(Yuv420Planes{y.data(), yStride, cb.data(), cr.data(), cStride});
    writer.finish();
  }
  const DecodedFile file = readBack(path);
  ASSERT_EQ(file.luma.size(), 2u);
  const auto at = [](const std::vector<std::uint8_t>& plane, int planeWidth, int x, int row) {
    return static_cast<int>(plane[static_cast<std::size_t>(row * planeWidth + x)]);
  };
  EXPECT_NEAR(at(file.luma[1], w, w / 4, h / 2), 60, 2);
  EXPECT_NEAR(at(file.luma[1], w, 3 * w / 4, h / 2), 200, 2);
  EXPECT_NEAR(at(file.chromaU[1], w / 2, w / 4, h / 8), 90, 2);
  EXPECT_NEAR(at(file.chromaU[1], w / 2, w / 4, 3 * h / 8), 128, 2);
  EXPECT_NEAR(at(file.chromaV[1], w / 2, w / 4, h / 4), 170, 2);
}

// ---- unequal lengths and tiny files ----

TEST(Mp4Writer, OneFrameAndAFewMillisecondsOfSound) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "tiny.mp4";
  writeClip(path, smallOptions(), 1, std::vector<float>(100, 0.25F));  // 6.25 ms
  const DecodedFile file = readBack(path);
  EXPECT_EQ(file.video.packets, 1);
  EXPECT_EQ(file.luma.size(), 1u);
  EXPECT_NEAR(file.video.durationSeconds, 1.0 / 30, 1e-6);
  EXPECT_NEAR(file.audio.durationSeconds, 1.0 / 30, 1.0 / 48000 + 1e-9);  // padded to the frame
  EXPECT_NEAR(file.audio.startSeconds, 0.0, 1e-9);
}

TEST(Mp4Writer, AudioLongerThanTheVideoIsKeptWhole) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "long_audio.mp4";
  const std::vector<float> audio = toneAfter(2.0, 1.5, 16000);
  writeClip(path, smallOptions(), 10, audio);
  const DecodedFile file = readBack(path);
  EXPECT_NEAR(file.video.durationSeconds, 10.0 / 30, 1e-6);
  EXPECT_NEAR(file.audio.durationSeconds, 2.0, 1.0 / 48000 + 1e-9);
  EXPECT_NEAR(file.durationSeconds, 2.0, 0.01);
  EXPECT_EQ(file.luma.size(), 10u);
  EXPECT_NEAR(static_cast<double>(firstLoudSample(file.audioSamples, 0.1F)) / 48000, 1.5, 0.001);
}

TEST(Mp4Writer, AudioShorterThanTheVideoIsPaddedWithSilence) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "short_audio.mp4";
  writeClip(path, smallOptions(), 30, toneAfter(0.2, 0.1, 16000));
  const DecodedFile file = readBack(path);
  EXPECT_NEAR(file.video.durationSeconds, 1.0, 1e-6);
  EXPECT_NEAR(file.audio.durationSeconds, 1.0, 1.0 / 48000 + 1e-9);
  EXPECT_NEAR(static_cast<double>(firstLoudSample(file.audioSamples, 0.1F)) / 48000, 0.1, 0.001);
  // Silence after the 0.2 s of sound (allowing the codec's ringing for 10 ms).
  const auto afterEnd = static_cast<std::size_t>(0.21 * 48000);
  ASSERT_GT(file.audioSamples.size(), afterEnd);
  float loudest = 0.0F;
  for (std::size_t n = afterEnd; n < file.audioSamples.size(); ++n)
    loudest = std::max(loudest, std::abs(file.audioSamples[n]));
  EXPECT_LT(loudest, 0.02F);
}

TEST(Mp4Writer, WithoutAudioTheSoundTrackIsSilent) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "mute.mp4";
  writeClip(path, smallOptions(), 15, {});
  const DecodedFile file = readBack(path);
  ASSERT_TRUE(file.audio.present);
  EXPECT_NEAR(file.audio.durationSeconds, 0.5, 1.0 / 48000 + 1e-9);
  EXPECT_EQ(firstLoudSample(file.audioSamples, 0.001F), -1);
}

TEST(Mp4Writer, AllAudioFirstOrLastGivesTheSameTiming) {
  TemporaryFolder folder;
  Mp4Options options = smallOptions();
  options.framesPerSecond = 25.0;
  options.audioSampleRateHz = 22050;
  options.outputAudioRateHz = 44100;
  const std::vector<float> audio = toneAfter(0.8, 0.3, options.audioSampleRateHz);
  const auto frames =
      static_cast<int>(videoFramesFor(audio.size(), options.audioSampleRateHz, options.framesPerSecond));
  for (const bool audioFirst : {true, false}) {
    const fs::path path = folder.path() / (audioFirst ? "first.mp4" : "last.mp4");
    {
      Mp4Writer writer(path, options);
      if (audioFirst) writer.addAudio(audio);
      for (int f = 0; f < frames; ++f) writer.addVideoFrame(greyFrame(160, 120, greyOf(f)), 160 * 3);
      if (!audioFirst) writer.addAudio(audio);
      EXPECT_NEAR(writer.audioSeconds(), 0.8, 1e-9);
      EXPECT_NEAR(writer.videoSeconds(), frames / 25.0, 1e-9);
      writer.finish();
    }
    const DecodedFile file = readBack(path);
    EXPECT_EQ(file.audio.sampleRateHz, 44100);
    EXPECT_NEAR(file.video.durationSeconds, frames / 25.0, 1e-6) << path;
    EXPECT_NEAR(file.audio.durationSeconds, file.video.durationSeconds, 1.0 / 44100 + 1e-9) << path;
    EXPECT_NEAR(static_cast<double>(firstLoudSample(file.audioSamples, 0.1F)) / 44100, 0.3, 0.001) << path;
    EXPECT_NEAR(file.audio.startSeconds, 0.0, 1e-9) << path;
  }
}

TEST(Mp4Writer, FractionalFrameRate) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "ntsc.mp4";
  Mp4Options options = smallOptions();
  options.framesPerSecond = 30000.0 / 1001.0;
  const std::vector<float> audio(16000, 0.0F);
  const auto frames = static_cast<int>(videoFramesFor(audio.size(), 16000, options.framesPerSecond));
  EXPECT_EQ(frames, 30);  // 29.97 frames, rounded up
  writeClip(path, options, frames, audio);
  const DecodedFile file = readBack(path);
  EXPECT_NEAR(file.video.durationSeconds, frames * 1001.0 / 30000.0, 1e-4);
  EXPECT_NEAR(file.audio.durationSeconds, file.video.durationSeconds, 1.0 / 48000 + 1e-4);
}

TEST(Mp4Writer, LosslessQualityUsesTheHigh444PredictiveProfile) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "lossless.mp4";
  Mp4Options options = smallOptions();
  options.crf = 0;
  options.preset = "ultrafast";
  writeClip(path, options, 3, {});
  const DecodedFile file = readBack(path);
  EXPECT_EQ(file.video.profile, FF_PROFILE_H264_HIGH_444_PREDICTIVE);
  ASSERT_EQ(file.luma.size(), 3u);
  EXPECT_NEAR(mean(file.luma[2]), 16.0 + greyOf(2) * 219.0 / 255.0, 0.6);
}

TEST(Mp4Writer, X264SettingsApplyOverThePreset) {
  // Detailed frames (a deterministic noise texture), encoded at the default quality and with a fixed quantiser
  // of 51 (the coarsest) given as an x264 setting: a far smaller file.
  TemporaryFolder folder;
  Mp4Options options = smallOptions();
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(options.width * options.height * 3));
  const auto write = [&](const fs::path& path) {
    Mp4Writer writer(path, options);
    for (int f = 0; f < 5; ++f) {
      for (std::size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = static_cast<std::uint8_t>((i * 2654435761U + f * 97U) >> 24);
      writer.addVideoFrame(rgb.data(), options.width * 3);
    }
    writer.finish();
    return fs::file_size(path);
  };
  const auto standard = write(folder.path() / "default.mp4");
  options.x264Params = "qp=51";
  const auto coarse = write(folder.path() / "coarse.mp4");
  EXPECT_LT(coarse * 4, standard);
}

TEST(Mp4Writer, VideoFramesForRoundsUpExactly) {
  EXPECT_EQ(videoFramesFor(16000, 16000, 30.0), 30);
  EXPECT_EQ(videoFramesFor(16001, 16000, 30.0), 31);
  EXPECT_EQ(videoFramesFor(15999, 16000, 30.0), 30);
  EXPECT_EQ(videoFramesFor(0, 16000, 30.0), 0);
  EXPECT_EQ(videoFramesFor(1, 16000, 30.0), 1);
  EXPECT_EQ(videoFramesFor(48000 * 3600, 48000, 25.0), 90000);
  EXPECT_EQ(videoFramesFor(1001 * 16, 16000, 30000.0 / 1001.0), 30);
  EXPECT_THROW(videoFramesFor(10, 0, 30.0), Error);
  EXPECT_THROW(videoFramesFor(10, 16000, 0.0), Error);
}

// ---- all or nothing ----

// Both kinds of temporary file: the unnamed O_TMPFILE (the default) and the hidden named one.
class Mp4WriterTemporaryFile : public ::testing::TestWithParam<bool> {
 protected:
  Mp4Options options() const {
    Mp4Options result = smallOptions();
    result.unnamedTemporaryFile = GetParam();
    return result;
  }
};

TEST_P(Mp4WriterTemporaryFile, NothingIsVisibleUntilFinishAndNothingIsLeftAfterIt) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "clip.mp4";
  Mp4Writer writer(path, options());
  writer.addVideoFrame(greyFrame(160, 120, 9), 160 * 3);
  const std::vector<std::string> during = listFolder(folder.path());
  if (GetParam()) {
    EXPECT_TRUE(during.empty()) << during.front();
  } else {
    ASSERT_EQ(during.size(), 1u);
    EXPECT_EQ(during.front().rfind(".clip.mp4.", 0), 0u) << during.front();
    EXPECT_EQ(fs::path(during.front()).extension(), ".tmp");
  }
  writer.finish();
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"clip.mp4"});
  EXPECT_EQ(readBack(path).video.packets, 1);
}

TEST_P(Mp4WriterTemporaryFile, UnfinishedWriterLeavesNothing) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "cancelled.mp4";
  {
    Mp4Writer writer(path, options());
    for (int f = 0; f < 20; ++f) writer.addVideoFrame(greyFrame(160, 120, greyOf(f)), 160 * 3);
    writer.addAudio(std::vector<float>(16000, 0.1F));
  }
  EXPECT_TRUE(listFolder(folder.path()).empty());
}

TEST_P(Mp4WriterTemporaryFile, ExistingTargetIsReplacedOnlyOnSuccess) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "out.mp4";
  std::ofstream(path) << "old";
  {
    Mp4Writer writer(path, options());
    writer.addVideoFrame(greyFrame(160, 120, 9), 160 * 3);
  }
  EXPECT_EQ(readText(path), "old");
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"out.mp4"});
  {
    Mp4Writer writer(path, options());
    writer.addVideoFrame(greyFrame(160, 120, 9), 160 * 3);
    EXPECT_EQ(readText(path), "old");
    writer.finish();
  }
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"out.mp4"});
  EXPECT_EQ(readBack(path).video.packets, 1);
}

TEST_P(Mp4WriterTemporaryFile, AFailedFinishLeavesTheOldTarget) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "empty.mp4";
  std::ofstream(path) << "old";
  {
    Mp4Writer writer(path, options());
    EXPECT_THROW(writer.finish(), Error);  // no frames
    EXPECT_EQ(readText(path), "old");
  }
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"empty.mp4"});
}

INSTANTIATE_TEST_SUITE_P(Kinds, Mp4WriterTemporaryFile, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& kind) { return kind.param ? "Unnamed" : "Named"; });

// With the unnamed temporary file (the default), even a killed process leaves nothing behind.
TEST(Mp4Writer, KilledProcessLeavesNothing) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "killed.mp4";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      Mp4Writer writer(path, smallOptions());
      for (int f = 0; f < 40; ++f) writer.addVideoFrame(greyFrame(160, 120, greyOf(f)), 160 * 3);
      writer.addAudio(std::vector<float>(16000, 0.1F));
      ::kill(::getpid(), SIGKILL);  // as an export killed mid-way: no destructor runs
    } catch (...) {
    }
    ::_exit(3);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the child failed before it was killed, status " << status;
  EXPECT_TRUE(listFolder(folder.path()).empty()) << listFolder(folder.path()).front();
}

// ---- errors ----

// The message of the th::Error that `act` throws ("(no error)" if none).
std::string errorOf(const std::function<void()>& act) {
  try {
    act();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Mp4Writer, RefusesBadOptionsBeforeWritingAnything) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "bad.mp4";
  const auto open = [&](const std::function<void(Mp4Options&)>& change) {
    Mp4Options options = smallOptions();
    change(options);
    return errorOf([&] { Mp4Writer writer(path, options); });
  };
  expectFileError(open([](Mp4Options& o) { o.width = 161; }), path, "161x120 is odd");
  expectFileError(open([](Mp4Options& o) { o.height = 99; }), path, "160x99 is odd");
  expectFileError(open([](Mp4Options& o) { o.width = 0; }), path, "not positive");
  expectFileError(open([](Mp4Options& o) { o.height = -2; }), path, "not positive");
  expectFileError(open([](Mp4Options& o) { o.framesPerSecond = 0.0; }), path, "frame rate");
  expectFileError(open([](Mp4Options& o) { o.framesPerSecond = -30.0; }), path, "frame rate");
  expectFileError(open([](Mp4Options& o) { o.framesPerSecond = std::nan(""); }), path, "frame rate");
  expectFileError(open([](Mp4Options& o) { o.audioSampleRateHz = 0; }), path, "audio sample rate");
  expectFileError(open([](Mp4Options& o) { o.outputAudioRateHz = 44000; }), path, "AAC does not support");
  expectFileError(open([](Mp4Options& o) { o.crf = 52; }), path, "crf");
  expectFileError(open([](Mp4Options& o) { o.preset = "ludicrous"; }), path, "unknown x264 preset");
  expectFileError(open([](Mp4Options& o) { o.threads = -1; }), path, "threads");
  EXPECT_TRUE(listFolder(folder.path()).empty());
}

TEST(Mp4Writer, RefusesTargetsThatCannotBeWritten) {
  TemporaryFolder folder;
  const fs::path missing = folder.path() / "no_such_folder" / "out.mp4";
  expectFileError(errorOf([&] { Mp4Writer writer(missing, smallOptions()); }), missing, "folder does not exist");
  const fs::path isFolder = folder.path() / "sub";
  fs::create_directory(isFolder);
  expectFileError(errorOf([&] { Mp4Writer writer(isFolder, smallOptions()); }), isFolder, "is a folder");
  // Not writable even for root.
  const fs::path unwritable = "/proc/talkinghead-test.mp4";
  if (fs::is_directory("/proc")) {
    expectFileError(errorOf([&] { Mp4Writer writer(unwritable, smallOptions()); }), unwritable, "cannot be written");
  }
  EXPECT_EQ(listFolder(folder.path()), std::vector<std::string>{"sub"});
  // A device or a pipe is never replaced by a file (a named pipe stands in for /dev/null here).
  const fs::path pipe = folder.path() / "pipe.mp4";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  expectFileError(errorOf([&] { Mp4Writer writer(pipe, smallOptions()); }), pipe, "not a regular file");
  EXPECT_TRUE(fs::is_fifo(pipe));
}

TEST(Mp4Writer, RefusesBadFramesAndLateCalls) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "late.mp4";
  Mp4Writer writer(path, smallOptions());
  const std::vector<std::uint8_t> rgb = greyFrame(160, 120, 100);
  expectFileError(errorOf([&] { writer.addVideoFrame(rgb.data(), 160 * 3 - 1); }), path, "479 bytes apart");
  expectFileError(errorOf([&] { writer.addVideoFrame(rgb.data(), -100); }), path, "bytes apart");
  expectFileError(errorOf([&] { writer.addVideoFrame(static_cast<const std::uint8_t*>(nullptr), 480); }), path,
                  "null pointer");
  expectFileError(errorOf([&] { writer.addVideoFrame(std::span<const std::uint8_t>(rgb).first(1000), 480); }), path,
                  "smaller than");
  const std::vector<float> bad = {0.0F, std::nanf("")};
  expectFileError(errorOf([&] { writer.addAudio(bad); }), path, "audio sample 1 is not a finite number");
  EXPECT_EQ(writer.framesWritten(), 0);
  // Refused frames do not spoil the writer.
  writer.addVideoFrame(rgb, 480);
  writer.finish();
  expectFileError(errorOf([&] { writer.addVideoFrame(rgb.data(), 480); }), path, "after finish()");
  expectFileError(errorOf([&] { writer.addAudio(std::vector<float>(10, 0.0F)); }), path, "after finish()");
  expectFileError(errorOf([&] { writer.finish(); }), path, "twice");
  EXPECT_EQ(readBack(path).video.packets, 1);
}

TEST(Mp4Writer, NoFramesIsAnError) {
  TemporaryFolder folder;
  const fs::path path = folder.path() / "none.mp4";
  Mp4Writer writer(path, smallOptions());
  writer.addAudio(std::vector<float>(1000, 0.0F));
  expectFileError(errorOf([&] { writer.finish(); }), path, "no video frames");
  expectFileError(errorOf([&] { writer.addVideoFrame(greyFrame(160, 120, 1), 480); }), path, "earlier error");
  EXPECT_TRUE(listFolder(folder.path()).empty());
}

TEST(Mp4Writer, ThisFfmpegHasTheEncoders) {
  EXPECT_NE(avcodec_find_encoder_by_name("libx264"), nullptr);
  EXPECT_NE(avcodec_find_encoder_by_name("aac"), nullptr);
}

}  // namespace
}  // namespace th::formats
