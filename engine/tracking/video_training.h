// Training data from talking videos: each clip tracked and fitted (track.h), its jaw and lip FAPs resampled to
// the animation rate and paired with the MFCCs of its own sound, as the mouth model trains on them
// (animation/mouth_model.h, visual parameters = FAPs).
//
//   std::vector<std::filesystem::path> clips = th::tracking::listVideos("grid/s1");
//   th::tracking::VideoCorpus corpus = th::tracking::loadVideoCorpus(clips, faceModel, {.trackFolder = "tracks"});
//   th::animation::MouthModel model = th::tracking::trainVideoMouthModel(corpus.recordings(), {});
//
// A clip's sound is its own audio track, or, for a video without one, the WAV of the same name beside it (what
// `talkinghead record` and `talkinghead track --audio` write). Tracks are kept in trackFolder (one CSV per
// clip, trackFileName) and read back instead of tracking again while they are newer than their video and
// were made by this tracker with the same options (the folder's tracker.txt says how). A clip that cannot be used (no
// face, no sound, unreadable) is left out with its reason; the corpus fails only if no clip is left. Thread contract:
// loadVideoCorpus tracks clips on `threads` threads of its own; the face model is shared read-only; progress is called
// under a lock, from any of them.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "animation/head_data.h"
#include "animation/mouth_data.h"
#include "animation/mouth_model.h"
#include "audio/audio_file.h"
#include "face/face_model.h"
#include "tracking/face_fit.h"
#include "tracking/track.h"

namespace th::tracking {

// Whether a file's name is a video's, by its extension: .mpg .mpeg .mp4 .m4v .avi .mov .mkv .webm, any case.
bool isVideoName(const std::filesystem::path& path);

// The videos in a folder (not its sub-folders), by name (isVideoName). Throws th::Error naming the folder if it
// is missing or holds none.
std::vector<std::filesystem::path> listVideos(const std::filesystem::path& folder);

// A clip's sound at 16 kHz: its own audio track, else the WAV of its name beside it (clipSoundFile: a silent
// video and its separately recorded sound, as `record` writes and some corpora ship). Errors name the video.
audio::AudioClip readClipSound(const std::filesystem::path& video);
std::filesystem::path clipSoundFile(const std::filesystem::path& video);  // "a/b.mp4" -> "a/b.wav"

// The fitted FAPs of a track (track.fittedFaps, ascending) at `framesPerSecond` (linear between video frames,
// the ends held), paired with the speech frames of the clip's 16 kHz sound at the same rate; both cut to the
// shorter. With soundLateSeconds, the sound is taken to lag the picture by that much (a clip whose sound was
// put in late): animation frame i, at i / fps in the sound, pairs with the picture at i / fps − soundLateSeconds.
// `lipShape`, if given, receives the landmarks' inner-lip opening and mouth width (track.h's mouthOpening and
// mouthWidth; 2 x T) at the same times.
animation::MouthRecording mouthRecordingOf(const Track& fittedTrack, std::span<const float> samples16k,
                                           double framesPerSecond = 30.0, double soundLateSeconds = 0.0,
                                           Eigen::MatrixXd* lipShape = nullptr);

// The head's rotations of a fitted track (FAPs 48-50 as degrees) beside the prosody of the clip's 16 kHz sound, at
// 30 fps (animation::headRecordingOf): the person a head style is fitted to. Throws th::Error naming the video
// when the face was found in fewer than half of its frames.
animation::HeadRecording headRecordingOf(const Track& fittedTrack, std::span<const float> samples16k);

// How far a clip's sound lags its picture, estimated from the clip itself: the lag that best lines up the
// frame-to-frame changes of the sound's level with those of the mouth (the jaw FAP and the lip opening, each
// standardised), searched over ±maxLagSeconds and refined between frames (a parabola through the peak), less the
// lead the lips naturally have over the sound (naturalLeadSeconds: on GRID's speaker s1, whose sound and picture
// agree, the same measure peaks with the mouth a little ahead; `talkinghead eval mouth` prints it). Changes rather
// than levels: the slow rise and fall of a sentence would otherwise broaden the peak. Clips shorter than
// minSeconds are too short to say (on GRID's 3 s clips the estimate scatters widely: docs/results.md, "Mouth:
// the data and the demo") and count as in sync.
struct SoundSyncOptions {
  double maxLagSeconds = 0.3;
  double naturalLeadSeconds = 0.010;
  double minSeconds = 10.0;
};

struct SoundOffset {
  double lateSeconds = 0.0;  // the sound's lag behind the picture (negative: ahead); 0 when not measured
  double correlation = 0.0;  // of the changes at the peak
  bool measured = false;     // false: the clip was too short
};

// levelDb, jaw and lipOpening: the same frames at framesPerSecond, sound and picture taken as in sync.
SoundOffset estimateSoundOffset(const Eigen::RowVectorXd& levelDb, const Eigen::RowVectorXd& jaw,
                                const Eigen::RowVectorXd& lipOpening, double framesPerSecond,
                                const SoundSyncOptions& options = {});

struct VideoClip {
  std::filesystem::path video;
  animation::MouthRecording recording;  // visual rows: `faps` of the corpus
  Eigen::MatrixXd lipShape;             // 2 x T: the landmarks' inner-lip opening and mouth width, per frame
  SoundOffset soundOffset;              // taken out of the recording when the corpus was synchronised
  double meanResidualPixels = 0.0;
  double faceFoundShare = 0.0;  // of its frames
  bool trackedNow = false;      // false: its track was read from trackFolder
  // With VideoCorpusOptions::heads: the head's motion beside the prosody of the sound (headRecordingOf), or
  // why there is none (the clip's mouth is used all the same).
  std::optional<animation::HeadRecording> head;
  std::string headMissing;
};

struct SkippedClip {
  std::filesystem::path video;
  std::string reason;  // the one-line error
};

struct VideoCorpus {
  std::vector<int> faps;         // the visual rows of every recording
  std::vector<VideoClip> clips;  // in the order given, the skipped ones left out
  std::vector<SkippedClip> skipped;
  double trackingSeconds = 0.0;  // wall-clock time of the whole load
  std::vector<animation::MouthRecording> recordings() const;
};

// A clip's track file in trackFolder: its whole file name with ".csv" added ("a.mp4" -> "a.mp4.csv"), so clips
// that differ only in their extension keep tracks of their own.
std::filesystem::path trackFileName(const std::filesystem::path& video);

struct VideoCorpusOptions {
  std::filesystem::path trackFolder;  // empty: track every clip, keep nothing
  FitOptions fit{};
  TrackOptions track{};
  unsigned threads = 0;      // 0: the machine's cores
  bool synchronise = false;  // estimate each clip's sound offset (estimateSoundOffset) and take it out
  SoundSyncOptions sync{};
  bool heads = false;  // also each clip's head motion (VideoClip::head), for training the head model
};

// progress(clipsDone, clipsTotal) after each clip.
VideoCorpus loadVideoCorpus(const std::vector<std::filesystem::path>& videos, const face::FaceModel& face,
                            const VideoCorpusOptions& options = {}, const std::function<void(int, int)>& progress = {});

// The mouth model on FAP recordings: FAPs share one unit (FAPU counts), so they are not standardised before
// PCA (the lips' small, noisy FAPs would weigh as much as the jaw); the model's visualFaps name the rows.
animation::MouthModel trainVideoMouthModel(const std::vector<animation::MouthRecording>& recordings,
                                           const std::vector<int>& faps, animation::MouthModelOptions options);

}  // namespace th::tracking
