#include "tracking/video_reader.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/display.h>
}

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <system_error>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/ffmpeg_support.h"
#include "tracking/bgr_pictures.h"

namespace th::tracking {
namespace {

const int kTryAgain = AVERROR(EAGAIN);

}  // namespace

// FFmpeg's demuxer and decoder, read the way OpenCV's VideoCapture reads a file with its FFmpeg back-end (its frame
// rate, frame count, BGR conversion and turn by the stream's display matrix), without linking OpenCV's video I/O
// (a hundred libraries - GStreamer, GDAL, camera drivers - every process would load at start).
struct VideoReader::Capture {
  ffmpeg::InputHandle input;
  ffmpeg::CodecHandle codec;
  ffmpeg::PacketHandle packet{av_packet_alloc()};
  ffmpeg::FrameHandle frame{av_frame_alloc()};
  BgrConverter converter;
  int stream = -1;
  int turnDegrees = 0;  // clockwise, to show the picture upright: 0, 90, 180 or 270
  bool draining = false;
  bool ended = false;

  // The next decoded picture in `frame`; false at the end of the stream (or a packet that cannot be read).
  bool decodeNext() {
    while (!ended) {
      const int received = avcodec_receive_frame(codec.get(), frame.get());
      if (received == 0) return true;
      if (received != kTryAgain || draining) {
        ended = true;
        break;
      }
      const int read = av_read_frame(input.get(), packet.get());
      if (read < 0) {
        // The end, or a file that breaks off: the decoder's delayed pictures still come out.
        draining = true;
        avcodec_send_packet(codec.get(), nullptr);
        continue;
      }
      // A damaged packet is skipped (its error ignored), as players do; the decoder goes on with the next one.
      if (packet->stream_index == stream) avcodec_send_packet(codec.get(), packet.get());
      av_packet_unref(packet.get());
    }
    return false;
  }

  // The decoded picture as an 8-bit BGR image, turned upright.
  bool toBgr(cv::Mat& bgr) {
    cv::Mat picture;
    if (!converter.convert(*frame, picture)) return false;
    switch (turnDegrees) {
      case 90:
        cv::rotate(picture, bgr, cv::ROTATE_90_CLOCKWISE);
        break;
      case 180:
        cv::rotate(picture, bgr, cv::ROTATE_180);
        break;
      case 270:
        cv::rotate(picture, bgr, cv::ROTATE_90_COUNTERCLOCKWISE);
        break;
      default:
        bgr = picture;
    }
    return true;
  }
};

VideoReader::VideoReader(const std::filesystem::path& path) : path_(path), capture_(std::make_unique<Capture>()) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw fileError(path, "no such file");
  if (!std::filesystem::is_regular_file(path, error)) throw fileError(path, "not a file");
  // FFmpeg would otherwise print its complaints about a damaged stream; ours is one line.
  ffmpeg::silenceLogging();
  Capture& c = *capture_;
  try {
    c.input = ffmpeg::openInputFile(path);
  } catch (const Error&) {
    throw fileError(path, "not a video that can be read (FFmpeg could not open it)");
  }
  // The first video stream, as OpenCV takes (not FFmpeg's "best" one).
  for (unsigned s = 0; s < c.input->nb_streams && c.stream < 0; ++s)
    if (c.input->streams[s]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO &&
        (c.input->streams[s]->disposition & AV_DISPOSITION_ATTACHED_PIC) == 0)
      c.stream = static_cast<int>(s);
  if (c.stream < 0) throw fileError(path, "not a video that can be read (it has no video stream)");
  AVStream* stream = c.input->streams[c.stream];
  for (unsigned s = 0; s < c.input->nb_streams; ++s)
    if (static_cast<int>(s) != c.stream) c.input->streams[s]->discard = AVDISCARD_ALL;
  const AVCodec* decoder = avcodec_find_decoder(stream->codecpar->codec_id);
  if (decoder == nullptr)
    throw fileError(path, std::string("not a video that can be read (no decoder for ") +
                              avcodec_get_name(stream->codecpar->codec_id) + ")");
  c.codec.reset(avcodec_alloc_context3(decoder));
  if (!c.codec || !c.packet || !c.frame) throw fileError(path, "out of memory while opening the video");
  if (avcodec_parameters_to_context(c.codec.get(), stream->codecpar) < 0)
    throw fileError(path, "not a video that can be read (its decoder cannot be set up)");
  c.codec->pkt_timebase = stream->time_base;
  // Frame threads: decoding keeps up with the tracker (the pictures are the same whatever the thread count).
  c.codec->thread_count = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
  if (avcodec_open2(c.codec.get(), decoder, nullptr) < 0)
    throw fileError(path, "not a video that can be read (its decoder cannot be opened)");

  // The nominal rate: the stream's average frame rate, else its time base's.
  fps_ = av_q2d(stream->avg_frame_rate);
  if (!(fps_ > 1e-6)) fps_ = stream->time_base.num > 0 ? 1.0 / av_q2d(stream->time_base) : 0.0;
  if (!(fps_ > 0.0 && fps_ < 1000.0)) throw fileError(path, "the video has no usable frame rate");
  double frames = static_cast<double>(stream->nb_frames);
  if (frames <= 0.0) {
    const double seconds = stream->duration != AV_NOPTS_VALUE
                               ? static_cast<double>(stream->duration) * av_q2d(stream->time_base)
                           : c.input->duration != AV_NOPTS_VALUE ? static_cast<double>(c.input->duration) / AV_TIME_BASE
                                                                 : 0.0;
    frames = std::floor(seconds * fps_ + 0.5);
  }
  frameCountHint_ = static_cast<int>(std::clamp(frames, 0.0, 1e9));
  // A phone's video is stored sideways with a display matrix that says how to show it.
  if (const std::uint8_t* matrix = av_stream_get_side_data(stream, AV_PKT_DATA_DISPLAYMATRIX, nullptr)) {
    const double counterClockwise = av_display_rotation_get(reinterpret_cast<const std::int32_t*>(matrix));
    if (std::isfinite(counterClockwise)) {
      const int clockwise = static_cast<int>(std::lround(-counterClockwise / 90.0)) * 90;
      c.turnDegrees = ((clockwise % 360) + 360) % 360;
    }
  }

  if (!c.decodeNext() || !c.toBgr(first_) || first_.empty()) throw fileError(path, "no video frame could be decoded");
  width_ = first_.cols;
  height_ = first_.rows;
}

VideoReader::~VideoReader() = default;

bool VideoReader::read(cv::Mat& frame, double& seconds) {
  if (firstPending_) {
    firstPending_ = false;
    frame = first_;
    first_ = cv::Mat();
  } else if (!capture_->decodeNext() || !capture_->toBgr(frame) || frame.cols != width_ || frame.rows != height_) {
    return false;
  }
  seconds = framesRead_ / fps_;
  ++framesRead_;
  return true;
}

}  // namespace th::tracking
