// A take for training from video (`train --video DIR`): the webcam (OpenCV) and the microphone (PortAudio,
// audio/capture.h) recorded together on one clock, as NAME.avi (Motion-JPEG, no sound) and NAME.wav beside it
// (16 kHz mono), which the trainer pairs by name.
//
//   th::tracking::RecordingOptions options{.folder = "takes", .seconds = 30.0};
//   th::tracking::RecordedTake take = th::tracking::recordTalkingVideo(options, [] { return stopped(); });
//
// The shared clock is the steady clock. Sound sample 0 is the first sample the device delivers after the
// take starts, and sample k is at start + k / rate. Each camera frame is stamped when it is grabbed, and the
// video is written at a constant rate whose frame f shows the latest camera frame grabbed by start + f / fps
// (one is repeated when the camera lags, one dropped when it runs fast). Picture and sound therefore agree to
// within a frame plus the devices' own buffering, which they do not report.
//
// Errors are th::Error, thrown before anything is written: a folder that is not there, a take that exists
// already, and where there is no camera or no sound input, one message that names each missing device. The
// video is written under a hidden name and renamed when the take is complete, so a failed take leaves no
// files. Thread contract: one call records on the caller's thread; stopRequested is polled there.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace th::tracking {

struct RecordingOptions {
  std::filesystem::path folder{};    // must exist
  std::string name{};                // empty: take_YYYYMMDD_HHMMSS (local time)
  int camera = 0;                    // /dev/videoN
  std::optional<int> soundDevice{};  // a PortAudio input's index; empty: the default input
  double seconds = 0.0;              // 0: until stopRequested
  double framesPerSecond = 25.0;     // of the video written
  int width = 640;                   // asked of the camera
  int height = 480;
};

// What the take runs on, once both devices are open (before its first frame).
struct RecordingStarted {
  int width = 0;  // what the camera gives
  int height = 0;
  double framesPerSecond = 0.0;
  std::string soundDevice;
  double soundRateHz = 0.0;    // the device's (the take is kept at 16 kHz)
  std::filesystem::path take;  // folder / name, without an extension
};

struct RecordedTake {
  std::filesystem::path video;  // NAME.avi
  std::filesystem::path sound;  // NAME.wav, 16 kHz mono
  std::int64_t framesWritten = 0;
  std::int64_t framesGrabbed = 0;  // from the camera
  double soundSeconds = 0.0;
  // "interrupted", "the duration was reached", "the camera went away", "the sound input went away"
  std::string stoppedBy;
  bool deviceLost = false;  // a device went away: the take so far is kept
};

// Records until the duration is reached, stopRequested() says so, or a device goes away. Throws th::Error as
// above, and if a device went away (or the stop came) before two frames and some sound were recorded.
RecordedTake recordTalkingVideo(const RecordingOptions& options, const std::function<bool()>& stopRequested,
                                const std::function<void(const RecordingStarted&)>& onStart = {});

}  // namespace th::tracking
