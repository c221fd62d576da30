// How fast the speech features are, next to the pitch trackers Debian ships (Praat, SPTK's RAPT).
//
//   taskset -c 0 build/bench/features_bench            # or scripts/bench.sh; ~30 s
//   build/bench/features_bench --quick                 # one short pass, a smoke check (scripts/test.sh)
//
// Input: the first 60 s of ../shared/data/beat2/2_scott_0_1_1.wav (16 kHz mono speech; TALKINGHEAD_DATA
// overrides the folder). Every benchmark reports `realtime_factor` = audio seconds / seconds per iteration,
// and a summary table follows the run. Our benchmarks are timed in CPU time of this thread; the peers run as
// subprocesses, so they are timed in wall-clock time, and their time includes starting the program, reading
// the file and (for RAPT) our own conversion of the WAV to SPTK's raw floats. The *_startup benchmarks run the
// same tools on 0.1 s of audio, so the reader can subtract the fixed cost.
//
// Thread contract: single-threaded; pin it to one core (the budget is "on one core").
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "bench_arguments.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "eval/peer_trackers.h"
#include "features/mfcc.h"
#include "features/online_features.h"
#include "features/pitch.h"

namespace {

constexpr int kRateHz = th::audio::kEngineSampleRateHz;
constexpr double kAudioSeconds = 60.0;
constexpr double kStartupAudioSeconds = 0.1;
constexpr const char* kRecording = "beat2/2_scott_0_1_1.wav";
const th::eval::PeerSettings kPeerSettings{0.005, 60.0, 500.0};

// A WAV in the temporary folder, removed when it goes out of scope.
class TemporaryWav {
 public:
  explicit TemporaryWav(const std::vector<float>& samples) : file_(".wav") {
    th::audio::writeWav16(file_.path(), samples, kRateHz);
  }
  const std::filesystem::path& path() const { return file_.path(); }

