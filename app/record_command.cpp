// `talkinghead record DIR`: a take for training from video (`train --video DIR`) — the webcam (OpenCV) and
// the microphone (PortAudio) together, on one clock, as NAME.avi (Motion-JPEG, no sound) and NAME.wav beside
// it (16 kHz mono), which the trainer pairs by name.
//
// The shared clock is the steady clock. Sound sample 0 is the first sample the device delivers after the
// take starts, and sample k is at start + k / rate. Each camera frame is stamped when it is grabbed, and the
// video is written at a constant rate whose frame f shows the latest camera frame grabbed by start + f / fps
// (one is repeated when the camera lags, one dropped when it runs fast). Picture and sound therefore agree to
// within a frame plus the devices' own buffering, which they do not report.
// Where there is no camera or no sound input, it says which in one line and writes nothing.
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "audio/audio_file.h"
#include "audio/capture.h"
#include "audio/resampler.h"
#include "commands.h"
#include "core/audio_ring.h"
#include "core/error.h"
#include "interrupt.h"

namespace th::app {
namespace {

struct RecordArguments {
  std::string folder;
  std::string name;  // empty: take_YYYYMMDD_HHMMSS
  int camera = 0;
  std::string device = "default";
  double seconds = 0.0;  // 0: until Ctrl-C
  double fps = 25.0;
  int width = 640;
  int height = 480;
};

std::string takeName() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char text[32];
  std::strftime(text, sizeof text, "take_%Y%m%d_%H%M%S", &local);
  return text;
}

std::int64_t nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void runRecord(const RecordArguments& arguments) {
  const std::filesystem::path folder = arguments.folder;
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) throw fileError(folder, "is not a folder (make it first)");
  const std::string name = arguments.name.empty() ? takeName() : arguments.name;
  const std::filesystem::path videoPath = folder / (name + ".avi");
  const std::filesystem::path soundPath = folder / (name + ".wav");
  for (const auto& path : {videoPath, soundPath})
    if (std::filesystem::exists(path, error)) throw fileError(path, "exists already (give another --name)");

