// libtalkinghead_camera.so: the camera and the take's writer through OpenCV's video I/O (camera_module.h says why a
// module of their own).
#include "tracking/camera_module.h"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio.hpp>

namespace th::tracking {
namespace {

class OpenCvCamera final : public CameraDevice {
 public:
  explicit OpenCvCamera(int index) : capture_(index, cv::CAP_V4L2) {}
  bool opened() const { return capture_.isOpened(); }
  void ask(int width, int height, double framesPerSecond) {
    capture_.set(cv::CAP_PROP_FRAME_WIDTH, width);
    capture_.set(cv::CAP_PROP_FRAME_HEIGHT, height);
    capture_.set(cv::CAP_PROP_FPS, framesPerSecond);
  }
  bool grab() override { return capture_.grab(); }
  bool retrieve(cv::Mat& frame) override { return capture_.retrieve(frame) && !frame.empty(); }

 private:
  cv::VideoCapture capture_;
};

class OpenCvWriter final : public TakeVideoWriter {
 public:
  OpenCvWriter(const std::filesystem::path& path, double framesPerSecond, cv::Size size)
      : writer_(path.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), framesPerSecond, size) {}
  bool opened() const { return writer_.isOpened(); }
  void write(const cv::Mat& frame) override { writer_.write(frame); }
  void finish() override { writer_.release(); }

 private:
  cv::VideoWriter writer_;
};

std::unique_ptr<CameraDevice> openCamera(int index, int width, int height, double framesPerSecond) {
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);  // the caller's message is the one line
  auto camera = std::make_unique<OpenCvCamera>(index);
  if (!camera->opened()) return nullptr;
  camera->ask(width, height, framesPerSecond);
  return camera;
}

std::unique_ptr<TakeVideoWriter> openWriter(const std::filesystem::path& path, double framesPerSecond, cv::Size size) {
  auto writer = std::make_unique<OpenCvWriter>(path, framesPerSecond, size);
  if (!writer->opened()) return nullptr;
  return writer;
}

const CameraModule kModule{openCamera, openWriter};

}  // namespace
}  // namespace th::tracking

extern "C" __attribute__((visibility("default"))) const th::tracking::CameraModule* talkinghead_camera_module() {
  return &th::tracking::kModule;
}