 private:
  th::TemporaryFile file_;
};

// realtime_factor = audio seconds per second of the benchmark's own clock (CPU, or wall for UseRealTime()).
void setRealtimeFactor(benchmark::State& state, double audioSeconds) {
  state.counters["realtime_factor"] = benchmark::Counter(audioSeconds, benchmark::Counter::kIsIterationInvariantRate);
}

void benchFeatures(benchmark::State& state, const std::vector<float>& samples) {
  const th::features::FeatureOptions options = th::features::batchFeatureOptions();
  for (auto _ : state) {
    th::features::FeatureMatrix matrix = th::features::computeFeatures(samples, options);
    benchmark::DoNotOptimize(matrix.values.data());
  }
  setRealtimeFactor(state, kAudioSeconds);
}

void benchPitch(benchmark::State& state, const std::vector<float>& samples) {
  const th::features::PitchOptions options = th::features::batchFeatureOptions().pitch;
  for (auto _ : state) {
    std::vector<th::features::PitchFrame> frames = th::features::trackPitch(samples, kRateHz, options);
    benchmark::DoNotOptimize(frames.data());
  }
  setRealtimeFactor(state, kAudioSeconds);
}

// MFCCs alone, framed as the feature extractor frames them: one window per animation frame (30 fps), centred
// on the frame's time, zero outside the signal.
void benchMfcc(benchmark::State& state, const std::vector<float>& samples) {
  const th::features::FeatureOptions options = th::features::batchFeatureOptions();
  th::features::MfccComputer mfcc(options.mfcc, kRateHz);
  const auto length = static_cast<long long>(mfcc.windowLength());
  const auto numSamples = static_cast<long long>(samples.size());
  const auto numFrames =
      static_cast<long long>((static_cast<double>(numSamples) - 1.0) * options.framesPerSecond / kRateHz) + 1;
  std::vector<float> window(static_cast<size_t>(length));
  std::vector<float> coefficients(static_cast<size_t>(mfcc.numOutputs()));
  for (auto _ : state) {
    for (long long frame = 0; frame < numFrames; ++frame) {
      const long long start = std::llround(static_cast<double>(frame) * kRateHz / options.framesPerSecond) - length / 2;
      for (long long n = 0; n < length; ++n) {
        const long long index = start + n;
        window[static_cast<size_t>(n)] = index >= 0 && index < numSamples ? samples[static_cast<size_t>(index)] : 0.0f;
      }
      mfcc.compute(window, coefficients);
      benchmark::DoNotOptimize(coefficients.data());
    }
  }
  setRealtimeFactor(state, kAudioSeconds);
}

// CPU seconds used by finished (waited-for) child processes and their descendants so far.
double childCpuSeconds() {
  rusage usage{};
  ::getrusage(RUSAGE_CHILDREN, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// Timed in wall-clock time (the work happens in another process); the CPU time the subprocesses used is
// reported too (child_cpu_ms per iteration), which does not grow when the machine is busy.
void benchPeer(benchmark::State& state, th::eval::PeerTracker peer, const std::filesystem::path& wav,
               double audioSeconds) {
  const double childCpuBefore = childCpuSeconds();
  for (auto _ : state) {
    try {
      th::eval::F0Track track = th::eval::runPeerTracker(peer, wav, kPeerSettings);
      benchmark::DoNotOptimize(track.f0Hz.data());
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());  // e.g. the program is not installed: report it, run the others
      break;
    }
  }
  setRealtimeFactor(state, audioSeconds);
  state.counters["child_cpu_ms"] =
      benchmark::Counter(1e3 * (childCpuSeconds() - childCpuBefore), benchmark::Counter::kAvgIterations);
}

// What the summary needs from one benchmark: its realtime factor and wall/CPU seconds per iteration.
struct Measured {
  double realtimeFactor = 0.0;
  double realSeconds = 0.0;
  double cpuSeconds = 0.0;       // this process
  double childCpuSeconds = 0.0;  // subprocesses (peers only)
  long long iterations = 0;
};

// Passes every report to the reporter the user asked for (--benchmark_format) and keeps what the summary needs.
class SummaryReporter : public benchmark::BenchmarkReporter {
 public:
  explicit SummaryReporter(std::unique_ptr<benchmark::BenchmarkReporter> inner) : inner_(std::move(inner)) {}

  bool ReportContext(const Context& context) override { return inner_->ReportContext(context); }
  void Finalize() override { inner_->Finalize(); }

  void ReportRuns(const std::vector<Run>& runs) override {
    inner_->ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.error_occurred) {
        ++errors_;
        continue;
      }
      // Prefer the median when --benchmark_repetitions asked for aggregates; else the last plain run.
      const bool isMedian = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      if (run.run_type == Run::RT_Aggregate && !isMedian) continue;
      const std::string& name = run.run_name.function_name;
      if (!isMedian && medianSeen_.count(name) > 0) continue;
      if (isMedian) medianSeen_.insert({name, true});
      Measured measured;
      const double toSeconds = 1.0 / benchmark::GetTimeUnitMultiplier(run.time_unit);
      measured.realSeconds = run.GetAdjustedRealTime() * toSeconds;
      measured.cpuSeconds = run.GetAdjustedCPUTime() * toSeconds;
      measured.iterations = static_cast<long long>(run.iterations);
      const auto counter = run.counters.find("realtime_factor");
      if (counter != run.counters.end()) measured.realtimeFactor = counter->second.value;
      const auto child = run.counters.find("child_cpu_ms");
      if (child != run.counters.end()) measured.childCpuSeconds = child->second.value * 1e-3;
      results_[name] = measured;
    }
  }

  int errors() const { return errors_; }

  std::optional<Measured> find(const std::string& name) const {
    const auto it = results_.find(name);
    if (it == results_.end()) return std::nullopt;
    return it->second;
  }

 private:
  std::unique_ptr<benchmark::BenchmarkReporter> inner_;
  std::map<std::string, Measured> results_;
  std::map<std::string, bool> medianSeen_;
  int errors_ = 0;
};

