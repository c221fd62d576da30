// A talking face as a video file: an animation (FAP curves) played on the face model, or on the user's own
// character, rendered off-screen and encoded with its sound track as MP4 (H.264 + AAC). What `talkinghead export` and
// bench/export_bench run.
//
//   const th::face::FaceModel face = th::face::FaceModel::buildDefault();
//   th::pipeline::exportVideo(face, track, clip.samples, clip.sampleRateHz, "talk.mp4", {.width = 1280});
//
// Two threads: the calling one owns an OSMesa context and renders frame f + 1 while a worker finishes frame f
// (the backdrop under the head, FXAA, Y'CbCr) and encodes it (x264 in that thread on two cores, see
// encoderThreads). On llvmpipe every stage runs on the CPU: in one thread the cores would idle in turn.
// At most three frames are in flight (th::SlotQueue), so memory does not grow with the length.
//
// The video has as many frames as cover the sound (formats::videoFramesFor): the two end within one frame of
// each other. All or nothing: the file appears only when complete (formats::Mp4Writer); an exception from
// either thread, or from `hooks.check` (an interrupt), stops both threads and leaves no file.
// Thread contract: call from one thread; the hooks run on the worker thread (progress) and the calling
// thread (check).
#pragma once

#include <filesystem>
#include <functional>
#include <span>
#include <string>

#include "avatar/avatar_model.h"
#include "face/face_model.h"
#include "face/fap_track.h"

namespace th::pipeline {

struct VideoExportOptions {
  int width = 1280;
  int height = 720;
  double framesPerSecond = 30.0;
  int crf = 20;                     // x264 quality (see formats::Mp4Options)
  std::string preset = "veryfast";  // x264 speed/size trade-off
  // Over the preset: sub-pixel motion refinement 1 instead of veryfast's 2 saves export CPU for files a little
  // larger at the same quality setting; superfast would save as much for files far larger (docs/results.md,
  // "Figures behind choices in the code").
  std::string x264Params = "subme=1";
  // x264's threads. 0: one on a machine of up to two cores, else FFmpeg's choice (1.5 per core). On two
  // cores the renderer (its GL thread and llvmpipe's) already keeps both busy, and x264's frame threads only
  // add contention: encoding in the finishing thread alone made the whole export faster, with the same output
  // size (docs/results.md, "Figures behind choices in the code").
  int encoderThreads = 0;
  // Draw this character (avatar/avatar_model.h) instead of our face, posed by the same frames; null: our face.
  const avatar::Avatar* avatar = nullptr;
};

struct VideoExportHooks {
  std::function<void(int framesDone, int framesTotal)> progress;  // after each frame is encoded (worker thread)
  std::function<void()> check;  // before each frame is rendered (calling thread); throw to stop
};

// Renders `animation` on `face` with `samples` (mono, sampleRateHz) as its sound into `output` (.mp4).
// Returns the number of video frames. Throws th::Error (naming `output` for file problems).
int exportVideo(const face::FaceModel& face, const face::FapTrack& animation, std::span<const float> samples,
                int sampleRateHz, const std::filesystem::path& output, const VideoExportOptions& options,
                const VideoExportHooks& hooks = {});

}  // namespace th::pipeline
