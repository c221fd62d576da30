#include "tracking/video_reader.h"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio.hpp>
#include <system_error>

#include "core/error.h"
#include "core/ffmpeg_support.h"

namespace th::tracking {

struct VideoReader::Capture {
  cv::VideoCapture capture;
};

VideoReader::VideoReader(const std::filesystem::path& path) : path_(path), capture_(std::make_unique<Capture>()) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw fileError(path, "no such file");
  if (!std::filesystem::is_regular_file(path, error)) throw fileError(path, "not a file");
  // Both libraries would otherwise print their complaints about a damaged stream; ours is one line.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  ffmpeg::silenceLogging();
  // The FFmpeg back-end only: it reads local files (OpenCV's image-sequence back-end would take "%d" patterns).
  if (!capture_->capture.open(path.string(), cv::CAP_FFMPEG) || !capture_->capture.isOpened())
    throw fileError(path, "not a video that can be read (OpenCV/FFmpeg could not open it)");
  fps_ = capture_->capture.get(cv::CAP_PROP_FPS);
  if (!(fps_ > 0.0 && fps_ < 1000.0)) throw fileError(path, "the video has no usable frame rate");
  frameCountHint_ = static_cast<int>(std::max(0.0, capture_->capture.get(cv::CAP_PROP_FRAME_COUNT)));
  if (!capture_->capture.read(first_) || first_.empty()) throw fileError(path, "no video frame could be decoded");
  if (first_.type() != CV_8UC3) throw fileError(path, "frames are not 8-bit colour images");
  width_ = first_.cols;
  height_ = first_.rows;
}

VideoReader::~VideoReader() = default;

bool VideoReader::read(cv::Mat& frame, double& seconds) {
  if (firstPending_) {
    firstPending_ = false;
    frame = first_;
    first_ = cv::Mat();
  } else if (!capture_->capture.read(frame) || frame.empty() || frame.cols != width_ || frame.rows != height_ ||
             frame.type() != CV_8UC3) {
    return false;
  }
  seconds = framesRead_ / fps_;
  ++framesRead_;
  return true;
}

}  // namespace th::tracking
