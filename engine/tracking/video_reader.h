// Frames of a video file, in order, as 8-bit BGR images with their times, decoded by FFmpeg (MPEG-1/2 as in GRID,
// MP4, AVI, MKV, ...) and converted as OpenCV's VideoCapture converts them (tracks of GRID, StyleTalk and news
// clips are byte for byte those read through it), turned upright by the stream's display matrix; local files only.
//
//   th::tracking::VideoReader video(th::sharedDataPath("grid/s1/bbal7s.mpg"));   // 25 fps, 360x288
//   cv::Mat frame;
//   double seconds = 0.0;
//   while (video.read(frame, seconds)) use(frame, seconds);
//
// Frame f's time is f / fps (the container's nominal rate), so times are exact multiples of the frame period
// even where the container's time stamps jitter. Bad input throws th::Error with one line "PATH: what is wrong":
// missing, not a video FFmpeg can open, no frame rate, no frame at all. A file that breaks off part-way ends
// at its last good frame (read() returns false), as players do; framesRead() tells how many came.
//
// Thread contract: one thread per reader.
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>

namespace th::tracking {

class VideoReader {
 public:
  explicit VideoReader(const std::filesystem::path& path);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  // The next frame (BGR, 8 bits a channel) and its time in seconds; false at the end.
  bool read(cv::Mat& frame, double& seconds);

  double framesPerSecond() const { return fps_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // How many frames the container says it has (an estimate for some formats; 0 if it does not say).
  int frameCountHint() const { return frameCountHint_; }
  int framesRead() const { return framesRead_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  struct Capture;
  std::filesystem::path path_;
  std::unique_ptr<Capture> capture_;
  cv::Mat first_;  // read at opening (a file that opens but has no frame is an error there)
  bool firstPending_ = true;
  double fps_ = 0.0;
  int width_ = 0;
  int height_ = 0;
  int frameCountHint_ = 0;
  int framesRead_ = 0;
};

}  // namespace th::tracking
