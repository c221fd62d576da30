#include "audio/media_audio.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/samplefmt.h>
}

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

#include "audio/resampler.h"
#include "core/error.h"
#include "core/ffmpeg_support.h"
#include "core/text_files.h"

#if LIBAVUTIL_VERSION_INT < AV_VERSION_INT(57, 24, 100)
#error "media_audio.cpp needs FFmpeg 5.1 or later (AVFrame::ch_layout)"
#endif

namespace th::audio {
namespace {

// FFmpeg's error codes, spelled once (its macros contain C casts).
const int kEndOfFile = AVERROR_EOF;
const int kTryAgain = AVERROR(EAGAIN);
const int kStreamNotFound = AVERROR_STREAM_NOT_FOUND;
const int kDecoderNotFound = AVERROR_DECODER_NOT_FOUND;

using FormatHandle = ffmpeg::InputHandle;
using ffmpeg::CodecHandle;
using ffmpeg::FrameHandle;
using ffmpeg::PacketHandle;

constexpr double kMaxSampleMagnitude = 1e6;  // as readAudioFile: 120 dB over full scale is corrupt data

// Collects the stream's samples as mono (channel mean), checking each one.
class MonoCollector {
 public:
  MonoCollector(const std::filesystem::path& path, const AudioReadOptions& options) : path_(path), options_(options) {}

  void add(const AVFrame& frame) {
    if (frame.nb_samples <= 0) return;
    checkRate(frame.sample_rate);
    const int channels = frame.ch_layout.nb_channels;
    if (channels <= 0) throw fileError(path_, "its audio stream has no channels");
    if (channels > sourceChannels_) sourceChannels_ = channels;
    const auto format = static_cast<AVSampleFormat>(frame.format);
    switch (av_get_packed_sample_fmt(format)) {
      case AV_SAMPLE_FMT_U8:
        mix<uint8_t>(frame, channels, [](uint8_t v) { return (static_cast<double>(v) - 128.0) / 128.0; });
        break;
      case AV_SAMPLE_FMT_S16:
        mix<int16_t>(frame, channels, [](int16_t v) { return static_cast<double>(v) / 32768.0; });
        break;
      case AV_SAMPLE_FMT_S32:
        mix<int32_t>(frame, channels, [](int32_t v) { return static_cast<double>(v) / 2147483648.0; });
        break;
      case AV_SAMPLE_FMT_S64:
        mix<int64_t>(frame, channels, [](int64_t v) { return static_cast<double>(v) / 9223372036854775808.0; });
        break;
      case AV_SAMPLE_FMT_FLT:
        mix<float>(frame, channels, [](float v) { return static_cast<double>(v); });
        break;
      case AV_SAMPLE_FMT_DBL:
        mix<double>(frame, channels, [](double v) { return v; });
        break;
      default: {
        const char* formatName = av_get_sample_fmt_name(format);
        throw fileError(path_, std::string("its audio decoder produces an unsupported sample format (") +
                                   (formatName != nullptr ? formatName : "unknown") + ")");
      }
    }
  }

  std::vector<float>& samples() { return mono_; }
  int sourceRateHz() const { return sourceRateHz_; }
  int sourceChannels() const { return sourceChannels_; }

 private:
  void checkRate(int rateHz) {
    if (sourceRateHz_ == 0) {
      if (rateHz < options_.minInputRateHz || rateHz > options_.maxInputRateHz) {
        throw fileError(path_, "sample rate " + std::to_string(rateHz) + " Hz is outside the supported " +
                                   std::to_string(options_.minInputRateHz) + "-" +
                                   std::to_string(options_.maxInputRateHz) + " Hz");
      }
      sourceRateHz_ = rateHz;
    } else if (rateHz != sourceRateHz_) {
      throw fileError(path_, "the audio's sample rate changes from " + std::to_string(sourceRateHz_) + " to " +
                                 std::to_string(rateHz) + " Hz after " + std::to_string(mono_.size()) + " samples");
    }
  }

