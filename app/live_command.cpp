// `talkinghead live --headless`: the live pipeline without a window. The sound comes from a recording played
// into the session at real-time pace (or faster), or from a sound input through PortAudio (--device); the
// worker decodes it, and a display loop takes the frames, as the window's render thread will. What it
// received can be dumped as an animation file; the session's counters and the per-frame decoding delay go to
// stdout. `--list-devices` lists the sound inputs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "animation/animate.h"
#include "animation/fap_mapping.h"
#include "audio/media_audio.h"
#include "audio/capture.h"
#include "animation_models.h"
#include "commands.h"
#include "interrupt.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/live_decoder.h"
#include "pipeline/live_session.h"
#include "video/animation_file.h"

namespace th::app {
namespace {

struct LiveArguments {
  bool headless = false;
  bool listDevices = false;
  std::string input;
  std::string device;  // "default" or an index
  double speed = 1.0;
  double duration = 0.0;
  std::string dump;
  std::string headVariant = "trajectory";
  std::string mouthMethod = "inversion";
  int lagFrames = 6;
  int windowFrames = 2;
  int iterations = 20;
  bool waitForHead = false;
  std::string headModel = defaultHeadModel();
  std::string mouthModel = defaultMouthModel();
};

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto at = static_cast<std::size_t>(p / 100.0 * static_cast<double>(values.size() - 1) + 0.5);
  return values[std::min(at, values.size() - 1)];
}

void listDevices() {
  const audio::PortAudioSystem system;
  const std::vector<audio::AudioDevice> inputs = system.inputDevices();
  if (inputs.empty()) std::printf("no sound input devices\n");
  for (const audio::AudioDevice& d : inputs)
    std::printf("%3d  %s%s  (%s, %d channels, %.0f Hz)\n", d.index, d.name.c_str(), d.isDefaultInput ? "  [default]" : "",
                d.hostApi.c_str(), d.inputChannels, d.defaultRateHz);
}

std::optional<int> deviceIndexOf(const std::string& text) {
  if (text == "default") return std::nullopt;
  std::size_t used = 0;
  int index = -1;
  try {
    index = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || index < 0)
    throw Error("--device " + text + ": expected \"default\" or a device number from --list-devices");
  return index;
}

void runLive(const LiveArguments& arguments) {
  if (arguments.listDevices) {
    listDevices();
    return;
  }
  if (!arguments.headless) throw Error("live: only --headless so far (the window is issue 6's next step)");
  if (arguments.input.empty() == arguments.device.empty())
    throw Error("live: give the sound either as --input FILE or as --device (default or a number)");
  if (!arguments.device.empty() && arguments.speed != 1.0) throw Error("live: --speed is for --input files; a device runs in real time");
  if (!arguments.dump.empty()) {
    video::animationFormatOf(arguments.dump);
    checkOutputTarget(arguments.dump);
  }
  pipeline::LiveDecoderOptions options;
  options.head.variant = arguments.headVariant == "paper" ? animation::HeadVariant::kStateMeans
                                                          : animation::HeadVariant::kTrajectory;
  options.head.maxLagFrames = arguments.lagFrames;
  options.mouth.method = arguments.mouthMethod == "mmse" ? animation::MouthMethod::kMmse : animation::MouthMethod::kInversion;
  options.mouth.windowFrames = arguments.windowFrames;
  options.mouth.maxIterations = arguments.iterations;
  options.waitForHead = arguments.waitForHead;
  const AnimationModels models = loadAnimationModels("live", arguments.headVariant, arguments.headModel,
                                                     arguments.mouthMethod, arguments.mouthModel);
  const animation::HeadModel* head = models.head.get();
  const animation::MouthModel* mouth = models.mouth.get();

  InterruptGuard interrupts;
  auto decoder = std::make_unique<pipeline::LiveDecoder>(head, mouth, options);
  const pipeline::DecoderLookahead lookahead = decoder->lookahead();
  const std::vector<int> fapNumbers = decoder->fapNumbers();
  // The source: a file played into the ring, or a device's callback writing into it.
  std::unique_ptr<audio::PortAudioSystem> system;
  std::unique_ptr<audio::Capture> capture;
  std::unique_ptr<pipeline::LiveSession> session;
  std::unique_ptr<pipeline::FileFeeder> feeder;
  std::string source;
  double seconds = 0.0;
  if (!arguments.input.empty()) {
    audio::AudioClip clip = audio::readRecording(arguments.input);
    if (clip.samples.empty()) throw fileError(arguments.input, "has no samples");
    if (arguments.duration > 0.0)
      clip.samples.resize(std::min(clip.samples.size(), static_cast<std::size_t>(arguments.duration * clip.sampleRateHz)));
    seconds = static_cast<double>(clip.samples.size()) / clip.sampleRateHz;
    source = arguments.input;
    session = std::make_unique<pipeline::LiveSession>(std::move(decoder));
    session->start();
    feeder = std::make_unique<pipeline::FileFeeder>(*session, std::move(clip.samples), arguments.speed);
  } else {
    system = std::make_unique<audio::PortAudioSystem>();
    const std::optional<int> index = deviceIndexOf(arguments.device);
    // The decoder converts the device's rate if it will not run at 16 kHz; the device is opened once the
    // session (which owns the ring) exists.
    const double rate = audio::captureRateFor(*system, index, 16000.0);
    std::unique_ptr<pipeline::FrameDecoder> chain = std::move(decoder);
    if (rate != 16000.0) chain = std::make_unique<pipeline::ResamplingDecoder>(std::move(chain), rate);
    pipeline::LiveSessionOptions sessionOptions;
    sessionOptions.ringSamples = static_cast<std::size_t>(4.0 * rate);
    session = std::make_unique<pipeline::LiveSession>(std::move(chain), sessionOptions);
    session->start();
    capture = std::make_unique<audio::Capture>(*system, index, rate, session->ring());
    source = "sound input " + std::to_string(capture->device().index) + " (" + capture->device().name + ", " +
             std::to_string(static_cast<int>(rate)) + " Hz)";
  }
  const auto started = std::chrono::steady_clock::now();
  bool deviceLost = false;

  // The display loop: 60 Hz in the recording's time (faster when it plays faster; at full speed as often as
  // it can), taking whatever the worker has decoded.
  std::vector<pipeline::AnimationFrame> shown;
  std::vector<double> decodeMs;
  pipeline::AnimationFrame frame;
  const auto tick = std::chrono::microseconds(
      arguments.speed > 0.0 ? static_cast<long>(16667.0 / std::max(arguments.speed, 1.0)) : 500L);
  auto next = std::chrono::steady_clock::now();
  while (!session->done()) {
    while (session->nextFrame(frame)) {
      decodeMs.push_back(static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
      shown.push_back(frame);
    }
    if (capture) {
      // A device runs until --duration, an interrupt, or until it goes away.
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      const bool lost = !capture->active();
      if ((arguments.duration > 0.0 && elapsed >= arguments.duration) || InterruptGuard::requested() || lost) {
        deviceLost = lost;
        seconds = elapsed;
        capture.reset();
        session->endOfInput();
      }
    } else if (InterruptGuard::requested()) {
      feeder->stop();
    }
    next += tick;
    std::this_thread::sleep_until(next);
  }
  while (session->nextFrame(frame)) shown.push_back(frame);
  session->rethrowError();
  if (deviceLost) std::fprintf(stderr, "talkinghead: %s: the device went away; stopped\n", source.c_str());

  const pipeline::SessionCounters counters = session->counters();
  char pace[64] = "as fast as possible, not";
  if (arguments.speed > 0.0) std::snprintf(pace, sizeof(pace), "%gx", arguments.speed);
  std::printf("live (headless): %s, %.2f s of sound at %s real time\n", source.c_str(), seconds, pace);
  std::printf("  frames: %llu decoded, %zu shown, %llu dropped; samples: %llu in, %llu overrun\n",
              static_cast<unsigned long long>(counters.framesDecoded), shown.size(),
              static_cast<unsigned long long>(counters.framesDropped), static_cast<unsigned long long>(counters.samplesIn),
              static_cast<unsigned long long>(counters.overrunSamples));
  std::printf("  look-ahead: mouth %.1f ms (features %.1f ms + %d frames), head %.1f ms (features %.1f ms + %d frames)",
              lookahead.mouthMs, lookahead.mouthFeaturesMs, lookahead.mouthFrames, lookahead.headMs,
              lookahead.featuresMs, lookahead.headFrames);
  if (lookahead.headDelayFrames > 0) std::printf(", the head shown %d frames late", lookahead.headDelayFrames);
  std::printf(": %.1f ms\n", lookahead.totalMs);
  std::printf("  decoding, from the read to the frame out: median %.2f ms, 95th percentile %.2f ms, max %.2f ms\n",
              percentile(decodeMs, 50), percentile(decodeMs, 95), percentile(decodeMs, 100));

  if (!arguments.dump.empty()) {
    video::Animation animation;
    animation.name = std::filesystem::path(arguments.input).stem().string();
    animation.framesPerSecond = animation::kAnimationFramesPerSecond;
    animation.faps = fapNumbers;
    animation.values.resize(static_cast<Eigen::Index>(shown.size()), static_cast<Eigen::Index>(animation.faps.size()));
    for (std::size_t f = 0; f < shown.size(); ++f)
      for (std::size_t c = 0; c < animation.faps.size(); ++c)
        animation.values(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(c)) =
            shown[f].faps[static_cast<std::size_t>(animation.faps[c])];
    video::writeAnimation(arguments.dump, animation);
    std::printf("wrote %s: %zu frames\n", arguments.dump.c_str(), shown.size());
  }
}

}  // namespace

void addLiveCommand(CLI::App& app) {
  auto arguments = std::make_shared<LiveArguments>();
  CLI::App* live = app.add_subcommand("live", "The live pipeline: speech in real time -> animation frames");
  live->add_flag("--headless", arguments->headless, "Without a window: decode, and report or dump what a display would get");
  live->add_flag("--list-devices", arguments->listDevices, "List the sound inputs and exit");
  live->add_option("--input", arguments->input, "Recording to play into the pipeline (WAV, FLAC, ... or a video's audio)");
  live->add_option("--device", arguments->device, "Sound input: default, or a number from --list-devices");
  live->add_option("--speed", arguments->speed, "Times real time (0: as fast as the worker decodes)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  live->add_option("--duration", arguments->duration, "Seconds to run: of the recording (0: all), or of listening (0: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e6));
  live->add_option("--dump", arguments->dump, "Write the frames the display received: .csv, .json or .fap");
  live->add_option("--head", arguments->headVariant, "Head: trajectory (smooth), paper (Viterbi state means), none")
      ->check(CLI::IsMember({"trajectory", "paper", "none"}))
      ->capture_default_str();
  live->add_option("--mouth", arguments->mouthMethod, "Mouth: inversion, mmse, none")
      ->check(CLI::IsMember({"inversion", "mmse", "none"}))
      ->capture_default_str();
  live->add_option("--lag", arguments->lagFrames, "Head decoding lag, frames")->check(CLI::Range(0, 300))->capture_default_str();
  live->add_option("--window", arguments->windowFrames, "Mouth inversion window, frames")
      ->check(CLI::Range(1, 300))
      ->capture_default_str();
  live->add_flag("--wait-for-head", arguments->waitForHead,
                 "Each frame waits for its own head (~400 ms) instead of showing the head late behind a ~110 ms mouth");
  live->add_option("--iterations", arguments->iterations, "Mouth inversion: most EM iterations a window")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  addModelFileOptions(*live, arguments->headModel, arguments->mouthModel);
  live->callback([arguments] { runLive(*arguments); });
}

}  // namespace th::app
