// `talkinghead track VIDEO -o TRACK.csv`: the face's 68 landmarks in every frame of a talking video, the face
// model fitted to them (head rotation, jaw and lip FAPs), and the video's sound as a WAV beside the track
// (engine/tracking).
#include <iostream>
#include <memory>

#include "commands.h"
#include "tracking/track_files.h"

namespace th::app {
namespace {

struct TrackArguments {
  tracking::TrackFiles request;
  bool noSmooth = false;
};

}  // namespace

void addTrackCommand(CLI::App& app) {
  auto arguments = std::make_shared<TrackArguments>();
  CLI::App* track = app.add_subcommand(
      "track",
      "Talking video -> per frame the head's rotation, jaw and lip FAPs and the 68 landmarks (dlib) as CSV; its "
      "sound as WAV");
  track
      ->add_option("video", arguments->request.video,
                   "Video: MPEG-1/2, MP4, AVI, MKV, ... with a face, and a sound track or a WAV of its name beside it")
      ->required();
  track
      ->add_option(
          "-o,--output", arguments->request.output,
          "Track: .csv (time_s, face, pitch_deg, yaw_deg, roll_deg, fapN..., residual_px, x0, y0 ... x67, y67)")
      ->required();
  track->add_option("--audio", arguments->request.audio, "The sound as WAV (default: the track's name with .wav)");
  track->add_flag("--no-smooth", arguments->noSmooth,
                  "Landmarks as dlib gave them in each frame, and the model fitted to those (default: each landmark's "
                  "path smoothed over 5 frames, Savitzky-Golay)");
  track->callback([arguments] {
    tracking::TrackFiles request = arguments->request;
    request.smooth = !arguments->noSmooth;
    tracking::writeTrackFiles(request, std::cout, std::cerr);
  });
}

}  // namespace th::app
