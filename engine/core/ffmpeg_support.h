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
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
}

#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

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

}  // namespace th::ffmpeg
