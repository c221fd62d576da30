#include "pipeline/video_export.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <thread>

#include "core/slot_queue.h"
#include "formats/mp4_writer.h"
#include "render/gl_context.h"
#include "render/head.h"

namespace th::pipeline {

using render::RawFrame;
using render::Yuv420Image;
namespace {

// Stops and joins the worker however the scope is left (an exception included).
class JoinOnExit {
 public:
  JoinOnExit(SlotQueue<RawFrame>& queue, std::thread& worker) : queue_(queue), worker_(worker) {}
  ~JoinOnExit() {
    queue_.abort();
    if (worker_.joinable()) worker_.join();
  }
  JoinOnExit(const JoinOnExit&) = delete;
  JoinOnExit& operator=(const JoinOnExit&) = delete;

 private:
  SlotQueue<RawFrame>& queue_;
  std::thread& worker_;
};

int encoderThreadsFor(const VideoExportOptions& options) {
  if (options.encoderThreads != 0) return options.encoderThreads;  // (Mp4Writer rejects a negative one)
  const unsigned cores = std::thread::hardware_concurrency();
  return cores != 0 && cores <= 2 ? 1 : 0;
}

}  // namespace

int exportVideo(const face::FaceModel& face, const face::FapTrack& animation, std::span<const float> samples,
                int sampleRateHz, const std::filesystem::path& output, const VideoExportOptions& options,
                const VideoExportHooks& hooks) {
  render::OffscreenContext context;
  // FXAA on one sample instead of 4x MSAA: a third of the CPU per frame on llvmpipe, nearly as smooth.
  const std::unique_ptr<render::Head> head = render::makeHead(
      options.avatar, context, {.width = options.width, .height = options.height, .samples = 1, .fxaa = true}, &face);
  formats::Mp4Writer writer(output, {.width = options.width,
                                     .height = options.height,
                                     .framesPerSecond = options.framesPerSecond,
                                     .audioSampleRateHz = sampleRateHz,
                                     .crf = options.crf,
                                     .preset = options.preset,
                                     .x264Params = options.x264Params,
                                     .threads = encoderThreadsFor(options)});
  const auto frames = static_cast<int>(formats::videoFramesFor(samples.size(), sampleRateHz, options.framesPerSecond));
  // The sound is encoded by the worker as the video reaches it (frame by frame), not all before the first
  // frame: then it costs no time of its own on two busy cores.
  const auto samplesUntil = [&](int videoFrames) {
    const double seconds = videoFrames / options.framesPerSecond;
    return std::min(samples.size(), static_cast<std::size_t>(std::ceil(seconds * sampleRateHz)));
  };

  SlotQueue<RawFrame> queue(3);
  std::exception_ptr workerError;
  std::thread worker([&] {
    try {
      Yuv420Image image;
      int done = 0;
      std::size_t audioDone = 0;
      while (RawFrame* raw = queue.takePublished()) {
        head->finish(*raw, image, writer.usesBt709());
        queue.release(raw);
        writer.addVideoFrame(image.planes());
        const std::size_t audioEnd = done + 1 == frames ? samples.size() : samplesUntil(done + 1);
        writer.addAudio(samples.subspan(audioDone, audioEnd - audioDone));
        audioDone = audioEnd;
        if (hooks.progress) hooks.progress(++done, frames);
      }
    } catch (...) {
      workerError = std::current_exception();
      queue.abort();
    }
  });
  {
    const JoinOnExit join(queue, worker);
    for (int frame = 0; frame < frames; ++frame) {
      if (hooks.check) hooks.check();
      RawFrame* raw = queue.takeFree();
      if (raw == nullptr) break;  // the worker failed: its error is rethrown below
      head->poseAt(animation, frame / options.framesPerSecond);
      head->render();
      head->readRaw(*raw);
      queue.publish(raw);
    }
    queue.close();
    worker.join();
  }
  if (workerError) std::rethrow_exception(workerError);
  if (hooks.check) hooks.check();
  writer.finish();
  return frames;
}

}  // namespace th::pipeline
