// `talkinghead track VIDEO -o TRACK.csv`: the face's 68 landmarks in every frame of a talking video, the face
// model fitted to them (head rotation, jaw and lip FAPs), and the video's sound as a WAV beside the track
// (engine/tracking).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "face/face_model.h"
#include "tracking/track.h"
#include "tracking/video_training.h"

namespace th::app {
namespace {

struct TrackArguments {
  std::string video;
  std::string output;
  std::string audio;  // empty: the track's name with .wav
  bool noSmooth = false;
};

void runTrack(const TrackArguments& arguments) {
  const std::filesystem::path output = arguments.output;
  if (output.extension() != ".csv") throw fileError(output, "the track is written as CSV: give a .csv name");
  const std::filesystem::path audioPath = arguments.audio.empty()
                                              ? std::filesystem::path(output).replace_extension(".wav")
                                              : std::filesystem::path(arguments.audio);
  if (audioPath == output) throw fileError(audioPath, "the sound and the track cannot be the same file");
  checkOutputTarget(output);
  checkOutputTarget(audioPath);
  std::error_code noSuchFile;
  if (std::filesystem::equivalent(audioPath, tracking::clipSoundFile(arguments.video), noSuchFile))
    throw fileError(
        audioPath, "is the video's own sound; write the track's sound elsewhere (--audio) or name the track otherwise");

  // The sound first: a video without it (and without a WAV of its name beside it) is refused before the
  // (longer) tracking.
  const audio::AudioClip sound = tracking::readClipSound(arguments.video);
  const auto started = std::chrono::steady_clock::now();
  tracking::TrackOptions trackOptions;
  trackOptions.smooth = !arguments.noSmooth;
  // The sound's length stands for the video's (containers do not always say how many frames they hold).
  ProgressBar bar(static_cast<double>(sound.samples.size()) / sound.sampleRateHz, "track", std::cerr);
  tracking::Track track = tracking::trackVideo(arguments.video, trackOptions, [&](double done) { bar.update(done); });
  bar.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const face::FaceModel face = face::FaceModel::buildDefault();
  const auto fitStarted = std::chrono::steady_clock::now();
  tracking::fitTrack(track, face);
  const double fitSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fitStarted).count();
  double residual = 0.0;
  for (const tracking::TrackedFrame& frame : track.frames)
    residual += frame.fit.residualPixels / static_cast<double>(track.frames.size());

  audio::writeWav16(audioPath, sound.samples, sound.sampleRateHz);
  try {
    tracking::writeTrackCsv(output, track);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(audioPath, ignored);  // both or neither
    throw;
  }
  std::cout << "wrote " << output.string() << ": " << track.frames.size() << " frames at " << track.framesPerSecond
            << " fps, the face found in " << track.framesFound() << " (searched for in the whole frame "
            << track.fullSearches << " times), " << static_cast<double>(track.frames.size()) / seconds
            << " frames a second; the face model fitted at " << static_cast<double>(track.frames.size()) / fitSeconds
            << " frames a second, " << residual << " px from the landmarks (mean; rest face: frame "
            << track.neutralFrame << "); the sound in " << audioPath.string() << " (" << sound.sampleRateHz << " Hz, "
            << static_cast<double>(sound.samples.size()) / sound.sampleRateHz << " s)\n";
}

}  // namespace

void addTrackCommand(CLI::App& app) {
  auto arguments = std::make_shared<TrackArguments>();
  CLI::App* track = app.add_subcommand(
      "track",
      "Talking video -> per frame the head's rotation, jaw and lip FAPs and the 68 landmarks (dlib) as CSV; its "
      "sound as WAV");
  track
      ->add_option("video", arguments->video,
                   "Video: MPEG-1/2, MP4, AVI, MKV, ... with a face, and a sound track or a WAV of its name beside it")
      ->required();
  track
      ->add_option(
          "-o,--output", arguments->output,
          "Track: .csv (time_s, face, pitch_deg, yaw_deg, roll_deg, fapN..., residual_px, x0, y0 ... x67, y67)")
      ->required();
  track->add_option("--audio", arguments->audio, "The sound as WAV (default: the track's name with .wav)");
  track->add_flag("--no-smooth", arguments->noSmooth,
                  "Landmarks as dlib gave them in each frame, and the model fitted to those (default: each landmark's "
                  "path smoothed over 5 frames, Savitzky-Golay)");
  track->callback([arguments] { runTrack(*arguments); });
}

}  // namespace th::app
