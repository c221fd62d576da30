#include "pipeline/recording_export.h"

#include <atomic>
#include <future>
#include <utility>

#include "animation/idle_motion.h"
#include "audio/media_audio.h"
#include "core/error.h"
#include "formats/animation_format.h"
#include "formats/mp4_writer.h"
#include "pipeline/offline.h"

namespace th::pipeline {

void addIdleIfMissing(face::FapTrack& animation, const IdleOptions& idle) {
  if (!idle.idle || animation.rowOf(19) >= 0 || animation.rowOf(20) >= 0) return;
  animation::addIdleMotion(animation, Eigen::RowVectorXd(), idle.motionOptions(), {});
}

RecordingExportResult exportRecording(const RecordingExport& job, const RecordingExportHooks& hooks) {
  const auto stopIfCancelled = [&] {
    if (hooks.cancelled && hooks.cancelled()) throw Cancelled();
  };
  stopIfCancelled();
  // The face model (about 0.2 s) is built on another thread while the recording is read and animated.
  std::future<face::FaceModel> building =
      std::async(std::launch::async, [] { return face::FaceModel::buildDefault(); });
  RecordingExportResult result;
  audio::AudioClip clip;
  if (!job.animation.empty()) {
    clip = audio::readRecording(job.recording);
    result.animation = formats::readAnimation(job.animation);
    addIdleIfMissing(result.animation, job.idle);
  } else {
    const AnimateOptions options = animateOptionsOf(job.models, job.head, job.idle);
    result.animation = job.loadedModels ? animateRecording(job.recording, *job.loadedModels, options, &clip)
                                        : animateRecording(job.recording, loadModels(job.models), options, &clip);
  }
  if (clip.samples.empty()) throw fileError(job.recording, "has no samples");
  result.face = building.get();
  result.seconds = static_cast<double>(clip.samples.size()) / clip.sampleRateHz;

  // The encoder reports frames on its worker thread; the hooks hear of them on this one, before each frame is
  // rendered.
  std::atomic<int> encoded{0};
  int reported = 0;
  const auto frames =
      static_cast<int>(formats::videoFramesFor(clip.samples.size(), clip.sampleRateHz, job.video.framesPerSecond));
  const auto report = [&] {
    const int done = encoded.load();
    if (done == reported || !hooks.progress) return;
    reported = done;
    hooks.progress(done, frames);
  };
  result.videoFrames =
      exportVideo(result.face, result.animation, clip.samples, clip.sampleRateHz, job.output, job.video,
                  {.progress = [&](int done, int) { encoded.store(done); },
                   .check =
                       [&] {
                         report();
                         stopIfCancelled();
                       }});
  report();
  return result;
}

}  // namespace th::pipeline
