#include "tracking/video_training.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <sstream>
#include <limits>
#include <mutex>
#include <optional>
#include <system_error>

#include "audio/audio_file.h"
#include "audio/media_audio.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel_for.h"
#include "core/text_files.h"
#include "animation/mouth_evaluation.h"

namespace th::tracking {

namespace {

bool isVideoName(const std::filesystem::path& path) {
  const std::string extension = lowercaseExtension(path);
  for (const char* known : {".mpg", ".mpeg", ".mp4", ".m4v", ".avi", ".mov", ".mkv", ".webm"})
    if (extension == known) return true;
  return false;
}

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

audio::AudioClip readClipSound(const std::filesystem::path& video) {
  try {
    return audio::readMediaAudio(video);
  } catch (const Error&) {
    std::filesystem::path wav = video;
    wav.replace_extension(".wav");
    std::error_code error;
    if (!std::filesystem::is_regular_file(wav, error)) throw;
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
                                           double framesPerSecond) {
  if (fittedTrack.fittedFaps.empty()) throw fileError(fittedTrack.video, "the track has no fitted FAPs");
  const std::vector<int> faps = sorted(fittedTrack.fittedFaps);
  const std::vector<TrackedFrame>& frames = fittedTrack.frames;
  animation::MouthRecording recording;
  recording.framesPerSecond = framesPerSecond;
  recording.mfcc = animation::mfccOf(samples16k);
  // Animation frame i shows time i / fps; the video's frames end at the last frame's time.
  const auto videoFrames = static_cast<Eigen::Index>(std::floor(frames.back().seconds * framesPerSecond + 1e-9)) + 1;
  const Eigen::Index count = std::min(videoFrames, recording.mfcc.cols());
  recording.mfcc.conservativeResize(Eigen::NoChange, count);
  recording.visual.resize(static_cast<Eigen::Index>(faps.size()), count);
  std::size_t after = 0;  // the first video frame at or after the time
  for (Eigen::Index i = 0; i < count; ++i) {
    const double seconds = static_cast<double>(i) / framesPerSecond;
    while (after < frames.size() && frames[after].seconds < seconds) ++after;
    const std::size_t hi = std::min(after, frames.size() - 1);
    const std::size_t lo = after == 0 ? 0 : std::min(after - 1, frames.size() - 1);
    const double span = frames[hi].seconds - frames[lo].seconds;
    const double w = span > 0.0 ? std::clamp((seconds - frames[lo].seconds) / span, 0.0, 1.0) : 0.0;
    for (std::size_t k = 0; k < faps.size(); ++k) {
      const auto n = static_cast<std::size_t>(faps[k]);
      recording.visual(static_cast<Eigen::Index>(k), i) = (1.0 - w) * frames[lo].fit.faps[n] + w * frames[hi].fit.faps[n];
    }
  }
  return recording;
}

std::vector<animation::MouthRecording> VideoCorpus::recordings() const {
  std::vector<animation::MouthRecording> all;
  all.reserve(clips.size());
  for (const VideoClip& clip : clips) all.push_back(clip.recording);
  return all;
}

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
    const std::filesystem::path& video = videos[i];
    try {
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
      clip.recording = mouthRecordingOf(*track, sound.samples);
      if (clip.recording.numFrames() < 2) throw fileError(video, "is shorter than two animation frames");
      clip.meanResidualPixels = meanResidual(*track);
      clip.faceFoundShare = static_cast<double>(track->framesFound()) / static_cast<double>(track->frames.size());
      loaded[i] = std::move(clip);
    } catch (const std::exception& error) {
      reasons[i] = error.what();
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(progressMutex);
      progress(++done, static_cast<int>(videos.size()));
    }
  });
  if (!stampFile.empty() && !reuse && std::any_of(loaded.begin(), loaded.end(), [](const auto& clip) { return clip.has_value(); })) {
    AtomicFile out(stampFile);
    out.stream() << stamp;
    out.commit();
  }
  VideoCorpus corpus;
  corpus.faps = faps;
  for (std::size_t i = 0; i < videos.size(); ++i) {
    if (loaded[i]) corpus.clips.push_back(std::move(*loaded[i]));
    else corpus.skipped.push_back({videos[i], reasons[i]});
  }
  if (corpus.clips.empty())
    throw Error("no clip could be used" + (corpus.skipped.empty() ? std::string() : "; the first: " + corpus.skipped.front().reason));
  corpus.trackingSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return corpus;
}