std::unique_ptr<benchmark::BenchmarkReporter> makeDisplayReporter(const std::string& format) {
  if (format == "json") return std::make_unique<benchmark::JSONReporter>();
  const bool colour = ::isatty(STDOUT_FILENO) != 0;
  return std::make_unique<benchmark::ConsoleReporter>(colour ? benchmark::ConsoleReporter::OO_ColorTabular
                                                             : benchmark::ConsoleReporter::OO_Tabular);
}

std::string times(double factor) {
  char text[32];
  std::snprintf(text, sizeof text, factor >= 100.0 ? "%.0fx" : "%.1fx", factor);
  return text;
}

// The table after the run. Goes to stdout with the console format, else to stderr (the JSON stays parseable).
void printSummary(const SummaryReporter& reporter, std::ostream& out) {
  const auto ours = reporter.find("features");
  const auto pitch = reporter.find("features_pitch_only");
  const auto mfcc = reporter.find("features_mfcc_only");
  const auto praat = reporter.find("praat_pitch");
  const auto rapt = reporter.find("rapt_pitch");
  const auto praatStartup = reporter.find("praat_startup");
  const auto raptStartup = reporter.find("rapt_startup");
  char line[256];
  out << "\nSummary: " << kAudioSeconds << " s of speech (" << kRecording << "), times per " << kAudioSeconds
      << " s of audio\n";
  const auto row = [&](const char* what, const std::optional<Measured>& m, bool wall) {
    if (!m) return;
    std::snprintf(line, sizeof line, "  %-44s %8s real time  %8.1f ms %s\n", what, times(m->realtimeFactor).c_str(),
                  (wall ? m->realSeconds : m->cpuSeconds) * 1e3, wall ? "wall" : "CPU");
    out << line;
  };
  row("ours: F0 + energy + MFCC + deltas + context", ours, false);
  row("ours: pitch (F0) alone", pitch, false);
  row("ours: MFCC alone (30 fps frames)", mfcc, false);
  row("Praat To Pitch (ac), subprocess", praat, true);
  row("SPTK RAPT (sptk pitch -a 0), subprocess", rapt, true);
  const auto startupRow = [&](const char* what, const std::optional<Measured>& m) {
    if (!m) return;
    std::snprintf(line, sizeof line, "  %-44s %8.1f ms wall (on %.1f s of audio)\n", what, m->realSeconds * 1e3,
                  kStartupAudioSeconds);
    out << line;
  };
  startupRow("Praat start-up + file I/O", praatStartup);
  startupRow("RAPT start-up + file I/O", raptStartup);
  // Net of start-up: what the tool's own analysis costs, if start-up were free.
  const auto net = [](const std::optional<Measured>& all, const std::optional<Measured>& startup) -> double {
    if (!all || !startup) return 0.0;
    const double seconds = all->realSeconds - startup->realSeconds;
    return seconds > 0.0 ? kAudioSeconds / seconds : 0.0;
  };
  const double praatNet = net(praat, praatStartup);
  const double raptNet = net(rapt, raptStartup);
  if (praatNet > 0.0 || raptNet > 0.0) {
    out << "  without start-up: Praat " << times(praatNet) << ", RAPT " << times(raptNet) << " real time\n";
  }
  if (ours && praat && rapt && praat->realtimeFactor > 0.0) {
    out << "ours " << times(ours->realtimeFactor) << " real time, Praat " << times(praat->realtimeFactor) << ", RAPT "
        << times(rapt->realtimeFactor) << "; ours/Praat = ";
    std::snprintf(line, sizeof line, "%.1f", ours->realtimeFactor / praat->realtimeFactor);
    out << line << "\n";
  }
  // By CPU time (ours in-process; a peer's subprocess plus our part of the call): robust on a busy machine.
  const auto cpuFactor = [](const std::optional<Measured>& m) {
    const double seconds = m ? m->cpuSeconds + m->childCpuSeconds : 0.0;
    return seconds > 0.0 ? kAudioSeconds / seconds : 0.0;
  };
  if (ours && praat && rapt) {
    out << "by CPU time: ours " << times(cpuFactor(ours)) << ", Praat " << times(cpuFactor(praat)) << ", RAPT "
        << times(cpuFactor(rapt)) << " real time\n";
  }
  if (pitch && praatNet > 0.0) {
    std::snprintf(line, sizeof line, "%.1f", pitch->realtimeFactor / praatNet);
    out << "pitch alone vs Praat without start-up: ours " << times(pitch->realtimeFactor) << ", Praat "
        << times(praatNet) << "; ratio " << line << "\n";
  }
}