  // Planar formats hold one buffer per channel (extended_data[c]); packed ones interleave them in data[0].
  template <typename Sample, typename ToDouble>
  void mix(const AVFrame& frame, int channels, ToDouble toDouble) {
    const bool planar = av_sample_fmt_is_planar(static_cast<AVSampleFormat>(frame.format)) != 0;
    const auto count = static_cast<size_t>(frame.nb_samples);
    const auto channelCount = static_cast<size_t>(channels);
    // 24 hours at the maximum rate, as readAudioFile allows: beyond that the file is not a recording.
    const auto maxSamples = static_cast<size_t>(options_.maxInputRateHz) * 3600 * 24;
    if (mono_.size() + count > maxSamples) throw fileError(path_, "its audio is implausibly long (over 24 hours)");
    for (size_t n = 0; n < count; ++n) {
      double sum = 0.0;
      for (size_t c = 0; c < channelCount; ++c) {
        const Sample* base = planar ? reinterpret_cast<const Sample*>(frame.extended_data[c]) + n
                                    : reinterpret_cast<const Sample*>(frame.extended_data[0]) + n * channelCount + c;
        const double value = toDouble(*base);
        if (!std::isfinite(value)) {
          throw fileError(path_,
                          "sample " + std::to_string(mono_.size()) + " is not a finite number (NaN or infinity)");
        }
        if (std::abs(value) > kMaxSampleMagnitude) {
          char level[32];
          std::snprintf(level, sizeof(level), "%g", value);
          throw fileError(path_, "sample " + std::to_string(mono_.size()) + " is " + level +
                                     ", more than 120 dB above full scale (corrupt data?)");
        }
        sum += value;
      }
      mono_.push_back(static_cast<float>(sum / static_cast<double>(channelCount)));
    }
  }

