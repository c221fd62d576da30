#include "tracking/mjpeg_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include <string>

#include "core/error.h"
#include "core/ffmpeg_support.h"

namespace th::tracking {
namespace {

constexpr int kQuantiser = 2;  // JPEG quality: 1 (best) .. 31

}  // namespace

struct MjpegWriter::State {
  std::filesystem::path path;
  int width = 0, height = 0;
  ffmpeg::OutputHandle output;
  ffmpeg::CodecHandle codec;
  ffmpeg::FrameHandle picture{av_frame_alloc()};
  ffmpeg::PacketHandle packet{av_packet_alloc()};
  ffmpeg::ScalerHandle scaler;
  AVStream* stream = nullptr;
  std::int64_t framesWritten = 0;
  bool finished = false;

  Error failure(const std::string& what, int code) const {
    return fileError(path, what + (code < 0 ? " (FFmpeg: " + ffmpeg::message(code) + ")" : std::string()));
  }

  // One picture (nullptr: the end) to the encoder, and every packet it has ready to the file.
  void send(const AVFrame* frame) {
    int result = avcodec_send_frame(codec.get(), frame);
    if (result < 0) throw failure("Motion-JPEG encoding failed", result);
    for (;;) {
      result = avcodec_receive_packet(codec.get(), packet.get());
      if (result == AVERROR(EAGAIN) || result == AVERROR_EOF) return;
      if (result < 0) throw failure("Motion-JPEG encoding failed", result);
      av_packet_rescale_ts(packet.get(), codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      result = av_interleaved_write_frame(output.get(), packet.get());
      if (result < 0) throw failure("cannot be written", result);
    }
  }
};

MjpegWriter::MjpegWriter(const std::filesystem::path& path, double framesPerSecond, int width, int height)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.width = width;
  s.height = height;
  if (width <= 0 || height <= 0) throw fileError(path, "a video needs a picture size above 0");
  if (!(framesPerSecond > 0.0 && framesPerSecond < 1000.0)) throw fileError(path, "a video needs a frame rate above 0");
  ffmpeg::silenceLogging();
  if (!s.picture || !s.packet) throw s.failure("out of memory", 0);
  const std::string url = "file:" + path.string();  // a colon in the name is not a protocol
  AVFormatContext* raw = nullptr;
  int result = avformat_alloc_output_context2(&raw, nullptr, "avi", url.c_str());
  if (result < 0 || raw == nullptr) throw s.failure("cannot be written as AVI", result);
  s.output.reset(raw);
  const AVCodec* encoder = avcodec_find_encoder(AV_CODEC_ID_MJPEG);
  if (encoder == nullptr) throw s.failure("cannot be written: this FFmpeg has no Motion-JPEG encoder", 0);
  s.codec.reset(avcodec_alloc_context3(encoder));
  if (!s.codec) throw s.failure("out of memory", 0);
  AVCodecContext& codec = *s.codec;
  codec.width = width;
  codec.height = height;
  codec.pix_fmt = AV_PIX_FMT_YUVJ420P;
  codec.color_range = AVCOL_RANGE_JPEG;
  codec.framerate = ffmpeg::frameRateOf(framesPerSecond);
  codec.time_base = av_inv_q(codec.framerate);
  codec.flags |= AV_CODEC_FLAG_QSCALE;
  codec.global_quality = FF_QP2LAMBDA * kQuantiser;
  if (s.output->oformat->flags & AVFMT_GLOBALHEADER) codec.flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  result = avcodec_open2(&codec, encoder, nullptr);
  if (result < 0) throw s.failure("cannot set up the Motion-JPEG encoder", result);
  s.stream = avformat_new_stream(s.output.get(), nullptr);
  if (s.stream == nullptr) throw s.failure("out of memory", 0);
  s.stream->time_base = codec.time_base;
  result = avcodec_parameters_from_context(s.stream->codecpar, &codec);
  if (result < 0) throw s.failure("cannot set up the video stream", result);
  s.picture->format = codec.pix_fmt;
  s.picture->width = width;
  s.picture->height = height;
  s.picture->color_range = AVCOL_RANGE_JPEG;
  result = av_frame_get_buffer(s.picture.get(), 0);
  if (result < 0) throw s.failure("out of memory", result);
  s.scaler.reset(sws_getContext(width, height, AV_PIX_FMT_BGR24, width, height, AV_PIX_FMT_YUVJ420P, SWS_BICUBIC,
                                nullptr, nullptr, nullptr));
  if (!s.scaler) throw s.failure("cannot set up the BGR to YUV conversion", 0);
  result = avio_open(&s.output->pb, url.c_str(), AVIO_FLAG_WRITE);
  if (result < 0) throw s.failure("cannot be written", result);
  result = avformat_write_header(s.output.get(), nullptr);
  if (result < 0) throw s.failure("cannot be written", result);
}

MjpegWriter::~MjpegWriter() = default;

void MjpegWriter::write(const cv::Mat& bgr) {
  State& s = *state_;
  if (s.finished) throw s.failure("written to after it was finished", 0);
  if (bgr.type() != CV_8UC3 || bgr.cols != s.width || bgr.rows != s.height)
    throw s.failure("was given a picture of " + std::to_string(bgr.cols) + " x " + std::to_string(bgr.rows) +
                        " (it takes 8-bit BGR of " + std::to_string(s.width) + " x " + std::to_string(s.height) + ")",
                    0);
  int result = av_frame_make_writable(s.picture.get());
  if (result < 0) throw s.failure("out of memory", result);
  const std::uint8_t* const source[] = {bgr.data, nullptr, nullptr, nullptr};
  const int sourceStride[] = {static_cast<int>(bgr.step[0]), 0, 0, 0};
  sws_scale(s.scaler.get(), source, sourceStride, 0, s.height, s.picture->data, s.picture->linesize);
  s.picture->pts = s.framesWritten++;
  s.send(s.picture.get());
}

void MjpegWriter::finish() {
  State& s = *state_;
  if (s.finished) return;
  s.finished = true;
  s.send(nullptr);
  const int result = av_write_trailer(s.output.get());
  if (result < 0) throw s.failure("cannot be written", result);
  if (s.output->pb != nullptr) {
    const int closed = avio_closep(&s.output->pb);
    if (closed < 0) throw s.failure("cannot be written", closed);
  }
}

}  // namespace th::tracking
