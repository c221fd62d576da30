// The engine's speech -> animation path for JavaScript (embind): what the web package's worklet and its
// offline animate() call. Models are read from the module's file system, where the package writes them
// (/models/, the names of the repository's models/).
//
//   const decoder = new core.StreamDecoder('default', false);   // a live preset (pipeline/live_presets.h)
//   decoder.input().set(block);  decoder.accept(block.length);   // 16 kHz samples, through the module's memory
//   for (let frame; (frame = decoder.next()) !== null;) show(frame);
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "pipeline/live_decoder.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"

namespace {

using emscripten::val;

// A C++ exception reaches JavaScript as a bare pointer; errors are thrown to it as Error objects instead, with the
// engine's one-line message.
[[noreturn]] void throwToJavaScript(const std::exception& error) {
  val::global("Error").new_(std::string(error.what())).throw_();
}

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
val animateOnline(const val& samples) try {
  const std::vector<float> pcm = emscripten::convertJSArrayToNumberVector<float>(samples);
  th::pipeline::ModelOptions models;
  th::pipeline::HeadMotionOptions head;
  th::pipeline::IdleOptions idle;
  th::pipeline::StreamingOptions streaming{.window = 30};
  const th::pipeline::AnimateOptions options = th::pipeline::animateOptionsOf(models, head, idle, &streaming);
  const th::pipeline::AnimationModels loaded = th::pipeline::loadModels(models);
  return trackObject(th::pipeline::animate(pcm, loaded, options));
} catch (const std::exception& error) {
  throwToJavaScript(error);
}

// The live decoder with a preset's models and options, fed 16 kHz samples in blocks, frames out in order: what
// `talkinghead live` decodes (before its display adds the idle motion).
class StreamDecoder {
 public:
  StreamDecoder(const std::string& preset, bool waitForHead) try {
    th::pipeline::applyLivePreset(settings_, preset);
    settings_.live.waitForHead = waitForHead;
    settings_.check();
    models_ = th::pipeline::loadModels(settings_);
    decoder_ =
        std::make_unique<th::pipeline::LiveDecoder>(models_.head.get(), models_.mouth.get(), settings_.decoderOptions(),
                                                    models_.visemes.get(), models_.articulation.get());
    faps_ = decoder_->fapNumbers();
  } catch (const std::exception& error) {
    throwToJavaScript(error);
  }

  // The block JavaScript writes samples into (the module's memory: no copy, no allocation per block).
  val input() { return val(emscripten::typed_memory_view(block_.size(), block_.data())); }
  void accept(int count) {
    if (count < 0 || count > static_cast<int>(block_.size()))
      throwToJavaScript(th::Error("accept: a block holds at most " + std::to_string(block_.size()) + " samples"));
    decoder_->acceptWaveform(std::span<const float>(block_.data(), static_cast<std::size_t>(count)));
  }
  void finish() { decoder_->inputFinished(); }
  double lookaheadMs() const { return decoder_->lookahead().totalMs; }

  // The next frame, or null: {index, timeSeconds, faps: Float64Array (fapNumbers' order), mouthClass,
  // visemeProbabilities: Float32Array (17), headDegrees: [pitch, yaw, roll], levelDb}.
  val next() {
    th::pipeline::AnimationFrame frame;
    if (!decoder_->next(frame)) return val::null();
    val out = val::object();
    out.set("index", frame.index);
    out.set("timeSeconds", frame.timeSeconds);
    std::vector<double> values;
    values.reserve(faps_.size());
    for (const int fap : faps_) values.push_back(frame.faps[static_cast<std::size_t>(fap)]);
    out.set("faps", val::global("Float64Array").new_(val::array(values)));
    out.set("mouthClass", frame.mouthClass);
    out.set(
        "visemeProbabilities",
        val::global("Float32Array")
            .new_(val::array(std::vector<float>(frame.visemeProbabilities.begin(), frame.visemeProbabilities.end()))));
    val head = val::array();
    for (int axis = 0; axis < 3; ++axis) head.call<void>("push", frame.headDegrees[axis]);
    out.set("headDegrees", head);
    out.set("levelDb", frame.levelDb);
    return out;
  }
  val fapNumbers() const {
    val out = val::array();
    for (const int fap : faps_) out.call<void>("push", fap);
    return out;
  }

 private:
  th::pipeline::LiveSettings settings_;
  th::pipeline::AnimationModels models_;
  std::unique_ptr<th::pipeline::LiveDecoder> decoder_;
  std::vector<int> faps_;
  std::vector<float> block_ = std::vector<float>(4096);
};

}  // namespace

EMSCRIPTEN_BINDINGS(talkinghead) {
  emscripten::function("animateOnline", &animateOnline);
  emscripten::class_<StreamDecoder>("StreamDecoder")
      .constructor<std::string, bool>()
      .function("input", &StreamDecoder::input)
      .function("accept", &StreamDecoder::accept)
      .function("finish", &StreamDecoder::finish)
      .function("next", &StreamDecoder::next)
      .function("fapNumbers", &StreamDecoder::fapNumbers)
      .function("lookaheadMs", &StreamDecoder::lookaheadMs);
}