animation::MouthModel trainVideoMouthModel(const std::vector<animation::MouthRecording>& recordings,
                                           const std::vector<int>& faps, animation::MouthModelOptions options) {
  for (const animation::MouthRecording& recording : recordings)
    if (recording.visual.rows() != static_cast<Eigen::Index>(faps.size()))
      throw Error("video mouth model: a recording has " + std::to_string(recording.visual.rows()) + " visual rows, not " +
                  std::to_string(faps.size()) + " FAPs");
  options.standardiseVisual = false;
  animation::MouthModel model = animation::trainMouthModel(recordings, options);
  model.visualFaps = faps;
  return model;
}

}  // namespace th::tracking

namespace th::tracking {

FapScores scoreFaps(const std::vector<Eigen::MatrixXd>& estimates, const std::vector<int>& estimateFaps,
                    const std::vector<animation::MouthRecording>& truth, const std::vector<int>& truthFaps) {
  if (estimates.size() != truth.size()) throw Error("scoreFaps: as many estimates as clips are needed");
  std::vector<std::pair<Eigen::Index, Eigen::Index>> rows;  // estimate row, truth row, of each FAP both hold
  Eigen::Index jawRow = -1;
  for (std::size_t e = 0; e < estimateFaps.size(); ++e)
    for (std::size_t t = 0; t < truthFaps.size(); ++t)
      if (estimateFaps[e] == truthFaps[t]) {
        if (estimateFaps[e] == 3) jawRow = static_cast<Eigen::Index>(rows.size());
        rows.emplace_back(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(t));
      }
  if (rows.empty()) throw Error("scoreFaps: the estimate and the truth have no FAP in common");
  Eigen::Index frames = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) frames += std::min(estimates[i].cols(), truth[i].visual.cols());
  Eigen::MatrixXd estimate(static_cast<Eigen::Index>(rows.size()), frames);
  Eigen::MatrixXd actual(static_cast<Eigen::Index>(rows.size()), frames);
  Eigen::Index column = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Eigen::Index n = std::min(estimates[i].cols(), truth[i].visual.cols());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      estimate.row(static_cast<Eigen::Index>(r)).segment(column, n) = estimates[i].row(rows[r].first).head(n);
      actual.row(static_cast<Eigen::Index>(r)).segment(column, n) = truth[i].visual.row(rows[r].second).head(n);
    }
    column += n;
  }
  FapScores scores;
  scores.faps = static_cast<int>(rows.size());
  scores.frames = static_cast<int>(frames);
  scores.epsilon = animation::averageMse(estimate, actual);
  scores.rho = animation::averageCorrelation(estimate, actual);
  scores.jawEpsilon = scores.jawRho = std::numeric_limits<double>::quiet_NaN();
  if (jawRow >= 0) {
    scores.jawEpsilon = animation::averageMse(estimate.row(jawRow), actual.row(jawRow));
    scores.jawRho = animation::averageCorrelation(estimate.row(jawRow), actual.row(jawRow));
  }
  return scores;
}

std::vector<Eigen::MatrixXd> predictFaps(const animation::MouthModel& model,
                                         const std::vector<animation::MouthRecording>& clips,
                                         const animation::MouthSynthesisOptions& options, int audioShift) {
  std::vector<Eigen::MatrixXd> estimates;
  const auto n = static_cast<int>(clips.size());
  for (int i = 0; i < n; ++i) {
    const animation::MouthRecording& source = clips[static_cast<std::size_t>(((i + audioShift) % n + n) % n)];
    estimates.push_back(animation::mouthFapsOf(model, animation::synthesiseMouth(model, source.mfcc, options)));
  }
  return estimates;
}

}  // namespace th::tracking
