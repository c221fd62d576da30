// What every use of FFmpeg's libraries in the engine shares: owning handles for its C objects, its error codes
// as text, and its logging switched off (errors reach callers as one th::Error line instead).
//
//   th::ffmpeg::silenceLogging();
//   th::ffmpeg::CodecHandle codec(avcodec_alloc_context3(decoder));   // avcodec_free_context on scope exit
//   if (result < 0) throw th::fileError(path, "cannot decode (FFmpeg: " + th::ffmpeg::message(result) + ")");
//
// Include only from .cpp files that link FFmpeg (PkgConfig::FFMPEG). Thread contract: no shared state besides
// the one-time logging switch.
#pragma once

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/rational.h>
#include <libswscale/swscale.h>
}

#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include "core/error.h"

namespace th::ffmpeg {

struct CodecFreer {
  void operator()(AVCodecContext* context) const { avcodec_free_context(&context); }
};
struct FrameFreer {
  void operator()(AVFrame* frame) const { av_frame_free(&frame); }
};
struct PacketFreer {
  void operator()(AVPacket* packet) const { av_packet_free(&packet); }
};
using CodecHandle = std::unique_ptr<AVCodecContext, CodecFreer>;
using FrameHandle = std::unique_ptr<AVFrame, FrameFreer>;
using PacketHandle = std::unique_ptr<AVPacket, PacketFreer>;
struct InputCloser {
  void operator()(AVFormatContext* context) const { avformat_close_input(&context); }
};
using InputHandle = std::unique_ptr<AVFormatContext, InputCloser>;
// An output's context with its file (closed first, when one was opened).
struct OutputCloser {
  void operator()(AVFormatContext* context) const {
    if (context->pb != nullptr) avio_closep(&context->pb);
    avformat_free_context(context);
  }
};
using OutputHandle = std::unique_ptr<AVFormatContext, OutputCloser>;
struct ScalerFreer {
  void operator()(SwsContext* context) const { sws_freeContext(context); }
};
using ScalerHandle = std::unique_ptr<SwsContext, ScalerFreer>;

// A frame rate as the nearest rational with terms up to 100000 (29.97 -> 2997/100).
inline AVRational frameRateOf(double framesPerSecond) {
  return av_d2q(framesPerSecond, 100000);
}

// FFmpeg's error code as text ("Permission denied", "End of file", ...).
// An AVDictionary of options, freed on scope exit (FFmpeg's open calls replace it with the unused ones).
struct Dictionary {
  AVDictionary* entries = nullptr;
  Dictionary() = default;
  Dictionary(const Dictionary&) = delete;
  Dictionary& operator=(const Dictionary&) = delete;
  ~Dictionary() { av_dict_free(&entries); }
};

inline std::string message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  if (av_strerror(code, text, sizeof(text)) < 0) {
    std::snprintf(text, sizeof(text), "error %d", code);
  }
  return text;
}

// FFmpeg logs to stderr by default, warnings and all; switched off for the whole process on first call.
inline void silenceLogging() {
  static std::once_flag once;
  std::call_once(once, [] { av_log_set_level(AV_LOG_QUIET); });
}

// A local media file opened for reading, its streams' parameters read; th::Error "PATH: not a readable media file
// (FFmpeg: ...)" when it cannot be.
inline InputHandle openInputFile(const std::filesystem::path& path) {
  Dictionary options;
  // Local files only: a playlist or concat list inside the file must not make FFmpeg open URLs.
  av_dict_set(&options.entries, "protocol_whitelist", "file", 0);
  // "file:" keeps a name with a colon in it ("take:2.mpg") from being read as a protocol.
  const std::string url = "file:" + path.string();
  AVFormatContext* raw = nullptr;
  const int opened = avformat_open_input(&raw, url.c_str(), nullptr, &options.entries);
  if (opened < 0) {  // avformat_open_input frees the context itself on failure
    throw fileError(path, "not a readable media file (FFmpeg: " + message(opened) + ")");
  }
  InputHandle input(raw);
  const int found = avformat_find_stream_info(input.get(), nullptr);
  if (found < 0) {
    throw fileError(path, "not a readable media file (FFmpeg cannot read its streams: " + message(found) + ")");
  }
  return input;
}

}  // namespace th::ffmpeg