std::vector<float> loadSpeech() {
  const std::filesystem::path wav = th::sharedDataPath(kRecording);
  std::vector<float> samples = th::audio::readAudioFile(wav).samples;
  const auto wanted = static_cast<size_t>(kAudioSeconds * kRateHz);
  if (samples.size() < wanted) {
    throw th::Error(wav.string() + ": shorter than " + std::to_string(kAudioSeconds) + " s");
  }
  samples.resize(wanted);
  return samples;
}

}  // namespace

int main(int argc, char** argv) {
  const BenchArguments arguments = parseBenchArguments(argc, argv, "features_bench");
  if (!arguments.ok) return 1;
  const bool quick = arguments.quick;
  const std::string& format = arguments.format;

  try {
    const std::vector<float> speech = loadSpeech();
    const std::vector<float> start(speech.begin(), speech.begin() + static_cast<long>(kStartupAudioSeconds * kRateHz));
    const TemporaryWav speechWav(speech);
    const TemporaryWav startWav(start);

    // Minimum measuring time per benchmark: long enough for several subprocess runs, unless --quick.
    const double ourMinSeconds = quick ? 0.0 : 2.0;
    const double peerMinSeconds = quick ? 0.0 : 4.0;
    const auto configure = [&](benchmark::internal::Benchmark* b, double minSeconds, bool wall) {
      b->Unit(benchmark::kMillisecond);
      if (quick) {
        b->Iterations(1);
      } else {
        b->MinTime(minSeconds);
      }
      if (wall) b->UseRealTime();
    };
    configure(benchmark::RegisterBenchmark("features", benchFeatures, speech), ourMinSeconds, false);
    configure(benchmark::RegisterBenchmark("features_pitch_only", benchPitch, speech), ourMinSeconds, false);
    configure(benchmark::RegisterBenchmark("features_mfcc_only", benchMfcc, speech), ourMinSeconds, false);
    configure(benchmark::RegisterBenchmark("praat_pitch", benchPeer, th::eval::PeerTracker::kPraat, speechWav.path(),
                                           kAudioSeconds),
              peerMinSeconds, true);
    configure(benchmark::RegisterBenchmark("rapt_pitch", benchPeer, th::eval::PeerTracker::kRapt, speechWav.path(),
                                           kAudioSeconds),
              peerMinSeconds, true);
    configure(benchmark::RegisterBenchmark("praat_startup", benchPeer, th::eval::PeerTracker::kPraat, startWav.path(),
                                           kStartupAudioSeconds),
              peerMinSeconds / 2, true);
    configure(benchmark::RegisterBenchmark("rapt_startup", benchPeer, th::eval::PeerTracker::kRapt, startWav.path(),
                                           kStartupAudioSeconds),
              peerMinSeconds / 2, true);

    SummaryReporter reporter(makeDisplayReporter(format));
    benchmark::RunSpecifiedBenchmarks(&reporter);
    printSummary(reporter, format == "console" ? std::cout : std::cerr);
    benchmark::Shutdown();
    if (reporter.errors() > 0) {
      std::cerr << "features_bench: " << reporter.errors() << " benchmark(s) failed\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "features_bench: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
