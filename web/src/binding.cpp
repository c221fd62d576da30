// The engine's speech -> animation path for JavaScript (embind): what the web package's worklet (LipSyncStream)
// and its animate() (animateSamples) call. Models are read from the module's file system, where the package
// writes them (/models/, the names of the repository's models/).
//
//   const stream = new core.LipSyncStream('default', 48000, false, true, 1);  // preset, rate, waitForHead, idle, seed
//   stream.input().set(block);  stream.accept(block.length);                  // through the module's memory
//   while (stream.next()) show(stream.record());                              // a Float64Array, frameLayout()'s
//
//   const animation = core.animateSamples(samples, 44100, 'default', true, 1); // offline, the same frames
//   for (let i = 0; i < animation.numFrames(); ++i) { animation.select(i); show(animation.record()); }
//   const csv = animation.write('arkit');                                      // the text native animate writes
//
// A frame's record (frameLayout() names the offsets): its time and index, the class shown, the level, Oculus's 15
// viseme weights, ARKit's 52, VRM's 5 vowels, the head's rotation as a quaternion (x, y, z, w) and as pitch, yaw
// and roll in degrees, the blinks and the gaze. One record, rewritten per frame: nothing is allocated per block.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "audio/sinc_resampler.h"
#include "core/error.h"
#include "formats/animation_format.h"
#include "formats/arkit_format.h"
#include "outputs/avatar_frame.h"
#include "outputs/live_display.h"
#include "pipeline/live_decoder.h"
#include "pipeline/offline.h"
#include "pipeline/options.h"

