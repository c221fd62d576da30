// `talkinghead record DIR`: a take for training from video (`train --video DIR`), the webcam and the microphone
// together on one clock as NAME.avi and NAME.wav (tracking/take_recorder.h). Where there is no camera or no
// sound input, it says which in one line and writes nothing.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "core/error.h"
#include "interrupt.h"
#include "tracking/take_recorder.h"

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

void runRecord(const RecordArguments& arguments) {
  tracking::RecordingOptions options{.folder = arguments.folder,
                                     .name = arguments.name,
                                     .camera = arguments.camera,
                                     .seconds = arguments.seconds,
                                     .framesPerSecond = arguments.fps,
                                     .width = arguments.width,
                                     .height = arguments.height};
  if (arguments.device != "default") {
    try {
      options.soundDevice = std::stoi(arguments.device);
    } catch (const std::exception&) {
      throw Error("--device " + arguments.device + ": expected \"default\" or a device number (live --list-devices)");
    }
  }
  InterruptGuard guard;
  const tracking::RecordedTake take =
      tracking::recordTalkingVideo(options, InterruptGuard::requested, [&](const tracking::RecordingStarted& start) {
        std::fprintf(stderr, "recording %dx%d at %.0f fps and %s at %.0f Hz into %s; %s\n", start.width, start.height,
                     start.framesPerSecond, start.soundDevice.c_str(), start.soundRateHz, start.take.c_str(),
                     arguments.seconds > 0.0 ? "until the time is up or Ctrl-C" : "Ctrl-C ends the take");
      });
  std::cout << "wrote " << take.video.string() << " (" << take.framesWritten << " frames, " << take.framesGrabbed
            << " from the camera) and " << take.sound.string() << " (" << take.soundSeconds
            << " s); stopped: " << take.stoppedBy << '\n';
  if (take.deviceLost) throw Error("record: " + take.stoppedBy + "; the take so far is kept");
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
