// `talkinghead live --headless`: the live pipeline without a window. The sound comes from a recording played
// into the session at real-time pace (or faster), or from a sound input through PortAudio (--device); the
// worker decodes it, and a display loop takes the frames, as the window's render thread will. What it
// received can be dumped as an animation file; the session's counters and the per-frame decoding delay go to
// stdout. `--list-devices` lists the sound inputs.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/offline.h"
#include "animation/fap_mapping.h"
#include "audio/media_audio.h"
#include "audio/capture.h"
#include "animation_models.h"
#include "commands.h"
#include "live_settings.h"
#include "live_window.h"
#include "interrupt.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/statistics.h"
#include "pipeline/live_decoder.h"
#include "pipeline/live_session.h"
#include "formats/animation_format.h"

namespace th::app {
namespace {

struct LiveArguments {
  bool headless = false;
  bool listDevices = false;
  std::string input;
  double speed = 1.0;
  double duration = 0.0;
  double repeatTo = 0.0;     // --headless --input: play the recording over and over to this many seconds
  std::string dump;
  std::string settingsFile;  // the window's saved settings
  bool noSettings = false;
  std::string screenshot;    // the window: save it as PNG after `frames` frames and quit
  int frames = 90;
  int msaa = 0;
  double maxFps = 60.0;
  LiveSettings given;        // the options as typed (which ones were typed: CLI11's count)
  MotionControls motion;     // the head and idle options animate and export share
};

// This process's resident memory, MB (Linux: /proc/self/status), or -1 where it cannot be read.
double residentMegabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // "VmRSS:  12345 kB"
  return -1.0;
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

// The settings a run uses: the saved ones (window only), then the preset, then the options typed.
LiveSettings resolveSettings(const LiveArguments& arguments, const CLI::App& command, const LiveSettings& saved) {
  LiveSettings settings = saved;
  const LiveSettings& given = arguments.given;
  const auto typed = [&](const char* option) { return command.count(option) > 0; };
  if (typed("--preset")) applyPreset(settings, given.preset);
  if (typed("--device")) settings.device = given.device;
  if (typed("--head")) settings.headVariant = given.headVariant;
  if (typed("--mouth")) settings.mouthMethod = given.mouthMethod;
  if (typed("--covariance")) settings.covariance = given.covariance;
  if (typed("--head-model")) settings.headModel = given.headModel;
  if (typed("--mouth-model")) settings.mouthModel = given.mouthModel;
  if (typed("--lag")) settings.lagFrames = given.lagFrames;
  if (typed("--window")) settings.windowFrames = given.windowFrames;
  if (typed("--iterations")) settings.iterations = given.iterations;
  if (typed("--wait-for-head")) settings.waitForHead = given.waitForHead;
  if (typed("--min-f0")) settings.minF0Hz = given.minF0Hz;
  if (typed("--max-f0")) settings.maxF0Hz = given.maxF0Hz;
  if (typed("--head-amplitude")) settings.headAmplitude = arguments.motion.headAmplitude;
  if (typed("--head-smoothing")) settings.headSmoothing = arguments.motion.headSmoothing;
  if (typed("--head-variation")) settings.headVariation = arguments.motion.headVariation;
  if (typed("--no-idle")) settings.idle = false;
  if (typed("--blinks-per-minute")) settings.blinksPerMinute = arguments.motion.blinksPerMinute;
  if (typed("--seed")) settings.seed = arguments.motion.seed;
  if (!(settings.minF0Hz < settings.maxF0Hz)) throw Error("live: --min-f0 must be below --max-f0");
  return settings;
}

void runHeadless(const LiveArguments& arguments, const LiveSettings& settings, bool fromDevice) {
  if (fromDevice && arguments.speed != 1.0) throw Error("live: --speed is for --input files; a device runs in real time");
  if (!arguments.dump.empty()) {
    formats::animationFormatFor(arguments.dump);
    checkOutputTarget(arguments.dump);
  }
  const pipeline::LiveDecoderOptions options = decoderOptionsOf(settings);
  const AnimationModels models = loadAnimationModels("live", settings.headVariant, headModelOf(settings),
                                                     settings.mouthMethod, mouthModelOf(settings));
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
    seconds = std::max(static_cast<double>(clip.samples.size()) / clip.sampleRateHz, arguments.repeatTo);
    source = arguments.input;
    session = std::make_unique<pipeline::LiveSession>(std::move(decoder));
    session->start();
    feeder = std::make_unique<pipeline::FileFeeder>(*session, std::move(clip.samples), arguments.speed, 256,
                                                    static_cast<std::size_t>(arguments.repeatTo * clip.sampleRateHz));
  } else {
    system = std::make_unique<audio::PortAudioSystem>();
    const std::optional<int> index = deviceIndexOf(settings.device);
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
  // Frames are kept only for a dump: a soak of an hour would otherwise keep the hour.
  std::vector<pipeline::AnimationFrame> shown;
  std::uint64_t framesShown = 0;
  MillisecondHistogram decodeMs;
  const double startMegabytes = residentMegabytes();
  double minuteMegabytes = -1.0;
  pipeline::AnimationFrame frame;
  const auto tick = std::chrono::microseconds(
      arguments.speed > 0.0 ? static_cast<long>(16667.0 / std::max(arguments.speed, 1.0)) : 500L);
  auto next = std::chrono::steady_clock::now();
  while (!session->done()) {
    while (session->nextFrame(frame)) {
      decodeMs.add(static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
      if (!arguments.dump.empty()) shown.push_back(frame);
      if (++framesShown == 60 * 30) minuteMegabytes = residentMegabytes();  // a minute of sound in
    }
    if (capture) {
      // A device runs until --duration, an interrupt, or until it goes away.
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      const bool lost = !capture->active();
      if ((arguments.duration > 0.0 && elapsed >= arguments.duration) || InterruptGuard::requested() || lost) {
        deviceLost = lost;
        seconds = elapsed;
        // Closed on a thread of its own: closing a stream whose sound server died can block in PortAudio.
        if (!audio::closeInBackground(std::move(capture), std::move(system), std::chrono::milliseconds(2000)))
          std::fprintf(stderr, "talkinghead: %s: PortAudio has not closed it in 2 s; left closing\n", source.c_str());
        session->endOfInput();
      }
    } else if (feeder && InterruptGuard::requested()) {
      feeder->stop();
    }
    next += tick;
    std::this_thread::sleep_until(next);
  }
  while (session->nextFrame(frame)) {
    if (!arguments.dump.empty()) shown.push_back(frame);
    ++framesShown;
  }
  session->rethrowError();
  const double endMegabytes = residentMegabytes();
  if (deviceLost) std::fprintf(stderr, "talkinghead: %s: the device went away; stopped\n", source.c_str());

  const pipeline::SessionCounters counters = session->counters();
  char pace[64] = "as fast as possible, not";
  if (arguments.speed > 0.0) std::snprintf(pace, sizeof(pace), "%gx", arguments.speed);
  std::printf("live (headless): %s, %.2f s of sound at %s real time\n", source.c_str(), seconds, pace);
  std::printf("  frames: %llu decoded, %llu shown, %llu dropped; samples: %llu in, %llu overrun\n",
              static_cast<unsigned long long>(counters.framesDecoded), static_cast<unsigned long long>(framesShown),
              static_cast<unsigned long long>(counters.framesDropped), static_cast<unsigned long long>(counters.samplesIn),
              static_cast<unsigned long long>(counters.overrunSamples));
  std::printf("  look-ahead: mouth %.1f ms (features %.1f ms + %d frames), head %.1f ms (features %.1f ms + %d frames)",
              lookahead.mouthMs, lookahead.mouthFeaturesMs, lookahead.mouthFrames, lookahead.headMs,
              lookahead.featuresMs, lookahead.headFrames);
  if (lookahead.headDelayFrames > 0) std::printf(", the head shown %d frames late", lookahead.headDelayFrames);
  std::printf(": %.1f ms\n", lookahead.totalMs);
  std::printf("  decoding, from the read to the frame out: median %.2f ms, 95th percentile %.2f ms, max %.2f ms\n",
              decodeMs.percentile(50), decodeMs.percentile(95), decodeMs.largest());
  char afterAMinute[32] = "-";
  if (minuteMegabytes >= 0.0) std::snprintf(afterAMinute, sizeof afterAMinute, "%.1f MB", minuteMegabytes);
  std::printf("  memory (resident): %.1f MB at the start, %s after the first minute of sound, %.1f MB at the end\n",
              startMegabytes, afterAMinute, endMegabytes);

  if (!arguments.dump.empty()) {
    face::FapTrack animation;
    animation.name = std::filesystem::path(arguments.input).stem().string();
    animation.framesPerSecond = animation::kAnimationFramesPerSecond;
    animation.faps = fapNumbers;
    animation.values.resize(static_cast<Eigen::Index>(animation.faps.size()), static_cast<Eigen::Index>(shown.size()));
    for (std::size_t f = 0; f < shown.size(); ++f)
      for (std::size_t c = 0; c < animation.faps.size(); ++c)
        animation.values(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(f)) =
            shown[f].faps[static_cast<std::size_t>(animation.faps[c])];
    formats::writeAnimation(arguments.dump, animation);
    std::printf("wrote %s: %zu frames\n", arguments.dump.c_str(), shown.size());
  }
}

void runLive(const LiveArguments& arguments, const CLI::App& command) {
  if (arguments.listDevices) {
    listDevices();
    return;
  }
  const bool typedDevice = command.count("--device") > 0;
  if (!arguments.input.empty() && typedDevice) throw Error("live: give the sound either as --input FILE or as --device, not both");
  if (arguments.headless) {
    if (arguments.input.empty() && !typedDevice)
      throw Error("live --headless: give the sound either as --input FILE or as --device (default or a number)");
    if (!arguments.screenshot.empty()) throw Error("live: --screenshot is for the window, not --headless");
    runHeadless(arguments, resolveSettings(arguments, command, LiveSettings{}), typedDevice);
    return;
  }
  if (!arguments.dump.empty()) throw Error("live: --dump is for --headless runs");
  if (arguments.speed != 1.0) throw Error("live: --speed is for --headless runs; the window plays in real time");
  const std::filesystem::path settingsPath =
      arguments.noSettings ? std::filesystem::path() : (arguments.settingsFile.empty() ? defaultLiveSettingsPath()
                                                                                       : std::filesystem::path(arguments.settingsFile));
  const LiveSettings settings = resolveSettings(arguments, command, loadLiveSettings(settingsPath));
  runLiveWindow({.input = arguments.input, .settingsPath = settingsPath, .screenshot = arguments.screenshot,
                 .frames = arguments.frames, .duration = arguments.duration, .msaa = arguments.msaa,
                 .maxFps = arguments.maxFps},
                settings);
}

}  // namespace

void addLiveCommand(CLI::App& app) {
  auto arguments = std::make_shared<LiveArguments>();
  LiveSettings& given = arguments->given;
  CLI::App* live = app.add_subcommand(
      "live", "Speech in real time -> the face: a window with a panel, or --headless (frames reported or dumped)");
  live->add_flag("--headless", arguments->headless, "Without a window: decode, and report or dump what a display would get");
  live->add_flag("--list-devices", arguments->listDevices, "List the sound inputs and exit");
  live->add_option("--input", arguments->input, "Recording to play into the pipeline (WAV, FLAC, ... or a video's audio)");
  live->add_option("--device", given.device, "Sound input: default, or a number from --list-devices");
  live->add_option("--speed", arguments->speed, "--headless --input: times real time (0: as fast as the worker decodes)")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  live->add_option("--duration", arguments->duration, "Seconds to run: of the recording (0: all), or of listening (0: until Ctrl-C)")
      ->check(CLI::Range(0.0, 1e6));
  live->add_option("--repeat-to", arguments->repeatTo,
                   "--headless --input: play the recording over and over to this many seconds (a soak test)")
      ->check(CLI::Range(0.0, 1e6));
  live->add_option("--dump", arguments->dump, "--headless: write the frames the display received: .csv, .json or .fap");
  live->add_option("--preset", given.preset, "default (~85 ms), low-latency (~50 ms, less accurate), accurate (~200 ms, smooth)")
      ->check(CLI::IsMember({"default", "low-latency", "accurate"}))
      ->capture_default_str();
  live->add_option("--head", given.headVariant, "Head: trajectory (smooth), paper (Viterbi state means), none")
      ->check(CLI::IsMember({"trajectory", "paper", "none"}))
      ->capture_default_str();
  live->add_option("--mouth", given.mouthMethod, "Mouth: inversion, mmse, none")
      ->check(CLI::IsMember({"inversion", "mmse", "none"}))
      ->capture_default_str();
  live->add_option("--covariance", given.covariance, "The shipped mouth model's covariance: full, or its diagonal twin")
      ->check(CLI::IsMember({"full", "diagonal"}))
      ->capture_default_str();
  live->add_option("--lag", given.lagFrames, "Head decoding lag, frames")->check(CLI::Range(0, 300))->capture_default_str();
  live->add_option("--window", given.windowFrames, "Mouth inversion window, frames (the preset's by default)")
      ->check(CLI::Range(1, 300));
  live->add_flag("--wait-for-head", given.waitForHead,
                 "Each frame waits for its own head (~400 ms) instead of showing the head late behind the mouth");
  live->add_option("--iterations", given.iterations, "Mouth inversion: most EM iterations a window")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  live->add_option("--min-f0", given.minF0Hz, "Lowest F0 the prosody tracker searches, Hz")->check(CLI::Range(20.0, 1000.0))->capture_default_str();
  live->add_option("--max-f0", given.maxF0Hz, "Highest F0, Hz")->check(CLI::Range(40.0, 2000.0))->capture_default_str();
  addMotionControls(*live, arguments->motion);
  live->add_option("--head-model", given.headModel, "Head model file (default models/head.json)");
  live->add_option("--mouth-model", given.mouthModel, "Mouth model file (default: the preset's, in models/)");
  live->add_option("--settings", arguments->settingsFile,
                   "The window's settings file (default $XDG_CONFIG_HOME/talkinghead/live.json or ~/.config/...)");
  live->add_flag("--no-settings", arguments->noSettings, "Neither read nor save the window's settings");
  live->add_option("--screenshot", arguments->screenshot, "Window: save it as PNG after --frames frames and quit");
  live->add_option("--frames", arguments->frames, "Window: frames before the screenshot")->check(CLI::Range(1, 100000))->capture_default_str();
  live->add_option("--msaa", arguments->msaa, "Window: MSAA samples (0: 4 on a GPU, 1 = none on a software renderer)")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  live->add_option("--max-fps", arguments->maxFps,
                   "Window: the most frames a second where the display does not pace them (Xvfb); 0: as many as it can")
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  live->callback([arguments, live] { runLive(*arguments, *live); });
}

}  // namespace th::app
