#include "live/headless.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <thread>
#include <vector>

#include "animation/speech_analysis.h"
#include "audio/media_audio.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/statistics.h"
#include "formats/animation_format.h"
#include "interrupt.h"
#include "live/settings_file.h"
#include "outputs/live_display.h"
#include "pipeline/live.h"

namespace th::app {
namespace {

// This process's resident memory, MB (Linux: /proc/self/status), or -1 where it cannot be read.
double residentMegabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // "VmRSS:  12345 kB"
  return -1.0;
}

void printEvents(pipeline::LivePipeline& live) {
  for (const pipeline::LiveEvent& event : live.events())
    if (event.kind != pipeline::LiveEventKind::kStarted) std::fprintf(stderr, "talkinghead: %s\n", event.text.c_str());
}

face::FapTrack trackOf(const std::vector<pipeline::AnimationFrame>& frames, const std::vector<int>& faps,
                       const std::string& name) {
  face::FapTrack track;
  track.name = name;
  track.framesPerSecond = animation::kAnimationFramesPerSecond;
  track.faps = faps;
  track.values.resize(static_cast<Eigen::Index>(faps.size()), static_cast<Eigen::Index>(frames.size()));
  for (std::size_t f = 0; f < frames.size(); ++f)
    for (std::size_t r = 0; r < faps.size(); ++r)
      track.values(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(f)) =
          frames[f].faps[static_cast<std::size_t>(faps[r])];
  return track;
}

// What a run measured, for its report.
struct RunReport {
  std::string sourceName;
  double seconds = 0.0;  // of sound, all passes
  double speed = 1.0;    // times real time (0: as fast as the worker decodes)
  bool fromDevice = false;
  std::uint64_t framesShown = 0;
  const MillisecondHistogram* decodeMs = nullptr;  // from the read to the frame out
  double startMegabytes = 0.0;
  double minuteMegabytes = -1.0;  // after the first minute of sound (-1: the run was shorter)
  double endMegabytes = 0.0;
  std::vector<std::string> outputLines;  // each output's counts
};

// The run's report on stdout: the source and pace, the frames, the look-ahead, the decoding time, memory, outputs.
void printReport(const RunReport& report, pipeline::LivePipeline& live) {
  const pipeline::SessionCounters counters = live.counters();
  char pace[64] = "as fast as possible, not";
  if (report.speed > 0.0) std::snprintf(pace, sizeof(pace), "%gx", report.speed);
  std::printf("live (headless): %s, %.2f s of sound at %s real time\n", report.sourceName.c_str(), report.seconds,
              pace);
  std::printf(
      "  frames: %llu decoded, %llu shown, %llu dropped; samples: %llu in, %llu overrun\n",
      static_cast<unsigned long long>(counters.framesDecoded), static_cast<unsigned long long>(report.framesShown),
      static_cast<unsigned long long>(counters.framesDropped), static_cast<unsigned long long>(counters.samplesIn),
      static_cast<unsigned long long>(counters.overrunSamples));
  if (report.fromDevice)
    std::printf("  sound inputs: %llu opened, %llu lost\n", static_cast<unsigned long long>(live.sourcesOpened()),
                static_cast<unsigned long long>(live.sourcesLost()));
  const pipeline::DecoderLookahead& lookahead = live.lookahead();
  std::printf("  look-ahead: mouth %.1f ms (features %.1f ms + %d frames), head %.1f ms (features %.1f ms + %d frames)",
              lookahead.mouthMs, lookahead.mouthFeaturesMs, lookahead.mouthFrames, lookahead.headMs,
              lookahead.featuresMs, lookahead.headFrames);
  if (lookahead.headDelayFrames > 0) std::printf(", the head shown %d frames late", lookahead.headDelayFrames);
  std::printf(": %.1f ms\n", lookahead.totalMs);
  std::printf("  decoding, from the read to the frame out: median %.2f ms, 95th percentile %.2f ms, max %.2f ms\n",
              report.decodeMs->percentile(50), report.decodeMs->percentile(95), report.decodeMs->largest());
  char afterAMinute[32] = "-";
  if (report.minuteMegabytes >= 0.0)
    std::snprintf(afterAMinute, sizeof afterAMinute, "%.1f MB", report.minuteMegabytes);
  std::printf("  memory (resident): %.1f MB at the start, %s after the first minute of sound, %.1f MB at the end\n",
              report.startMegabytes, afterAMinute, report.endMegabytes);
  for (const std::string& line : report.outputLines) std::printf("  output %s\n", line.c_str());
}

// The sound the pipeline hears: the recording (cut to --duration, looped to --repeat-to), or the device.
// `seconds`: the recording's sound over all passes.
pipeline::LiveSource sourceOf(const HeadlessArguments& arguments, const outputs::LiveSessionSettings& settings,
                              pipeline::LivePipelineOptions& options, double& seconds) {
  pipeline::LiveSource source;
  if (arguments.input.empty()) {
    source.device = settings.live.deviceIndex();
    return source;
  }
  audio::AudioClip clip = audio::readRecording(arguments.input);
  if (clip.samples.empty()) throw fileError(arguments.input, "has no samples");
  if (arguments.duration > 0.0)
    clip.samples.resize(
        std::min(clip.samples.size(), static_cast<std::size_t>(arguments.duration * clip.sampleRateHz)));
  seconds = std::max(static_cast<double>(clip.samples.size()) / clip.sampleRateHz, arguments.repeatTo);
  options.repeatToSamples = static_cast<std::size_t>(arguments.repeatTo * clip.sampleRateHz);
  source.recording = std::move(clip.samples);
  source.name = arguments.input;
  return source;
}

// What the display loop saw.
struct DisplayRun {
  std::vector<pipeline::AnimationFrame> shown;  // kept only for a dump: a soak of an hour would keep the hour
  std::uint64_t framesShown = 0;
  MillisecondHistogram decodeMs;
  double startMegabytes = 0.0, minuteMegabytes = -1.0;
};

// The display loop: 60 Hz in the recording's time (faster when it plays faster; at full speed as often as it
// can), taking whatever the worker has decoded, until the input ends.
void displayUntilDone(pipeline::LivePipeline& live, outputs::LiveDisplay& display, const HeadlessArguments& arguments,
                      std::chrono::steady_clock::time_point started, DisplayRun& run) {
  const bool fromDevice = arguments.input.empty();
  run.startMegabytes = residentMegabytes();
  pipeline::AnimationFrame frame;
  const auto tick = std::chrono::microseconds(
      arguments.speed > 0.0 ? static_cast<long>(16667.0 / std::max(arguments.speed, 1.0)) : 500L);
  auto next = std::chrono::steady_clock::now();
  const auto take = [&] {
    while (live.nextFrame(frame)) {
      run.decodeMs.add(static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
      display.present(frame, frame.timeSeconds);
      if (!arguments.dump.empty()) run.shown.push_back(frame);
      if (++run.framesShown == 60 * 30) run.minuteMegabytes = residentMegabytes();  // a minute of sound in
    }
  };
  while (!live.done()) {
    take();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    // A device runs until --duration or an interrupt; a recording until it ends (or an interrupt).
    if (InterruptGuard::requested() || (fromDevice && arguments.duration > 0.0 && elapsed >= arguments.duration))
      live.endInput();
    live.supervise();
    printEvents(live);
    next += tick;
    std::this_thread::sleep_until(next);
  }
  take();
}

}  // namespace

void runHeadless(const HeadlessArguments& arguments, const outputs::LiveSessionSettings& settings) {
  const bool fromDevice = arguments.input.empty();
  if (fromDevice && arguments.speed != 1.0)
    throw Error("live: --speed is for --input files; a device runs in real time");
  if (!arguments.dump.empty()) {
    formats::animationFormatFor(arguments.dump);
    checkOutputTarget(arguments.dump);
  }
  const auto models = std::make_shared<const pipeline::AnimationModels>(pipeline::loadModels(settings));
  InterruptGuard interrupts;

  pipeline::LivePipelineOptions options{.decoder = settings.decoderOptions(),
                                        .speed = arguments.speed,
                                        .blockSamples = 256,
                                        .giveUpSeconds = arguments.reconnectSeconds};
  double seconds = 0.0;
  pipeline::LiveSource source = sourceOf(arguments, settings, options, seconds);
  pipeline::LivePipeline live(models, std::move(source), options);
  live.supervise();
  printEvents(live);
  // A sound input that will not open at the start is an error, not something to wait for.
  if (!live.running()) throw Error(live.sourceError().empty() ? "live: the source did not start" : live.sourceError());
  const auto issuedToken = std::make_shared<outputs::IssuedToken>();
  // The idle motion and the outputs as the window has them; the idle clock is the stream's own time, so a
  // recording played at any speed gives the same frames.
  outputs::LiveDisplay display(settings.idle, settings.live.blinks, settings.live.gaze);
  display.setOutputs(
      settings.outputs.open({.faps = live.fapNumbers(),
                             .tokenIssued = [issuedToken](const std::string& token) { issuedToken->set(token); }}));
  const std::string sourceName =
      fromDevice ? live.sourceName() + " (" + std::to_string(static_cast<int>(live.rateHz())) + " Hz)"
                 : live.sourceName();
  const auto started = std::chrono::steady_clock::now();
  DisplayRun run;
  displayUntilDone(live, display, arguments, started, run);

  const double runSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::vector<std::string> outputLines;
  for (const outputs::OutputStatus& status : display.statuses())
    outputLines.push_back(outputs::describe(status, runSeconds));
  display.closeOutputs();  // VTube Studio's thread ends before its token is read
  const double endMegabytes = residentMegabytes();
  if (fromDevice) seconds = live.deviceSeconds();

  printReport({.sourceName = sourceName,
               .seconds = seconds,
               .speed = arguments.speed,
               .fromDevice = fromDevice,
               .framesShown = run.framesShown,
               .decodeMs = &run.decodeMs,
               .startMegabytes = run.startMegabytes,
               .minuteMegabytes = run.minuteMegabytes,
               .endMegabytes = endMegabytes,
               .outputLines = outputLines},
              live);
  if (const std::string token = issuedToken->get(); !token.empty() && !arguments.settingsPath.empty()) {
    outputs::LiveSessionSettings kept = loadLiveSettings(arguments.settingsPath);
    kept.outputs.get<outputs::VtsSettings>().token = token;
    saveLiveSettings(arguments.settingsPath, kept);
    std::printf("  VTube Studio's token kept in %s\n", arguments.settingsPath.string().c_str());
  }
  std::fflush(stdout);
  if (!live.failure().empty()) throw Error(sourceName + ": " + live.failure() + "; no dump written");

  if (!arguments.dump.empty()) {
    formats::writeAnimation(arguments.dump, trackOf(run.shown, display.fapNumbers(live.fapNumbers()),
                                                    std::filesystem::path(arguments.input).stem().string()));
    std::printf("wrote %s: %zu frames\n", arguments.dump.c_str(), run.shown.size());
  }
}

}  // namespace th::app
