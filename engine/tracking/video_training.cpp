#include "tracking/video_training.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <system_error>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "core/text_files.h"
#include "face/fap.h"

namespace th::tracking {

bool isVideoName(const std::filesystem::path& path) {
  const std::string extension = lowercaseExtension(path);
  for (const char* known : {".mpg", ".mpeg", ".mp4", ".m4v", ".avi", ".mov", ".mkv", ".webm"})
    if (extension == known) return true;
  return false;
}

namespace {

bool upToDate(const std::filesystem::path& track, const std::filesystem::path& video) {
  std::error_code error;
  const auto trackTime = std::filesystem::last_write_time(track, error);
  if (error) return false;
  const auto videoTime = std::filesystem::last_write_time(video, error);
  return !error && trackTime >= videoTime;
}

double meanResidual(const Track& track) {
  double sum = 0.0;
  for (const TrackedFrame& frame : track.frames) sum += frame.fit.residualPixels;
  return track.frames.empty() ? 0.0 : sum / static_cast<double>(track.frames.size());
}

// What a track depends on besides its video: the tracker's version (raise it when tracking or fitting changes
// what they give) and the options.
constexpr int kTrackerVersion = 2;

std::string trackerStamp(const VideoCorpusOptions& options) {
  std::ostringstream stamp;
  stamp.precision(17);
  stamp << "talkinghead tracker " << kTrackerVersion << "\nfaps";
  for (int fap : options.fit.faps) stamp << ' ' << fap;
  stamp << "\nlandmarks";
  for (int landmark : options.fit.landmarks) stamp << ' ' << landmark;
  stamp << "\npriors " << options.fit.jawPrior << ' ' << options.fit.fapPrior << ' ' << options.fit.typicalFapRange
        << "\nfocal length " << options.fit.focalLengthPixels << "\nsmooth " << options.track.smooth << '\n';
  return stamp.str();
}

std::vector<int> sorted(std::vector<int> faps) {
  std::sort(faps.begin(), faps.end());
  return faps;
}

}  // namespace

std::filesystem::path trackFileName(const std::filesystem::path& video) {
  return video.filename().string() + ".csv";
}

std::filesystem::path clipSoundFile(const std::filesystem::path& video) {
  std::filesystem::path wav = video;
  wav.replace_extension(".wav");
  return wav;
}

audio::AudioClip readClipSound(const std::filesystem::path& video) {
  try {
    return audio::readMediaAudio(video);
  } catch (const Error& error) {
    const std::filesystem::path wav = clipSoundFile(video);
    std::error_code missing;
    if (!std::filesystem::is_regular_file(wav, missing))
      throw Error(std::string(error.what()) + ", and there is no " + wav.filename().string() + " beside it");
    return audio::readRecording(wav);
  }
}

std::vector<std::filesystem::path> listVideos(const std::filesystem::path& folder) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) throw fileError(folder, "is not a folder");
  std::vector<std::filesystem::path> videos;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error))
    if (entry.is_regular_file(error) && isVideoName(entry.path())) videos.push_back(entry.path());
  if (error) throw fileError(folder, "cannot be listed: " + error.message());
  if (videos.empty()) throw fileError(folder, "holds no videos (.mpg, .mpeg, .mp4, .m4v, .avi, .mov, .mkv, .webm)");
  std::sort(videos.begin(), videos.end());
  return videos;
}

