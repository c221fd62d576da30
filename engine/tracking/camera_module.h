// The webcam, as `record` uses it (take_recorder.cpp): FFmpeg's Video4Linux2 input from libavdevice, which loads
// some eighty libraries of its own (libavfilter, SDL, Wayland, PulseAudio, JACK, OpenAL, FireWire) into any process
// linking it: so it lives in a module, libtalkinghead_camera.so, which cameraModule() opens the first time a take
// is recorded, and every other command starts without them.
//
//   const th::tracking::CameraModule& module = th::tracking::cameraModule();   // throws if it cannot be opened
//   std::unique_ptr<th::tracking::CameraDevice> camera = module.openCamera(0, 640, 480, 25.0);   // null: none
//
// The module is looked for beside the running program, in the installed tree's lib/talkinghead/ (from the
// program's bin/: ../lib/talkinghead/, or its multiarch lib folder), then where this build made it. Thread contract:
// cameraModule() may be called from any thread; a device is used by one thread.
#pragma once

#include <filesystem>
#include <memory>
#include <opencv2/core/mat.hpp>

namespace th::tracking {

class CameraDevice {
 public:
  virtual ~CameraDevice() = default;
  virtual bool grab() = 0;                    // the next picture, kept in the device (false: the camera is gone)
  virtual bool retrieve(cv::Mat& frame) = 0;  // the picture grabbed, as 8-bit BGR (a new image each call)
};

struct CameraModule {
  // /dev/videoN asked for this size and rate (the driver may give the nearest it has); null where it cannot be
  // opened.
  std::unique_ptr<CameraDevice> (*openCamera)(int index, int width, int height, double framesPerSecond) = nullptr;
};

// The module's entry point, by this name (extern "C": found with dlsym).
#define TALKINGHEAD_CAMERA_MODULE_ENTRY "talkinghead_camera_module"
using CameraModuleEntry = const CameraModule* (*)();

// The module, opened once; th::Error naming where it looked when it cannot be opened.
const CameraModule& cameraModule();

}  // namespace th::tracking
