// A recording as a video of the face speaking it, the whole job: the sound read and animated with the models (or
// an animation given played instead), the face model built meanwhile, and the frames rendered on our face or the
// user's character and encoded (video_export.h). What `talkinghead export` and the C library's exports run.
//
//   th::pipeline::RecordingExport job{.recording = "speech.wav", .output = "talk.mp4"};
//   job.video.width = 640;
//   job.video.height = 360;
//   const th::pipeline::RecordingExportResult done =
//       th::pipeline::exportRecording(job, {.progress = [](int done, int total) { ... }});
//
// All or nothing: the file appears only when complete. A failure throws th::Error; `hooks.cancelled` returning
// true stops the job within a frame (or as soon as the animation is made) and throws th::Cancelled; either leaves
// no file.
// Thread contract: call from one thread; the hooks are called on it. The models are shared read-only.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>

#include "face/face_model.h"
#include "face/fap_track.h"
#include "pipeline/animation_models.h"
#include "pipeline/options.h"
#include "pipeline/video_export.h"

namespace th::pipeline {

struct RecordingExport {
  std::filesystem::path recording = {};  // any that audio/media_audio.h reads, a video's sound track included
  std::filesystem::path output = {};     // .mp4
  VideoExportOptions video = {};         // its size, rate and quality, and the character (null: our face)
  // The animation: this file's (its blinks and gaze added if it has none), else the models'.
  std::filesystem::path animation = {};
  ModelOptions models = {};
  HeadMotionOptions head = {};
  IdleOptions idle = {};
  // Models already loaded, used instead of loading the files `models` names (its variants still apply).
  std::shared_ptr<const AnimationModels> loadedModels = {};
};

struct RecordingExportHooks {
  std::function<void(int framesDone, int framesTotal)> progress = {};  // as frames are encoded, and once at the end
  std::function<bool()> cancelled = {};                                // true: stop (th::Cancelled)
};

struct RecordingExportResult {
  face::FapTrack animation;  // what was played
  face::FaceModel face;      // what it was played on (without a character)
  int videoFrames = 0;
  double seconds = 0.0;  // of the sound
};

RecordingExportResult exportRecording(const RecordingExport& job, const RecordingExportHooks& hooks = {});

// A file made elsewhere (or without idle motion) may lack blinks and gaze: they are added unless it has its own
// eyelids. With no sound to hear, the head stays as the file has it.
void addIdleIfMissing(face::FapTrack& animation, const IdleOptions& idle);

}  // namespace th::pipeline
