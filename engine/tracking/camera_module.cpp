// libtalkinghead_camera.so: the camera through FFmpeg's Video4Linux2 input (camera_module.h says why a module of
// its own).
#include "tracking/camera_module.h"

extern "C" {
#include <libavdevice/avdevice.h>
}

#include <cmath>
#include <mutex>
#include <string>
#include <utility>

#include "core/ffmpeg_support.h"
#include "tracking/bgr_pictures.h"

namespace th::tracking {
namespace {

class V4l2Camera final : public CameraDevice {
 public:
  // Null members when /dev/videoN cannot be opened or decoded.
  V4l2Camera(int index, int width, int height, double framesPerSecond) {
    static std::once_flag registered;
    std::call_once(registered, [] { avdevice_register_all(); });
    ffmpeg::silenceLogging();  // the caller's message is the one line
    const AVInputFormat* v4l2 = av_find_input_format("video4linux2");
    if (v4l2 == nullptr || !packet_ || !frame_) return;
    ffmpeg::Dictionary options;
    av_dict_set(&options.entries, "video_size", (std::to_string(width) + "x" + std::to_string(height)).c_str(), 0);
    av_dict_set(&options.entries, "framerate", std::to_string(std::lround(framesPerSecond)).c_str(), 0);
    const std::string device = "/dev/video" + std::to_string(index);
    AVFormatContext* raw = nullptr;
    if (avformat_open_input(&raw, device.c_str(), v4l2, &options.entries) < 0) return;  // frees raw itself
    input_.reset(raw);
    if (input_->nb_streams < 1) return;
    const AVCodecParameters& parameters = *input_->streams[0]->codecpar;
    const AVCodec* decoder = avcodec_find_decoder(parameters.codec_id);  // raw YUYV, or the camera's own MJPEG
    if (decoder == nullptr) return;
    ffmpeg::CodecHandle codec(avcodec_alloc_context3(decoder));
    if (!codec || avcodec_parameters_to_context(codec.get(), &parameters) < 0 ||
        avcodec_open2(codec.get(), decoder, nullptr) < 0)
      return;
    codec_ = std::move(codec);
  }

  bool opened() const { return codec_ != nullptr; }

  bool grab() override {
    av_packet_unref(packet_.get());
    return av_read_frame(input_.get(), packet_.get()) >= 0;
  }

  bool retrieve(cv::Mat& frame) override {
    if (packet_->size <= 0 || avcodec_send_packet(codec_.get(), packet_.get()) < 0) return false;
    av_packet_unref(packet_.get());  // decoded once
    if (avcodec_receive_frame(codec_.get(), frame_.get()) < 0) return false;
    return converter_.convert(*frame_, frame) && !frame.empty();
  }

 private:
  ffmpeg::InputHandle input_;
  ffmpeg::CodecHandle codec_;
  ffmpeg::PacketHandle packet_{av_packet_alloc()};
  ffmpeg::FrameHandle frame_{av_frame_alloc()};
  BgrConverter converter_;
};

std::unique_ptr<CameraDevice> openCamera(int index, int width, int height, double framesPerSecond) {
  auto camera = std::make_unique<V4l2Camera>(index, width, height, framesPerSecond);
  if (!camera->opened()) return nullptr;
  return camera;
}

const CameraModule kModule{openCamera};

}  // namespace
}  // namespace th::tracking

extern "C" __attribute__((visibility("default"))) const th::tracking::CameraModule* talkinghead_camera_module() {
  return &th::tracking::kModule;
}
