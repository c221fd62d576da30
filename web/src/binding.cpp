// The engine's speech -> animation path for JavaScript (embind): what the web package's worklet and its
// offline animate() call. Models are read from the module's file system, where the package writes them
// (/models/, the names of the repository's models/).
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"

namespace {

using emscripten::val;

// The track as {framesPerSecond, faps: [numbers], values: Float64Array (frame-major: frame 0's FAPs first)}.
val trackObject(const th::face::FapTrack& track) {
  val out = val::object();
  out.set("framesPerSecond", track.framesPerSecond);
  val faps = val::array();
  for (const int fap : track.faps) faps.call<void>("push", fap);
  out.set("faps", faps);
  std::vector<double> frameMajor(static_cast<std::size_t>(track.values.size()));
  for (Eigen::Index t = 0; t < track.values.cols(); ++t)
    for (Eigen::Index r = 0; r < track.values.rows(); ++r)
      frameMajor[static_cast<std::size_t>(t * track.values.rows() + r)] = track.values(r, t);
  out.set("values", val::global("Float64Array").new_(val::array(frameMajor)));
  return out;
}

// 16 kHz mono samples -> the FAP track `talkinghead animate --online` makes of them with the shipped models.
val animateOnline(const val& samples) {
  const std::vector<float> pcm = emscripten::convertJSArrayToNumberVector<float>(samples);
  th::pipeline::ModelOptions models;
  th::pipeline::HeadMotionOptions head;
  th::pipeline::IdleOptions idle;
  th::pipeline::StreamingOptions streaming{.window = 30};
  const th::pipeline::AnimateOptions options = th::pipeline::animateOptionsOf(models, head, idle, &streaming);
  const th::pipeline::AnimationModels loaded = th::pipeline::loadModels(models);
  return trackObject(th::pipeline::animate(pcm, loaded, options));
}

}  // namespace

EMSCRIPTEN_BINDINGS(talkinghead) {
  emscripten::function("animateOnline", &animateOnline);
}