namespace {

using emscripten::val;

constexpr double kEngineRateHz = 16000.0;
using th::face::kDegreesPerAngleUnit;  // FAPs 23-26 (the eyes)

// A C++ exception reaches JavaScript as a bare pointer; errors are thrown to it as Error objects instead, with the
// engine's one-line message.
[[noreturn]] void throwToJavaScript(const std::exception& error) {
  val::global("Error").new_(std::string(error.what())).throw_();
}

// The record's layout: offsets into a Float64Array.
enum Offset : int {
  kTime = 0,
  kIndex = 1,
  kMouthClass = 2,
  kLevelDb = 3,
  kOculus = 4,                                     // 15
  kArkit = kOculus + th::face::kNumOculusVisemes,  // 52
  kVrm = kArkit + 52,                              // 5
  kHeadQuaternion = kVrm + 5,                      // x, y, z, w
  kHeadDegrees = kHeadQuaternion + 4,              // pitch, yaw, roll
  kBlink = kHeadDegrees + 3,                       // left, right
  kGaze = kBlink + 2,                              // yaw, pitch (degrees)
  kRecordSize = kGaze + 2,
};
using Record = std::array<double, kRecordSize>;

val frameLayout() {
  val out = val::object();
  const std::array<std::pair<const char*, int>, 12> offsets{{{"time", kTime},
                                                             {"index", kIndex},
                                                             {"mouthClass", kMouthClass},
                                                             {"levelDb", kLevelDb},
                                                             {"oculus", kOculus},
                                                             {"arkit", kArkit},
                                                             {"vrm", kVrm},
                                                             {"headQuaternion", kHeadQuaternion},
                                                             {"headDegrees", kHeadDegrees},
                                                             {"blink", kBlink},
                                                             {"gaze", kGaze},
                                                             {"size", kRecordSize}}};
  for (const auto& [name, offset] : offsets) out.set(name, offset);
  val names = val::object();
  const auto list = [](const auto& strings) {
    val array = val::array();
    for (const auto& s : strings) array.call<void>("push", std::string(s));
    return array;
  };
  names.set("oculus", list(th::face::kOculusVisemeNames));
  names.set("arkit", list(th::formats::kArkitNames));
  names.set("vrm", list(th::face::kVrmVowelNames));
  out.set("names", names);
  return out;
}

// A frame as the record: the avatar frame the live outputs send (outputs/avatar_frame.h), the head's rotation as
// the quaternion of R = Ry(yaw) Rx(pitch) Rz(roll) in glTF's axes (y up, z forward, x the character's left: the
// head's own, BEAT2's), and the eyes from FAPs 19-20 (ARKit's eyeBlink) and 23-26.
void fillRecord(const th::pipeline::AnimationFrame& frame, const th::outputs::AvatarFrame& avatar, Record& record) {
  record[kTime] = frame.timeSeconds;
  record[kIndex] = frame.index;
  record[kMouthClass] = avatar.hasVisemes ? avatar.mouthClass : -1;
  record[kLevelDb] = frame.levelDb;
  std::copy(avatar.oculus.begin(), avatar.oculus.end(), record.begin() + kOculus);
  std::copy(avatar.arkit.begin(), avatar.arkit.end(), record.begin() + kArkit);
  std::copy(avatar.vrm.begin(), avatar.vrm.end(), record.begin() + kVrm);
  const auto& faps = frame.faps;
  const double pitch = avatar.headDegrees[0], yaw = avatar.headDegrees[1], roll = avatar.headDegrees[2];
  constexpr double kRadians = 3.14159265358979323846 / 180.0;
  const Eigen::Quaterniond q = Eigen::AngleAxisd(yaw * kRadians, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(pitch * kRadians, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(roll * kRadians, Eigen::Vector3d::UnitZ());
  record[kHeadQuaternion + 0] = q.x();
  record[kHeadQuaternion + 1] = q.y();
  record[kHeadQuaternion + 2] = q.z();
  record[kHeadQuaternion + 3] = q.w();
  record[kHeadDegrees + 0] = pitch;
  record[kHeadDegrees + 1] = yaw;
  record[kHeadDegrees + 2] = roll;
  record[kBlink + 0] = avatar.blinkLeft();
  record[kBlink + 1] = avatar.blinkRight();
  record[kGaze + 0] = 0.5 * (faps[23] + faps[24]) * kDegreesPerAngleUnit;
  record[kGaze + 1] = 0.5 * (faps[25] + faps[26]) * kDegreesPerAngleUnit;
}

// Live's settings for a preset (pipeline/live_presets.h), with the idle behaviour on or off and its seed.
th::pipeline::LiveSettings presetSettings(const std::string& preset, bool idle, unsigned seed) {
  th::pipeline::LiveSettings settings;
  th::pipeline::applyLivePreset(settings, preset);
  settings.idle.idle = idle;
  settings.idle.seed = seed;
  settings.check();
  return settings;
}

// The model files a preset reads ("": animate --online's), by name in /models/: what the package fetches first.
val modelFiles(const std::string& preset) try {
  std::vector<std::filesystem::path> paths;
  if (preset.empty()) {
    const th::pipeline::ModelOptions models;
    paths = {models.headModelPath(), models.mouthModelPath(), models.visemeModelPath(), models.articulationModelPath()};
  } else {
    const th::pipeline::LiveSettings settings = presetSettings(preset, true, 1);
    paths = {settings.models.headModelPath(), settings.mouthModelPath(), settings.models.visemeModelPath(),
             settings.articulationModelPath()};
  }
  val out = val::array();
  for (const std::filesystem::path& path : paths)
    if (!path.empty()) out.call<void>("push", path.filename().string());
  return out;
} catch (const std::exception& error) {
  throwToJavaScript(error);
}

// The format native animate writes `path` in: `name` if given, else by the path's extension; throws an Error
// naming the path when neither says.
std::string formatFor(const std::string& path, const std::string& name) try {
  return std::string(th::formats::formatForWriting(path, name).name());
} catch (const std::exception& error) {
  throwToJavaScript(error);
}

void checkRate(double sampleRateHz) {
  // Below 8 kHz speech has lost what tells its sounds apart; above 384 kHz no sound card records.
  if (!std::isfinite(sampleRateHz) || sampleRateHz < 8000.0 || sampleRateHz > 384000.0)
    throw th::Error("cannot resample " + (std::ostringstream() << sampleRateHz).str() +
                    " Hz: the sample rate must be 8,000 to 384,000 Hz");
}

// The live decoder with a preset's models, its display's idle behaviour (blinks, gaze, the head at rest in pauses,
// on the stream's own clock), fed blocks at the context's sample rate: what the worklet runs.
class LipSyncStream {
 public:
  LipSyncStream(const std::string& preset, double sampleRateHz, bool waitForHead, bool idle, unsigned seed) try
      : settings_(presetSettings(preset, idle, seed)),
        display_(settings_.idle, settings_.live.blinks, settings_.live.gaze) {
    checkRate(sampleRateHz);
    settings_.live.waitForHead = waitForHead;
    models_ = th::pipeline::loadModels(settings_);
    decoder_ =
        std::make_unique<th::pipeline::LiveDecoder>(models_.head.get(), models_.mouth.get(), settings_.decoderOptions(),
                                                    models_.visemes.get(), models_.articulation.get());
    if (sampleRateHz != kEngineRateHz) {
      resampler_.emplace(sampleRateHz, kEngineRateHz);
      resampled_.resize(std::max(resampler_->maxOutput(block_.size()), resampler_->maxOutput(0)));
    }
  } catch (const std::exception& error) {
    throwToJavaScript(error);
  }

  // The block JavaScript writes samples into (the module's memory: no copy, no allocation per block).
  val input() { return val(emscripten::typed_memory_view(block_.size(), block_.data())); }
  // The record next() fills.
  val record() { return val(emscripten::typed_memory_view(record_.size(), record_.data())); }

  void accept(int count) {
    if (count < 0 || count > static_cast<int>(block_.size()))
      throwToJavaScript(th::Error("accept: a block holds at most " + std::to_string(block_.size()) + " samples"));
    const std::span<const float> samples(block_.data(), static_cast<std::size_t>(count));
    if (!resampler_) {
      decoder_->acceptWaveform(samples);
      return;
    }
    const std::size_t n = resampler_->process(samples, resampled_);
    decoder_->acceptWaveform(std::span<const float>(resampled_.data(), n));
  }
  void finish() {
    if (resampler_) {
      const std::size_t n = resampler_->finish(resampled_);
      decoder_->acceptWaveform(std::span<const float>(resampled_.data(), n));
    }
    decoder_->inputFinished();
  }

  // The next frame into record(); false when none is decided yet.
  bool next() {
    if (!decoder_->next(frame_)) return false;
    fillRecord(frame_, display_.present(frame_, frame_.timeSeconds), record_);
    return true;
  }

  // What a frame waits for after its sound arrives: the decoder's look-ahead and the resampler's.
  double lookaheadMs() const {
    return decoder_->lookahead().totalMs + (resampler_ ? 1000.0 * resampler_->lookaheadSeconds() : 0.0);
  }
  double framesPerSecond() const { return th::animation::kAnimationFramesPerSecond; }

 private:
  th::pipeline::LiveSettings settings_;
  th::outputs::LiveDisplay display_;
  th::pipeline::AnimationModels models_;
  std::unique_ptr<th::pipeline::LiveDecoder> decoder_;
  std::optional<th::audio::SincResampler> resampler_;
  std::vector<float> block_ = std::vector<float>(4096);
  std::vector<float> resampled_ = std::vector<float>(4096);
  th::pipeline::AnimationFrame frame_;
  Record record_{};
};

// A whole recording's animation: its frames as records, and its text in any of native animate's formats.
class Animation {
 public:
  explicit Animation(th::face::FapTrack track) : track_(std::move(track)) {}

  int numFrames() const { return track_.numFrames(); }
  double framesPerSecond() const { return track_.framesPerSecond; }
  val record() { return val(emscripten::typed_memory_view(record_.size(), record_.data())); }

  // Frame `index` into record().
  void select(int index) {
    if (index < 0 || index >= track_.numFrames())
      throwToJavaScript(th::Error("select: no frame " + std::to_string(index) + " (the animation has " +
                                  std::to_string(track_.numFrames()) + ")"));
    th::pipeline::AnimationFrame frame;
    frame.index = index;
    frame.timeSeconds = index / track_.framesPerSecond;
    frame.levelDb = std::nan("");  // the recording's level is not kept with the track
    for (std::size_t r = 0; r < track_.faps.size(); ++r)
      frame.faps[static_cast<std::size_t>(track_.faps[r])] = track_.values(static_cast<Eigen::Index>(r), index);
    const th::face::VisemeTrack& visemes = track_.visemes;
    if (!visemes.empty()) {
      frame.visemeIndex = index;
      frame.mouthClass = visemes.classes[static_cast<std::size_t>(index)];
      for (int c = 0; c < th::face::kNumMouthClasses; ++c)
        frame.visemeProbabilities[static_cast<std::size_t>(c)] = static_cast<float>(visemes.posteriors(c, index));
    }
    fillRecord(frame, th::outputs::avatarFrameOf(frame), record_);
  }

  // The animation in a format of native animate's (formats/animation_format.h: "csv", "arkit", "oculus", ...).
  std::string write(const std::string& format) const try {
    const th::formats::AnimationFormat& chosen = th::formats::animationFormat(format);
    chosen.check(std::string("animation.") + std::string(chosen.extension()), track_);
    std::ostringstream out;
    chosen.write(out, track_);
    return out.str();
  } catch (const std::exception& error) {
    throwToJavaScript(error);
  }

  // The FAP curves: {framesPerSecond, faps: [numbers], values: Float64Array, frame after frame}.
  val fapTrack() const {
    val out = val::object();
    out.set("framesPerSecond", track_.framesPerSecond);
    val faps = val::array();
    for (const int fap : track_.faps) faps.call<void>("push", fap);
    out.set("faps", faps);
    std::vector<double> frameMajor(static_cast<std::size_t>(track_.values.size()));
    for (Eigen::Index t = 0; t < track_.values.cols(); ++t)
      for (Eigen::Index r = 0; r < track_.values.rows(); ++r)
        frameMajor[static_cast<std::size_t>(t * track_.values.rows() + r)] = track_.values(r, t);
    out.set("values", val::global("Float64Array").new_(val::array(frameMajor)));
    return out;
  }

 private:
  th::face::FapTrack track_;
  Record record_{};
};

// Samples from one rate to another with the engine's resampler (the worklet's): for a page that has sound at
// another rate, and the benchmark page.
val resample(const val& samples, double fromHz, double toHz) try {
  const std::vector<float> out =
      th::audio::sincResample(emscripten::convertJSArrayToNumberVector<float>(samples), fromHz, toHz);
  return val::global("Float32Array").new_(val(emscripten::typed_memory_view(out.size(), out.data())));
} catch (const std::exception& error) {
  throwToJavaScript(error);
}

// Mono samples at any rate from 8 kHz -> their animation: with a preset, the frames of `talkinghead animate
// --online --preset P` (live's decoding, each frame with its own head); with "", those of `animate --online`
// (the offline models, a second of inversion window).
Animation* animateSamples(const val& samples, double sampleRateHz, const std::string& preset, bool idle,
                          unsigned seed) try {
  checkRate(sampleRateHz);
  std::vector<float> pcm = emscripten::convertJSArrayToNumberVector<float>(samples);
  if (pcm.empty()) throw th::Error("no samples to animate");
  if (sampleRateHz != kEngineRateHz) pcm = th::audio::sincResample(pcm, sampleRateHz, kEngineRateHz);
  th::pipeline::AnimateOptions options;
  th::pipeline::AnimationModels models;
  if (preset.empty()) {
    th::pipeline::ModelOptions modelOptions;
    th::pipeline::HeadMotionOptions head;
    th::pipeline::IdleOptions idleOptions;
    idleOptions.idle = idle;
    idleOptions.seed = seed;
    th::pipeline::StreamingOptions streaming{.window = 30};
    options = th::pipeline::animateOptionsOf(modelOptions, head, idleOptions, &streaming);
    models = th::pipeline::loadModels(modelOptions);
  } else {
    const th::pipeline::LiveSettings settings = presetSettings(preset, idle, seed);
    options = th::pipeline::livePresetAnimateOptions(settings);
    models = th::pipeline::loadModels(settings);
  }
  return new Animation(th::pipeline::animate(pcm, models, options));
} catch (const std::exception& error) {
  throwToJavaScript(error);
}

// An animation file's text (a readable format: "csv", "json", "fap") as an Animation: its frames as records, as
// the package makes them of its own (e.g. of native animate's FAPs, to compare).
Animation* readAnimation(const std::string& text, const std::string& format) try {
  const th::formats::AnimationFormat& chosen = th::formats::animationFormat(format);
  return new Animation(chosen.read(text, std::string("animation.") + std::string(chosen.extension())));
} catch (const std::exception& error) {
  throwToJavaScript(error);
}

}  // namespace

EMSCRIPTEN_BINDINGS(talkinghead) {
  emscripten::function("frameLayout", &frameLayout);
  emscripten::function("modelFiles", &modelFiles);
  emscripten::function("formatFor", &formatFor);
  emscripten::function("resample", &resample);
  emscripten::function("readAnimation", &readAnimation, emscripten::allow_raw_pointers());
  emscripten::function("animateSamples", &animateSamples, emscripten::allow_raw_pointers());
  emscripten::class_<LipSyncStream>("LipSyncStream")
      .constructor<std::string, double, bool, bool, unsigned>()
      .function("input", &LipSyncStream::input)
      .function("record", &LipSyncStream::record)
      .function("accept", &LipSyncStream::accept)
      .function("finish", &LipSyncStream::finish)
      .function("next", &LipSyncStream::next)
      .function("lookaheadMs", &LipSyncStream::lookaheadMs)
      .function("framesPerSecond", &LipSyncStream::framesPerSecond);
  emscripten::class_<Animation>("Animation")
      .function("numFrames", &Animation::numFrames)
      .function("framesPerSecond", &Animation::framesPerSecond)
      .function("record", &Animation::record)
      .function("select", &Animation::select)
      .function("write", &Animation::write)
      .function("fapTrack", &Animation::fapTrack);
}