animation::MouthRecording mouthRecordingOf(const Track& fittedTrack, std::span<const float> samples16k,
                                           double framesPerSecond, double soundLateSeconds, Eigen::MatrixXd* lipShape) {
  if (fittedTrack.fittedFaps.empty()) throw fileError(fittedTrack.video, "the track has no fitted FAPs");
  const std::vector<int> faps = sorted(fittedTrack.fittedFaps);
  const std::vector<TrackedFrame>& frames = fittedTrack.frames;
  animation::MouthRecording recording;
  recording.framesPerSecond = framesPerSecond;
  recording.speech = animation::speechFramesOf(samples16k);
  // Animation frame i shows time i / fps of the sound, the picture's i / fps − soundLateSeconds; the video's
  // frames end at the last frame's time (beyond either end of the picture, its first or last frame is held).
  const auto videoFrames =
      static_cast<Eigen::Index>(std::floor((frames.back().seconds + soundLateSeconds) * framesPerSecond + 1e-9)) + 1;
  const Eigen::Index count =
      std::max<Eigen::Index>(0, std::min<Eigen::Index>(videoFrames, recording.speech.numFrames()));
  recording.speech = recording.speech.middleFrames(0, count);
  recording.visual.resize(static_cast<Eigen::Index>(faps.size()), count);
  if (lipShape != nullptr) lipShape->resize(2, count);
  std::size_t after = 0;  // the first video frame at or after the time
  for (Eigen::Index i = 0; i < count; ++i) {
    const double seconds = static_cast<double>(i) / framesPerSecond - soundLateSeconds;
    while (after < frames.size() && frames[after].seconds < seconds) ++after;
    const std::size_t hi = std::min(after, frames.size() - 1);
    const std::size_t lo = after == 0 ? 0 : std::min(after - 1, frames.size() - 1);
    const double span = frames[hi].seconds - frames[lo].seconds;
    const double w = span > 0.0 ? std::clamp((seconds - frames[lo].seconds) / span, 0.0, 1.0) : 0.0;
    for (std::size_t k = 0; k < faps.size(); ++k) {
      const auto n = static_cast<std::size_t>(faps[k]);
      recording.visual(static_cast<Eigen::Index>(k), i) =
          (1.0 - w) * frames[lo].fit.faps[n] + w * frames[hi].fit.faps[n];
    }
    if (lipShape != nullptr) {
      (*lipShape)(0, i) = (1.0 - w) * mouthOpening(frames[lo].landmarks) + w * mouthOpening(frames[hi].landmarks);
      (*lipShape)(1, i) = (1.0 - w) * mouthWidth(frames[lo].landmarks) + w * mouthWidth(frames[hi].landmarks);
    }
  }
  return recording;
}

namespace {

Eigen::RowVectorXd standardisedChanges(const Eigen::RowVectorXd& values) {
  const Eigen::Index n = values.size();
  const Eigen::RowVectorXd changes = values.tail(n - 1) - values.head(n - 1);
  const double mean = changes.mean();
  const double spread = std::sqrt((changes.array() - mean).square().mean());
  return (changes.array() - mean) / std::max(spread, 1e-12);
}

}  // namespace

SoundOffset estimateSoundOffset(const Eigen::RowVectorXd& levelDb, const Eigen::RowVectorXd& jaw,
                                const Eigen::RowVectorXd& lipOpening, double framesPerSecond,
                                const SoundSyncOptions& options) {
  const Eigen::Index n = std::min({levelDb.size(), jaw.size(), lipOpening.size()});
  SoundOffset offset;
  if (static_cast<double>(n) < options.minSeconds * framesPerSecond || n < 4) return offset;
  const Eigen::RowVectorXd sound = standardisedChanges(levelDb.head(n));
  const Eigen::RowVectorXd mouth = standardisedChanges(jaw.head(n)) + standardisedChanges(lipOpening.head(n));
  const int maxLag = std::max(1, static_cast<int>(std::lround(options.maxLagSeconds * framesPerSecond)));
  // r[lag]: the sound's change at t against the mouth's at t + lag (a negative lag: the mouth moves first).
  std::vector<double> r;
  for (int lag = -maxLag; lag <= maxLag; ++lag) {
    const Eigen::Index first = std::max(0, -lag), last = std::min<Eigen::Index>(sound.size(), sound.size() - lag);
    const Eigen::RowVectorXd a = sound.segment(first, last - first);
    const Eigen::RowVectorXd b = mouth.segment(first + lag, last - first);
    const Eigen::RowVectorXd ca = a.array() - a.mean(), cb = b.array() - b.mean();
    r.push_back(ca.dot(cb) / std::sqrt(std::max(ca.squaredNorm() * cb.squaredNorm(), 1e-300)));
  }
  const auto peak = static_cast<std::size_t>(std::max_element(r.begin(), r.end()) - r.begin());
  double lag = static_cast<double>(peak) - maxLag;
  if (peak > 0 && peak + 1 < r.size()) {
    const double curvature = r[peak - 1] - 2.0 * r[peak] + r[peak + 1];
    if (curvature < 0.0) lag += 0.5 * (r[peak - 1] - r[peak + 1]) / curvature;
  }
  offset.measured = true;
  offset.correlation = r[peak];
  // The mouth ahead of the sound by more than its natural lead: the sound is late by the difference.
  offset.lateSeconds = -lag / framesPerSecond - options.naturalLeadSeconds;
  return offset;
}

