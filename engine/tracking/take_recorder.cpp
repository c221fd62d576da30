#include "tracking/take_recorder.h"

#include <chrono>
#include <ctime>
#include <memory>
#include <system_error>
#include <vector>

#include "audio/audio_file.h"
#include "audio/capture.h"
#include "audio/resampler.h"
#include "core/audio_ring.h"
#include "core/error.h"
#include "tracking/camera_module.h"
#include "tracking/mjpeg_writer.h"

namespace th::tracking {
namespace {

constexpr double kTakeRateHz = 16000.0;

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

struct Devices {
  std::unique_ptr<CameraDevice> camera;
  std::unique_ptr<audio::PortAudioSystem> sound;
};

// Both devices are looked for before anything is written; a missing one is named with the other.
Devices openDevices(const RecordingOptions& options) {
  std::string missing;
  const CameraModule* module = nullptr;
  try {
    module = &cameraModule();
  } catch (const Error& noModule) {
    throw Error(std::string("record: ") + noModule.what());
  }
  Devices devices;
  devices.camera = module->openCamera(options.camera, options.width, options.height, options.framesPerSecond);
  if (!devices.camera)
    missing = "no camera (/dev/video" + std::to_string(options.camera) + " cannot be opened; --camera picks another)";
  try {
    devices.sound = std::make_unique<audio::PortAudioSystem>();
    if (!options.soundDevice && !devices.sound->defaultInput())
      throw Error("no sound input (a microphone; live --list-devices lists them)");
    (void)audio::captureRateFor(*devices.sound, options.soundDevice, kTakeRateHz);
  } catch (const Error& noInput) {
    missing += (missing.empty() ? "" : ", and ") + std::string(noInput.what());
  }
  if (!missing.empty()) throw Error("record: " + missing);
  return devices;
}

// Frames at the take's rate, each the latest the camera gave, and the sound, until something stops the take
// (take.stoppedBy says what). `shown`: the first frame grabbed.
void grabUntilStopped(CameraDevice& camera, MjpegWriter& writer, const audio::Capture& microphone,
                      const RecordingOptions& options, const std::function<bool()>& stopRequested, cv::Mat shown,
                      const std::function<void()>& takeSound, RecordedTake& take) {
  const std::int64_t startNs = nowNs();
  const double periodNs = 1e9 / options.framesPerSecond;
  std::string& stoppedBy = take.stoppedBy;
  while (stoppedBy.empty()) {
    if (!camera.grab()) {
      stoppedBy = "the camera went away";
      break;
    }
    const std::int64_t grabbedNs = nowNs();
    ++take.framesGrabbed;
    // Every output frame due before this grab shows the frame before it.
    while (static_cast<double>(startNs) + static_cast<double>(take.framesWritten) * periodNs <
           static_cast<double>(grabbedNs)) {
      writer.write(shown);
      ++take.framesWritten;
    }
    camera.retrieve(shown);
    takeSound();
    if (!microphone.active()) stoppedBy = "the sound input went away";
    if (stopRequested && stopRequested()) stoppedBy = "interrupted";
    if (options.seconds > 0.0 && static_cast<double>(grabbedNs - startNs) >= options.seconds * 1e9)
      stoppedBy = "the duration was reached";
  }
}

}  // namespace

RecordedTake recordTalkingVideo(const RecordingOptions& options, const std::function<bool()>& stopRequested,
                                const std::function<void(const RecordingStarted&)>& onStart) {
  const std::filesystem::path& folder = options.folder;
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) throw fileError(folder, "is not a folder (make it first)");
  const std::string name = options.name.empty() ? takeName() : options.name;
  RecordedTake take;
  take.video = folder / (name + ".avi");
  take.sound = folder / (name + ".wav");
  for (const auto& path : {take.video, take.sound})
    if (std::filesystem::exists(path, error)) throw fileError(path, "exists already (give another --name)");

  Devices devices = openDevices(options);
  std::unique_ptr<CameraDevice>& camera = devices.camera;

  cv::Mat frame;
  if (!camera->grab() || !camera->retrieve(frame)) throw Error("record: the camera gives no picture");
  const cv::Size size = frame.size();

  // Hidden names until the take is complete.
  const std::filesystem::path partialVideo = folder / ("." + name + ".avi.partial");
  struct Cleanup {
    std::filesystem::path path;
    bool keep = false;
    ~Cleanup() {
      std::error_code ignored;
      if (!keep) std::filesystem::remove(path, ignored);
    }
  } cleanup{partialVideo};
  std::unique_ptr<MjpegWriter> writer;
  try {
    writer = std::make_unique<MjpegWriter>(partialVideo, options.framesPerSecond, size.width, size.height);
  } catch (const Error& unwritable) {
    throw fileError(take.video, std::string("cannot be written (") + unwritable.what() + ")");
  }

  AudioRing ring(static_cast<std::size_t>(kTakeRateHz) * 10);
  audio::Capture microphone(*devices.sound, options.soundDevice, kTakeRateHz, ring);
  const double rate = microphone.rateHz();
  if (onStart)
    onStart({.width = size.width,
             .height = size.height,
             .framesPerSecond = options.framesPerSecond,
             .soundDevice = microphone.device().name,
             .soundRateHz = rate,
             .take = folder / name});
  // The take starts now: the sound the device delivered before is dropped.
  std::vector<float> sound, block(4096);
  while (ring.read(block.data(), block.size()) > 0) {
  }
  const auto takeSound = [&] {
    for (std::size_t got; (got = ring.read(block.data(), block.size())) > 0;)
      sound.insert(sound.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(got));
  };
  grabUntilStopped(*camera, *writer, microphone, options, stopRequested, frame.clone(), takeSound, take);
  takeSound();
  writer->finish();
  if (take.framesWritten < 2 || sound.empty())
    throw Error("record: " + take.stoppedBy + " before anything was recorded");
  // A device that would not run at 16 kHz ran at its own rate (Capture); the take is kept at 16 kHz.
  const std::vector<float> sound16k = rate == kTakeRateHz ? sound : audio::resample(sound, rate, kTakeRateHz);
  audio::writeWav16(take.sound, sound16k, static_cast<int>(kTakeRateHz));
  std::filesystem::rename(partialVideo, take.video, error);
  if (error) {
    std::filesystem::remove(take.sound, error);
    throw fileError(take.video, "cannot be written: " + error.message());
  }
  cleanup.keep = true;
  take.soundSeconds = static_cast<double>(sound16k.size()) / kTakeRateHz;
  take.deviceLost = take.stoppedBy.find("went away") != std::string::npos;
  return take;
}

}  // namespace th::tracking
