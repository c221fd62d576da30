// A take's video as Motion-JPEG in an AVI, through FFmpeg's encoder and muxer: every frame a JPEG of its own, so a
// take cut short still plays to its last frame and the tracker decodes any frame without its neighbours.
//
//   th::tracking::MjpegWriter writer(path, 25.0, 640, 480);   // th::Error "PATH: ..." when it cannot be written
//   writer.write(bgr);                                         // 8-bit BGR, 640 x 480
//   writer.finish();                                           // the file complete and closed
//
// Frame f is shown from f / fps. Pictures are full-range 4:2:0 JPEGs at a fixed high quality (quantiser 2 of
// 1..31, as `ffmpeg -q:v 2`), which keeps a face's edges for the landmark detector. A writer destroyed without
// finish() leaves a file whose end is missing; the caller decides what to keep. Thread contract: one thread per
// writer.
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>

namespace th::tracking {

class MjpegWriter {
 public:
  MjpegWriter(const std::filesystem::path& path, double framesPerSecond, int width, int height);
  ~MjpegWriter();
  MjpegWriter(const MjpegWriter&) = delete;
  MjpegWriter& operator=(const MjpegWriter&) = delete;

  void write(const cv::Mat& bgr);  // th::Error for a picture of another size or type, or a failed write
  void finish();                   // after it, write() is an error

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace th::tracking