  const std::filesystem::path& path_;
  const AudioReadOptions& options_;
  std::vector<float> mono_;
  int sourceRateHz_ = 0;
  int sourceChannels_ = 0;
};

// Takes every frame the decoder has ready; false once it has signalled the end of the stream.
bool receiveFrames(AVCodecContext* codec, AVFrame* frame, MonoCollector& collector, const std::filesystem::path& path) {
  for (;;) {
    const int result = avcodec_receive_frame(codec, frame);
    if (result == kTryAgain) return true;
    if (result == kEndOfFile) return false;
    if (result < 0) {
      throw fileError(path, "audio decoding failed after " + std::to_string(collector.samples().size()) +
                                " samples (FFmpeg: " + ffmpeg::message(result) + ")");
    }
    collector.add(*frame);
    av_frame_unref(frame);
  }
}

void sendPacket(AVCodecContext* codec, const AVPacket* packet, AVFrame* frame, MonoCollector& collector,
                const std::filesystem::path& path) {
  for (;;) {
    const int result = avcodec_send_packet(codec, packet);
    // EAGAIN: the decoder's output is full; take its frames and offer the packet again.
    if (result == kTryAgain) {
      if (!receiveFrames(codec, frame, collector, path)) return;
      continue;
    }
    if (result == kEndOfFile) return;  // already flushed
    if (result < 0) {
      throw fileError(path, "audio decoding failed after " + std::to_string(collector.samples().size()) +
                                " samples (FFmpeg: " + ffmpeg::message(result) + ")");
    }
    receiveFrames(codec, frame, collector, path);
    return;
  }
}

}  // namespace

AudioClip readMediaAudio(const std::filesystem::path& path, const AudioReadOptions& options) {
  ffmpeg::silenceLogging();
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw fileError(path, "no such file");
  if (std::filesystem::is_directory(status)) throw fileError(path, "is a directory, not a media file");
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw fileError(path, "cannot read: " + error.message());
  if (size == 0) throw fileError(path, "empty file (0 bytes)");

  FormatHandle format = ffmpeg::openInputFile(path);
  const AVCodec* decoder = nullptr;
  const int streamIndex = av_find_best_stream(format.get(), AVMEDIA_TYPE_AUDIO, -1, -1, &decoder, 0);
  if (streamIndex == kStreamNotFound) throw fileError(path, "has no audio stream");
  if (streamIndex == kDecoderNotFound || (streamIndex >= 0 && decoder == nullptr)) {
    std::string codecName = "unknown";
    for (unsigned s = 0; s < format->nb_streams; ++s) {
      if (format->streams[s]->codecpar->codec_type == AVMEDIA_TYPE_AUDIO) {
        codecName = avcodec_get_name(format->streams[s]->codecpar->codec_id);
        break;
      }
    }
    throw fileError(path, "has audio in a format FFmpeg cannot decode (" + codecName + ")");
  }
  if (streamIndex < 0) {
    throw fileError(path, "cannot choose its audio stream (FFmpeg: " + ffmpeg::message(streamIndex) + ")");
  }
  // Only the audio stream's packets are wanted: the demuxer may skip the rest.
  for (unsigned s = 0; s < format->nb_streams; ++s) {
    if (static_cast<int>(s) != streamIndex) format->streams[s]->discard = AVDISCARD_ALL;
  }
  const AVStream* stream = format->streams[streamIndex];

  CodecHandle codec(avcodec_alloc_context3(decoder));
  if (!codec) throw fileError(path, "cannot allocate an audio decoder");
  int result = avcodec_parameters_to_context(codec.get(), stream->codecpar);
  if (result < 0) {
    throw fileError(path, "cannot set up its audio decoder (FFmpeg: " + ffmpeg::message(result) + ")");
  }
  codec->pkt_timebase = stream->time_base;
  result = avcodec_open2(codec.get(), decoder, nullptr);
  if (result < 0) {
    throw fileError(path, std::string("cannot open its audio decoder ") + decoder->name +
                              " (FFmpeg: " + ffmpeg::message(result) + ")");
  }

  PacketHandle packet(av_packet_alloc());
  FrameHandle frame(av_frame_alloc());
  if (!packet || !frame) throw fileError(path, "out of memory while decoding");
  MonoCollector collector(path, options);
  for (;;) {
    result = av_read_frame(format.get(), packet.get());
    if (result == kEndOfFile) break;
    if (result < 0) {
      throw fileError(path, "read error after " + std::to_string(collector.samples().size()) +
                                " audio samples (FFmpeg: " + ffmpeg::message(result) + ")");
    }
    if (packet->stream_index == streamIndex) sendPacket(codec.get(), packet.get(), frame.get(), collector, path);
    av_packet_unref(packet.get());
  }
  // An empty packet flushes the decoder: its delayed frames come out, then the end of the stream.
  sendPacket(codec.get(), nullptr, frame.get(), collector, path);

  const size_t decoded = collector.samples().size();
  if (decoded == 0) throw fileError(path, "its audio stream contains no samples");
  AudioClip clip;
  clip.sourceRateHz = collector.sourceRateHz();
  clip.sourceChannels = collector.sourceChannels();
  clip.sampleRateHz = options.outputRateHz > 0 ? options.outputRateHz : clip.sourceRateHz;
  clip.samples = clip.sourceRateHz == clip.sampleRateHz
                     ? std::move(collector.samples())
                     : resample(collector.samples(), clip.sourceRateHz, clip.sampleRateHz);
  if (clip.samples.empty()) {
    throw fileError(path, "too short (" + std::to_string(decoded) + " samples at " + std::to_string(clip.sourceRateHz) +
                              " Hz make no sample at " + std::to_string(clip.sampleRateHz) + " Hz)");
  }
  return clip;
}

AudioClip readRecording(const std::filesystem::path& path, const AudioReadOptions& options) {
  const std::string extension = lowercaseExtension(path);
  const bool soundFile = extension == ".wav" || extension == ".flac" || extension == ".ogg" || extension == ".aiff" ||
                         extension == ".au" || extension == ".w64" || extension == ".caf";
  return soundFile ? readAudioFile(path, options) : readMediaAudio(path, options);
}

}  // namespace th::audio
