#include "outputs/headless_run.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <thread>
#include <vector>

#include "animation/speech_analysis.h"
#include "audio/media_audio.h"
#include "core/error.h"
#include "core/print_to.h"
#include "core/statistics.h"
#include "formats/animation_format.h"
#include "outputs/live_display.h"
#include "pipeline/live.h"

namespace th::outputs {
namespace {

// This process's resident memory, MB (Linux: /proc/self/status), or -1 where it cannot be read.
double residentMegabytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // "VmRSS:  12345 kB"
  return -1.0;
}

void writeEvents(pipeline::LivePipeline& live, std::ostream& log) {
  for (const pipeline::LiveEvent& event : live.events())
    if (event.kind != pipeline::LiveEventKind::kStarted) log << "talkinghead: " << event.text << '\n';
}

face::FapTrack trackOfFrames(const std::vector<pipeline::AnimationFrame>& frames, const std::vector<int>& faps,
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
struct HeadlessReport {
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

// The run's report: the source and pace, the frames, the look-ahead, the decoding time, memory, outputs.
void writeReport(std::ostream& out, const HeadlessReport& report, pipeline::LivePipeline& live) {
  const pipeline::SessionCounters counters = live.counters();
  char pace[64] = "as fast as possible, not";
  if (report.speed > 0.0) std::snprintf(pace, sizeof(pace), "%gx", report.speed);
  printTo(out, "live (headless): %s, %.2f s of sound at %s real time\n", report.sourceName.c_str(), report.seconds,
          pace);
  printTo(out, "  frames: %llu decoded, %llu shown, %llu dropped; samples: %llu in, %llu overrun\n",
          static_cast<unsigned long long>(counters.framesDecoded), static_cast<unsigned long long>(report.framesShown),
          static_cast<unsigned long long>(counters.framesDropped), static_cast<unsigned long long>(counters.samplesIn),
          static_cast<unsigned long long>(counters.overrunSamples));
  if (report.fromDevice)
    printTo(out, "  sound inputs: %llu opened, %llu lost\n", static_cast<unsigned long long>(live.sourcesOpened()),
            static_cast<unsigned long long>(live.sourcesLost()));
  const pipeline::DecoderLookahead& lookahead = live.lookahead();
  printTo(out,
          "  look-ahead: mouth %.1f ms (features %.1f ms + %d frames), head %.1f ms (features %.1f ms + %d frames)",
          lookahead.mouthMs, lookahead.mouthFeaturesMs, lookahead.mouthFrames, lookahead.headMs, lookahead.featuresMs,
          lookahead.headFrames);
  if (lookahead.headDelayFrames > 0) printTo(out, ", the head shown %d frames late", lookahead.headDelayFrames);
  printTo(out, ": %.1f ms\n", lookahead.totalMs);
  printTo(out, "  decoding, from the read to the frame out: median %.2f ms, 95th percentile %.2f ms, max %.2f ms\n",
          report.decodeMs->percentile(50), report.decodeMs->percentile(95), report.decodeMs->largest());
  char afterAMinute[32] = "-";
  if (report.minuteMegabytes >= 0.0)
    std::snprintf(afterAMinute, sizeof afterAMinute, "%.1f MB", report.minuteMegabytes);
  printTo(out, "  memory (resident): %.1f MB at the start, %s after the first minute of sound, %.1f MB at the end\n",
          report.startMegabytes, afterAMinute, report.endMegabytes);
  for (const std::string& line : report.outputLines) printTo(out, "  output %s\n", line.c_str());
}

// The source the run reads: the recording (cut to `duration`, its sound's seconds over all passes in `seconds`)
// or the sound input.
pipeline::LiveSource sourceOf(const HeadlessRun& run, const LiveSessionSettings& settings,
                              pipeline::LivePipelineOptions& options, double& seconds) {
  pipeline::LiveSource source;
  if (run.input.empty()) {
    source.device = settings.live.deviceIndex();
    return source;
  }
  audio::AudioClip clip = audio::readRecording(run.input);
  if (clip.samples.empty()) throw fileError(run.input, "has no samples");
  if (run.duration > 0.0)
    clip.samples.resize(std::min(clip.samples.size(), static_cast<std::size_t>(run.duration * clip.sampleRateHz)));
  seconds = std::max(static_cast<double>(clip.samples.size()) / clip.sampleRateHz, run.repeatTo);
  options.repeatToSamples = static_cast<std::size_t>(run.repeatTo * clip.sampleRateHz);
  source.recording = std::move(clip.samples);
  source.name = run.input;
  return source;
}

// What the display loop saw.
struct DisplayLoopResult {
  std::vector<pipeline::AnimationFrame> shown;  // kept only for a dump: a soak of an hour would otherwise keep it
  std::uint64_t framesShown = 0;
  MillisecondHistogram decodeMs;  // from the read to the frame out
  double minuteMegabytes = -1.0;
  double runSeconds = 0.0;
};

// The display loop: 60 Hz in the recording's time (faster when it plays faster; at full speed as often as it
// can), taking whatever the worker has decoded, until the input ends.
DisplayLoopResult runDisplayLoop(const HeadlessRun& run, pipeline::LivePipeline& live, LiveDisplay& display,
                                 const HeadlessHooks& hooks, std::ostream& log) {
  const bool fromDevice = run.input.empty();
  DisplayLoopResult result;
  const auto started = std::chrono::steady_clock::now();
  pipeline::AnimationFrame frame;
  const auto tick =
      std::chrono::microseconds(run.speed > 0.0 ? static_cast<long>(16667.0 / std::max(run.speed, 1.0)) : 500L);
  auto next = std::chrono::steady_clock::now();
  const auto take = [&] {
    while (live.nextFrame(frame)) {
      result.decodeMs.add(static_cast<double>(frame.decodedNs - frame.inputReadNs) * 1e-6);
      display.present(frame, frame.timeSeconds);
      if (!run.dump.empty()) result.shown.push_back(frame);
      if (++result.framesShown == 60 * 30) result.minuteMegabytes = residentMegabytes();  // a minute of sound in
    }
  };
  while (!live.done()) {
    take();
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    // A device runs until --duration or a stop; a recording until it ends (or a stop).
    const bool stop = hooks.stopRequested && hooks.stopRequested();
    if (stop || (fromDevice && run.duration > 0.0 && elapsed >= run.duration)) live.endInput();
    live.supervise();
    writeEvents(live, log);
    next += tick;
    std::this_thread::sleep_until(next);
  }
  take();
  result.runSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace

void runHeadless(const HeadlessRun& run, const LiveSessionSettings& settings,
                 std::shared_ptr<const pipeline::AnimationModels> models, const HeadlessHooks& hooks, std::ostream& out,
                 std::ostream& log) {
  const bool fromDevice = run.input.empty();
  pipeline::LivePipelineOptions options{.decoder = settings.decoderOptions(),
                                        .speed = run.speed,
                                        .blockSamples = 256,
                                        .giveUpSeconds = run.reconnectSeconds};
  double seconds = 0.0;  // of a recording's sound, all passes
  pipeline::LiveSource source = sourceOf(run, settings, options, seconds);
  pipeline::LivePipeline live(std::move(models), std::move(source), options);
  live.supervise();
  writeEvents(live, log);
  // A sound input that will not open at the start is an error, not something to wait for.
  if (!live.running()) throw Error(live.sourceError().empty() ? "live: the source did not start" : live.sourceError());
  const auto issuedToken = std::make_shared<IssuedToken>();
  // The idle motion and the outputs as the window has them; the idle clock is the stream's own time, so a
  // recording played at any speed gives the same frames.
  LiveDisplay display(settings.idle, settings.live.blinks, settings.live.gaze);
  display.setOutputs(
      settings.outputs.open({.faps = live.fapNumbers(),
                             .tokenIssued = [issuedToken](const std::string& token) { issuedToken->set(token); }}));
  const std::string sourceName =
      fromDevice ? live.sourceName() + " (" + std::to_string(static_cast<int>(live.rateHz())) + " Hz)"
                 : live.sourceName();
  const double startMegabytes = residentMegabytes();
  const DisplayLoopResult loop = runDisplayLoop(run, live, display, hooks, log);
  std::vector<std::string> outputLines;
  for (const OutputStatus& status : display.statuses()) outputLines.push_back(describe(status, loop.runSeconds));
  display.closeOutputs();  // VTube Studio's thread ends before its token is read
  const double endMegabytes = residentMegabytes();
  if (fromDevice) seconds = live.deviceSeconds();

  writeReport(out,
              {.sourceName = sourceName,
               .seconds = seconds,
               .speed = run.speed,
               .fromDevice = fromDevice,
               .framesShown = loop.framesShown,
               .decodeMs = &loop.decodeMs,
               .startMegabytes = startMegabytes,
               .minuteMegabytes = loop.minuteMegabytes,
               .endMegabytes = endMegabytes,
               .outputLines = outputLines},
              live);
  if (const std::string token = issuedToken->get(); !token.empty() && hooks.keepToken) hooks.keepToken(token);
  out.flush();
  if (!live.failure().empty()) throw Error(sourceName + ": " + live.failure() + "; no dump written");

  if (!run.dump.empty()) {
    formats::writeAnimation(run.dump, trackOfFrames(loop.shown, display.fapNumbers(live.fapNumbers()),
                                                    std::filesystem::path(run.input).stem().string()));
    printTo(out, "wrote %s: %zu frames\n", run.dump.c_str(), loop.shown.size());
  }
}

}  // namespace th::outputs