  // Both devices are looked for before anything is written; a missing one is named with the other.
  std::string missing;
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);  // our message is the one line
  cv::VideoCapture camera(arguments.camera, cv::CAP_V4L2);
  if (!camera.isOpened())
    missing = "no camera (/dev/video" + std::to_string(arguments.camera) + " cannot be opened; --camera picks another)";
  std::unique_ptr<audio::PortAudioSystem> system;
  std::optional<int> device;
  if (arguments.device != "default") {
    try {
      device = std::stoi(arguments.device);
    } catch (const std::exception&) {
      throw Error("--device " + arguments.device + ": expected \"default\" or a device number (live --list-devices)");
    }
  }
  try {
    system = std::make_unique<audio::PortAudioSystem>();
    if (!device && !system->defaultInput())
      throw Error("no sound input (a microphone; live --list-devices lists them)");
    (void)audio::captureRateFor(*system, device, 16000.0);
  } catch (const Error& noInput) {
    missing += (missing.empty() ? "" : ", and ") + std::string(noInput.what());
  }
  if (!missing.empty()) throw Error("record: " + missing);

  camera.set(cv::CAP_PROP_FRAME_WIDTH, arguments.width);
  camera.set(cv::CAP_PROP_FRAME_HEIGHT, arguments.height);
  camera.set(cv::CAP_PROP_FPS, arguments.fps);
  cv::Mat frame;
  if (!camera.read(frame) || frame.empty()) throw Error("record: the camera gives no picture");
  const cv::Size size = frame.size();

  // Hidden names until the take is complete.
  const std::filesystem::path partialVideo = folder / ("." + name + ".avi.partial");
  cv::VideoWriter writer(partialVideo.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'),
                         arguments.fps, size);
  if (!writer.isOpened()) throw fileError(videoPath, "cannot be written (Motion-JPEG through OpenCV)");
  struct Cleanup {
    std::filesystem::path path;
    bool keep = false;
    ~Cleanup() {
      std::error_code ignored;
      if (!keep) std::filesystem::remove(path, ignored);
    }
  } cleanup{partialVideo};

  AudioRing ring(16000 * 10);
  audio::Capture microphone(*system, device, 16000.0, ring);
  const double rate = microphone.rateHz();
  InterruptGuard guard;
  std::fprintf(stderr, "recording %dx%d at %.0f fps and %s at %.0f Hz into %s; %s\n", size.width, size.height,
               arguments.fps, microphone.device().name.c_str(), rate, (folder / name).c_str(),
               arguments.seconds > 0.0 ? "until the time is up or Ctrl-C" : "Ctrl-C ends the take");
  // The take starts now: the sound the device delivered before is dropped.
  std::vector<float> sound, block(4096);
  while (ring.read(block.data(), block.size()) > 0) {
  }
  const auto takeSound = [&] {
    for (std::size_t got; (got = ring.read(block.data(), block.size())) > 0;)
      sound.insert(sound.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(got));
  };
  const std::int64_t startNs = nowNs();
  const double periodNs = 1e9 / arguments.fps;
  cv::Mat shown = frame.clone();  // the latest camera frame grabbed
  std::int64_t written = 0, grabbed = 0;
  std::string stoppedBy;
  while (stoppedBy.empty()) {
    if (!camera.grab()) {
      stoppedBy = "the camera went away";
      break;
    }
    const std::int64_t grabbedNs = nowNs();
    ++grabbed;
    // Every output frame due before this grab shows the frame before it.
    while (static_cast<double>(startNs) + static_cast<double>(written) * periodNs < static_cast<double>(grabbedNs)) {
      writer.write(shown);
      ++written;
    }
    camera.retrieve(shown);
    takeSound();
    if (!microphone.active()) stoppedBy = "the sound input went away";
    if (InterruptGuard::requested()) stoppedBy = "interrupted";
    if (arguments.seconds > 0.0 && static_cast<double>(grabbedNs - startNs) >= arguments.seconds * 1e9)
      stoppedBy = "the duration was reached";
  }
  takeSound();
  writer.release();
  if (written < 2 || sound.empty()) throw Error("record: " + stoppedBy + " before anything was recorded");
  // A device that would not run at 16 kHz ran at its own rate (Capture); the take is kept at 16 kHz.
  const std::vector<float> sound16k = rate == 16000.0 ? sound : audio::resample(sound, rate, 16000.0);
  audio::writeWav16(soundPath, sound16k, 16000);
  std::filesystem::rename(partialVideo, videoPath, error);
  if (error) {
    std::filesystem::remove(soundPath, error);
    throw fileError(videoPath, "cannot be written: " + error.message());
  }
  cleanup.keep = true;
  std::cout << "wrote " << videoPath.string() << " (" << written << " frames, " << grabbed << " from the camera) and "
            << soundPath.string() << " (" << static_cast<double>(sound16k.size()) / 16000.0
            << " s); stopped: " << stoppedBy << '\n';
  if (stoppedBy.find("went away") != std::string::npos)
    throw Error("record: " + stoppedBy + "; the take so far is kept");
}

}  // namespace

void addRecordCommand(CLI::App& app) {
  auto arguments = std::make_shared<RecordArguments>();
  CLI::App* record =
      app.add_subcommand("record", "Webcam + microphone on one clock -> NAME.avi + NAME.wav, a take for train --video");
  record->add_option("folder", arguments->folder, "Folder for the take")->required();
  record->add_option("--name", arguments->name, "The take's name (default take_YYYYMMDD_HHMMSS)");
  record->add_option("--camera", arguments->camera, "Camera number (/dev/videoN)")
      ->check(CLI::Range(0, 63))
      ->capture_default_str();
  record->add_option("--device", arguments->device, "Sound input: default, or a number from live --list-devices")
      ->capture_default_str();
  record->add_option("--duration", arguments->seconds, "Seconds to record (default: until Ctrl-C)")
      ->check(CLI::Range(0.5, 36000.0));
  record->add_option("--fps", arguments->fps, "Video frames per second")
      ->check(CLI::Range(5.0, 60.0))
      ->capture_default_str();
  record->add_option("--width", arguments->width, "Camera width asked for")
      ->check(CLI::Range(160, 3840))
      ->capture_default_str();
  record->add_option("--height", arguments->height, "Camera height asked for")
      ->check(CLI::Range(120, 2160))
      ->capture_default_str();
  record->callback([arguments] { runRecord(*arguments); });
}

}  // namespace th::app
