// The webcam and the take's Motion-JPEG writer, as `record` uses them (take_recorder.cpp). Both are OpenCV's
// video I/O, which loads a hundred libraries (GStreamer, GDAL, camera drivers) into any process linking it: so
// they live in a module of their own, libtalkinghead_camera.so, which cameraModule() opens the first time a take
// is recorded, and every other command starts without them.
//
//   const th::tracking::CameraModule& module = th::tracking::cameraModule();   // throws if it cannot be opened
//   std::unique_ptr<th::tracking::CameraDevice> camera = module.openCamera(0, 640, 480, 25.0);   // null: none
//
// The module is looked for beside the running program, in the installed tree's lib/talkinghead/ (from the
// program's bin/: ../lib/talkinghead/, or its multiarch lib folder), then where this build made it. Thread contract:
// cameraModule() may be called from any thread; a device or writer is used by one thread.
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>

namespace th::tracking {

class CameraDevice {
 public:
  virtual ~CameraDevice() = default;
  virtual bool grab() = 0;                    // the next picture, kept in the device (false: the camera is gone)
  virtual bool retrieve(cv::Mat& frame) = 0;  // the picture grabbed, as 8-bit BGR
};

class TakeVideoWriter {
 public:
  virtual ~TakeVideoWriter() = default;
  virtual void write(const cv::Mat& frame) = 0;
  virtual void finish() = 0;  // the file complete and closed
};

struct CameraModule {
  // /dev/videoN asked for this size and rate; null where it cannot be opened.
  std::unique_ptr<CameraDevice> (*openCamera)(int index, int width, int height, double framesPerSecond) = nullptr;
  // Motion-JPEG in an AVI at `path`; null where it cannot be written.
  std::unique_ptr<TakeVideoWriter> (*openWriter)(const std::filesystem::path& path, double framesPerSecond,
                                                 cv::Size size) = nullptr;
};

// The module's entry point, by this name (extern "C": found with dlsym).
#define TALKINGHEAD_CAMERA_MODULE_ENTRY "talkinghead_camera_module"
using CameraModuleEntry = const CameraModule* (*)();

// The module, opened once; th::Error naming where it looked when it cannot be opened.
const CameraModule& cameraModule();

}  // namespace th::tracking