std::vector<animation::MouthRecording> VideoCorpus::recordings() const {
  std::vector<animation::MouthRecording> all;
  all.reserve(clips.size());
  for (const VideoClip& clip : clips) all.push_back(clip.recording);
  return all;
}

namespace {

// One clip: its track (re-used from the track folder when `reuse` and it is up to date with the video, else made
// and fitted, and kept there), its sound, synchronised to the lips if asked, and the head's motion if asked.
VideoClip loadVideoClip(const std::filesystem::path& video, const face::FaceModel& face,
                        const VideoCorpusOptions& options, const std::vector<int>& faps, bool reuse) {
  VideoClip clip;
  clip.video = video;
  const std::filesystem::path cached =
      options.trackFolder.empty() ? std::filesystem::path() : options.trackFolder / trackFileName(video);
  std::optional<Track> track;
  if (reuse && upToDate(cached, video)) {
    track = readTrackCsv(cached);
    if (sorted(track->fittedFaps) != faps) track.reset();  // fitted with other FAPs: fit again
  }
  if (!track) {
    track = trackVideo(video, options.track);
    fitTrack(*track, face, options.fit);
    if (!cached.empty()) writeTrackCsv(cached, *track);
    clip.trackedNow = true;
  }
  track->video = video;
  const audio::AudioClip sound = readClipSound(video);
  clip.recording = mouthRecordingOf(*track, sound.samples, animation::kMouthFramesPerSecond, 0.0, &clip.lipShape);
  if (options.synchronise) {
    const auto jaw = std::find(faps.begin(), faps.end(), 3);
    if (jaw == faps.end()) throw fileError(video, "cannot be synchronised without the jaw (FAP 3) fitted");
    clip.soundOffset = estimateSoundOffset(clip.recording.speech.levelDb, clip.recording.visual.row(jaw - faps.begin()),
                                           clip.lipShape.row(0), animation::kMouthFramesPerSecond, options.sync);
    if (clip.soundOffset.lateSeconds != 0.0)
      clip.recording = mouthRecordingOf(*track, sound.samples, animation::kMouthFramesPerSecond,
                                        clip.soundOffset.lateSeconds, &clip.lipShape);
  }
  if (clip.recording.numFrames() < 2) throw fileError(video, "is shorter than two animation frames");
  if (options.heads) {
    try {
      clip.head = headRecordingOf(*track, sound.samples);
    } catch (const Error& error) {
      clip.headMissing = error.what();
    }
  }
  clip.meanResidualPixels = meanResidual(*track);
  clip.faceFoundShare = static_cast<double>(track->framesFound()) / static_cast<double>(track->frames.size());
  return clip;
}

}  // namespace

