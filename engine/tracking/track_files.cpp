#include "tracking/track_files.h"

#include <chrono>
#include <filesystem>
#include <system_error>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "face/face_model.h"
#include "tracking/track.h"
#include "tracking/video_training.h"

namespace th::tracking {

void writeTrackFiles(const TrackFiles& request, std::ostream& out, std::ostream& log) {
  const std::filesystem::path output = request.output;
  if (output.extension() != ".csv") throw fileError(output, "the track is written as CSV: give a .csv name");
  const std::filesystem::path audioPath = request.audio.empty()
                                              ? std::filesystem::path(output).replace_extension(".wav")
                                              : std::filesystem::path(request.audio);
  if (audioPath == output) throw fileError(audioPath, "the sound and the track cannot be the same file");
  checkOutputTarget(output);
  checkOutputTarget(audioPath);
  std::error_code noSuchFile;
  if (std::filesystem::equivalent(audioPath, clipSoundFile(request.video), noSuchFile))
    throw fileError(
        audioPath, "is the video's own sound; write the track's sound elsewhere (--audio) or name the track otherwise");

  // The sound first: a video without it (and without a WAV of its name beside it) is refused before the
  // (longer) tracking.
  const audio::AudioClip sound = readClipSound(request.video);
  const auto started = std::chrono::steady_clock::now();
  TrackOptions trackOptions;
  trackOptions.smooth = request.smooth;
  // The sound's length stands for the video's (containers do not always say how many frames they hold).
  ProgressBar bar(static_cast<double>(sound.samples.size()) / sound.sampleRateHz, "track", log);
  Track track = trackVideo(request.video, trackOptions, [&](double done) { bar.update(done); });
  bar.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const face::FaceModel face = face::FaceModel::buildDefault();
  const auto fitStarted = std::chrono::steady_clock::now();
  fitTrack(track, face);
  const double fitSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - fitStarted).count();
  double residual = 0.0;
  for (const TrackedFrame& frame : track.frames)
    residual += frame.fit.residualPixels / static_cast<double>(track.frames.size());

  audio::writeWav16(audioPath, sound.samples, sound.sampleRateHz);
  try {
    writeTrackCsv(output, track);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(audioPath, ignored);  // both or neither
    throw;
  }
  out << "wrote " << output.string() << ": " << track.frames.size() << " frames at " << track.framesPerSecond
      << " fps, the face found in " << track.framesFound() << " (searched for in the whole frame " << track.fullSearches
      << " times), " << static_cast<double>(track.frames.size()) / seconds
      << " frames a second; the face model fitted at " << static_cast<double>(track.frames.size()) / fitSeconds
      << " frames a second, " << residual << " px from the landmarks (mean; rest face: frame " << track.neutralFrame
      << "); the sound in " << audioPath.string() << " (" << sound.sampleRateHz << " Hz, "
      << static_cast<double>(sound.samples.size()) / sound.sampleRateHz << " s)\n";
}

}  // namespace th::tracking