VideoCorpus loadVideoCorpus(const std::vector<std::filesystem::path>& videos, const face::FaceModel& face,
                            const VideoCorpusOptions& options, const std::function<void(int, int)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.trackFolder.empty()) {
    std::error_code error;
    std::filesystem::create_directories(options.trackFolder, error);
    if (!std::filesystem::is_directory(options.trackFolder, error))
      throw fileError(options.trackFolder, "is not a folder and cannot be made one");
  }
  const std::vector<int> faps = sorted(options.fit.faps);
  // Tracks made by another tracker, or fitted another way, are not re-used: the folder's stamp says how its
  // tracks were made.
  bool reuse = false;
  std::filesystem::path stampFile;
  std::string stamp;
  if (!options.trackFolder.empty()) {
    stampFile = options.trackFolder / "tracker.txt";
    stamp = trackerStamp(options);
    std::error_code missing;
    reuse = std::filesystem::is_regular_file(stampFile, missing) && readTextFile(stampFile, "tracker stamp") == stamp;
    // Stamped again only once this run's tracks are all written (an interrupted run leaves the folder unstamped).
    if (!reuse) std::filesystem::remove(stampFile, missing);
  }
  // Each slot is written by the one thread that takes its clip.
  std::vector<std::optional<VideoClip>> loaded(videos.size());
  std::vector<std::string> reasons(videos.size());
  std::mutex progressMutex;
  int done = 0;
  parallelFor(videos.size(), options.threads, [&](std::size_t i) {
    try {
      loaded[i] = loadVideoClip(videos[i], face, options, faps, reuse);
    } catch (const std::exception& error) {
      reasons[i] = error.what();
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(progressMutex);
      progress(++done, static_cast<int>(videos.size()));
    }
  });
  if (!stampFile.empty() && !reuse &&
      std::any_of(loaded.begin(), loaded.end(), [](const auto& clip) { return clip.has_value(); })) {
    AtomicFile out(stampFile);
    out.stream() << stamp;
    out.commit();
  }
  VideoCorpus corpus;
  corpus.faps = faps;
  for (std::size_t i = 0; i < videos.size(); ++i) {
    if (loaded[i])
      corpus.clips.push_back(std::move(*loaded[i]));
    else
      corpus.skipped.push_back({videos[i], reasons[i]});
  }
  if (corpus.clips.empty())
    throw Error("no clip could be used" +
                (corpus.skipped.empty() ? std::string() : "; the first: " + corpus.skipped.front().reason));
  corpus.trackingSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return corpus;
}

animation::MouthModel trainVideoMouthModel(const std::vector<animation::MouthRecording>& recordings,
                                           const std::vector<int>& faps, animation::MouthModelOptions options) {
  for (const animation::MouthRecording& recording : recordings)
    if (recording.visual.rows() != static_cast<Eigen::Index>(faps.size()))
      throw Error("video mouth model: a recording has " + std::to_string(recording.visual.rows()) +
                  " visual rows, not " + std::to_string(faps.size()) + " FAPs");
  options.standardiseVisual = false;
  animation::MouthModel model = animation::trainMouthModel(recordings, options);
  model.visualFaps = faps;
  return model;
}

animation::HeadRecording headRecordingOf(const Track& fittedTrack, std::span<const float> samples16k) {
  if (fittedTrack.fittedFaps.empty()) throw Error(fittedTrack.video.string() + ": the track has no fitted head");
  const int found = fittedTrack.framesFound();
  const auto frames = static_cast<Eigen::Index>(fittedTrack.frames.size());
  if (2 * found < frames) {
    throw fileError(fittedTrack.video, "the face was found in " + std::to_string(found) + " of its " +
                                           std::to_string(frames) + " frames; a head style needs it in most");
  }
  // FAPs 48-50, the head's pitch, yaw and roll in angle units, as degrees (track.h's pitch_deg ...).
  constexpr double kDegreesPerUnit = face::kAngleUnit * 180.0 / 3.14159265358979323846;
  Eigen::MatrixXd rotations(3, frames);
  for (Eigen::Index f = 0; f < frames; ++f) {
    for (int axis = 0; axis < 3; ++axis)
      rotations(axis, f) =
          fittedTrack.frames[static_cast<size_t>(f)].fit.faps[static_cast<size_t>(48 + axis)] * kDegreesPerUnit;
  }
  animation::HeadRecording take = animation::headRecordingOf(rotations, fittedTrack.framesPerSecond, samples16k,
                                                             fittedTrack.video.filename().string());
  return take;
}

}  // namespace th::tracking
