// How fast the HMM engine is: one Baum-Welch iteration of ours against the numpy reference (tools/hmm_reference.py)
// in the same run, and the per-frame cost of decoding (online Viterbi, emission log-likelihoods) at the papers'
// model sizes.
//
//   taskset -c 0 build/bench/hmm_bench                 # or: bash scripts/bench.sh hmm; ~2 min
//   build/bench/hmm_bench --quick                      # one pass of each, a smoke check
//
// Baum-Welch cases: N=12, M=1, d=4, full, T=100 000 (the head model) and N=4, M=2, d=123, full,
// T=20 000 (the mouth model). Data: one sequence sampled from a random model of that size (tests/hmm
// randomModel), which is also the starting model; both implementations do the same work (E-step over all
// frames, ML M-step of π, A, weights, means, covariances). Ours is timed in CPU time of this thread; the numpy
// reference runs as a subprocess (/usr/bin/python3, Debian's numpy) with OPENBLAS_NUM_THREADS=OMP_NUM_THREADS=
// MKL_NUM_THREADS=1, and times each iteration itself in CPU time (time.process_time: the iteration only, not
// start-up or reading the CSV); its times are fed to Google Benchmark as manual time. The summary names the
// BLAS/LAPACK library numpy loaded: Debian's default is the netlib reference BLAS, not OpenBLAS.
//
// Per-frame cases: OnlineViterbi::acceptFrame at N=12 and N=20 (maximum lag 30 frames, 1 s at 30 fps), and
// HmmModel::emissionLogLikelihoods for one frame at a time (the streaming call) and over a whole block.
// Thread contract: single-threaded; pin it to one core (the budgets are "on one core").
#include <benchmark/benchmark.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_arguments.h"
#include "core/error.h"
#include "core/temporary_file.h"
#include "hmm/inversion.h"
#include "hmm/model_file.h"
#include "hmm/sampling.h"
#include "hmm/training.h"
#include "hmm/viterbi.h"
#include "hmm_test_models.h"

namespace {

using th::hmm::CovarianceType;
using th::hmm::HmmModel;

constexpr const char* kPython = "/usr/bin/python3";
constexpr const char* kOneThread = "OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 MKL_NUM_THREADS=1";
constexpr int kMaxLagFrames = 30;
constexpr double kTargetRatio = 10.0;
constexpr double kFrameBudgetMs = 1.0;

std::string shellQuote(const std::string& argument) {
  std::string quoted = "'";
  for (char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

struct ModelSize {
  int numStates;
  int numMixtures;
  int dimension;
  CovarianceType covariance;
  std::string describe() const {
    return "N=" + std::to_string(numStates) + " M=" + std::to_string(numMixtures) + " d=" + std::to_string(dimension) +
           (covariance == CovarianceType::kFull ? " full" : " diag");
  }
};

HmmModel randomModelOf(const ModelSize& size, unsigned seed) {
  return th::test::randomModel(size.numStates, size.numMixtures, size.dimension, size.covariance, seed);
}

// A Baum-Welch case: the model, its sample, and the files the reference reads.
struct BaumWelchCase {
  std::string name;
  ModelSize size;
  int numFrames;
  HmmModel start;
  std::vector<Eigen::MatrixXd> sequences;
  Eigen::VectorXd varianceFloor;
  th::hmm::TrainingOptions options;
  std::unique_ptr<th::TemporaryFile> modelFile;
  std::unique_ptr<th::TemporaryFile> dataFile;

  BaumWelchCase(std::string caseName, const ModelSize& modelSize, int frames, unsigned seed)
      : name(std::move(caseName)), size(modelSize), numFrames(frames) {
    start = randomModelOf(size, seed);
    std::mt19937 random(seed + 1);
    sequences.push_back(th::hmm::sampleHmm(start, numFrames, random).frames);
    varianceFloor = th::hmm::varianceFloorFor(sequences, options.varianceFloorFraction);
    options.numStates = size.numStates;
    options.numMixtures = size.numMixtures;
    options.covariance = size.covariance;
    for (int k = 0; k < size.dimension; ++k) start.columnNames.push_back("x" + std::to_string(k));
    modelFile = std::make_unique<th::TemporaryFile>(".json");
    dataFile = std::make_unique<th::TemporaryFile>(".csv");
    th::hmm::saveModel(modelFile->path(), start);
    writeCsv(dataFile->path());
  }

  void writeCsv(const std::filesystem::path& path) const {
    std::ofstream out(path);
    for (int k = 0; k < size.dimension; ++k) out << (k > 0 ? "," : "") << start.columnNames[static_cast<size_t>(k)];
    out << '\n';
    char number[32];
    const Eigen::MatrixXd& frames = sequences.front();
    for (Eigen::Index t = 0; t < frames.cols(); ++t) {
      for (Eigen::Index k = 0; k < frames.rows(); ++k) {
        std::snprintf(number, sizeof number, "%.17g", frames(k, t));
        out << (k > 0 ? "," : "") << number;
      }
      out << '\n';
    }
    if (!out) throw th::Error(path.string() + ": cannot write the benchmark data");
  }
};

void benchOurBaumWelch(benchmark::State& state, const BaumWelchCase* c) {
  for (auto _ : state) {
    HmmModel model = c->start;  // a copy: microseconds next to the iteration
    const th::hmm::IterationRecord record = th::hmm::baumWelchIteration(model, c->sequences, c->varianceFloor, {});
    benchmark::DoNotOptimize(record.logLikelihood);
  }
  state.counters["frames"] = c->numFrames;
}

// What the numpy reference reported about itself.
struct NumpyRun {
  std::vector<double> cpuSeconds;
  std::string numpyVersion;
  std::string blas;  // the libraries it loaded
  std::string blasThreads;
};
std::map<std::string, NumpyRun> numpyRuns;  // by case name, for the summary

NumpyRun runNumpyIterations(const BaumWelchCase& c, int repeat) {
  const th::TemporaryFile errors(".log");
  const std::string command = std::string(kOneThread) + " " + shellQuote(kPython) + " " +
                              shellQuote(std::string(TALKINGHEAD_SOURCE_DIR) + "/tools/hmm_reference.py") +
                              " bw-iteration " + shellQuote(c.modelFile->path().string()) + " " +
                              shellQuote(c.dataFile->path().string()) + " --threads 1 --json --repeat " +
                              std::to_string(repeat) + " </dev/null 2>" + shellQuote(errors.path().string());
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) throw th::Error("cannot start " + std::string(kPython));
  std::string output;
  char buffer[4096];
  size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, got);
  const int status = ::pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::ifstream in(errors.path());
    std::stringstream text;
    text << in.rdbuf();
    throw th::Error("numpy reference failed: " + text.str());
  }
  const nlohmann::json report = nlohmann::json::parse(output);
  NumpyRun run;
  run.cpuSeconds = report.at("cpu_seconds").get<std::vector<double>>();
  run.numpyVersion = report.at("numpy").get<std::string>();
  for (const auto& library : report.at("blas")) run.blas += (run.blas.empty() ? "" : ", ") + library.get<std::string>();
  run.blasThreads = report.at("blas_threads").is_string() ? report.at("blas_threads").get<std::string>() : "unset";
  return run;
}

// Registered with Iterations(repeat): the reference runs once, `repeat` iterations, each reported as manual time.
void benchNumpyBaumWelch(benchmark::State& state, const BaumWelchCase* c) {
  NumpyRun run;
  try {
    run = runNumpyIterations(*c, static_cast<int>(state.max_iterations));
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    for (auto _ : state) {
    }
    return;
  }
  size_t next = 0;
  for (auto _ : state) state.SetIterationTime(run.cpuSeconds.at(next++ % run.cpuSeconds.size()));
  state.SetLabel("numpy " + run.numpyVersion + ", BLAS threads " + run.blasThreads);
  state.counters["frames"] = c->numFrames;
  numpyRuns[c->name] = run;
}

// Per-frame cases share one sample of each model size.
struct FrameCase {
  ModelSize size;
  HmmModel model;
  Eigen::MatrixXd frames;        // d x T
  Eigen::MatrixXd logEmissions;  // N x T
  explicit FrameCase(const ModelSize& modelSize, int numFrames, unsigned seed) : size(modelSize) {
    model = randomModelOf(size, seed);
    std::mt19937 random(seed + 1);
    frames = th::hmm::sampleHmm(model, numFrames, random).frames;
    logEmissions = model.emissionLogLikelihoods(frames);
  }
};

void benchOnlineViterbi(benchmark::State& state, const FrameCase* c) {
  const Eigen::Index numFrames = c->logEmissions.cols();
  for (auto _ : state) {
    th::hmm::OnlineViterbi decoder(c->model, {.maxLagFrames = kMaxLagFrames});
    for (Eigen::Index t = 0; t < numFrames; ++t) decoder.acceptFrame(c->logEmissions.col(t));
    decoder.finish();
    benchmark::DoNotOptimize(decoder.numDecided());
  }
  state.counters["frames"] = static_cast<double>(numFrames);
}

// One call per frame, as the live decoder makes it.
void benchEmissionsPerFrame(benchmark::State& state, const FrameCase* c) {
  const Eigen::Index numFrames = c->frames.cols();
  for (auto _ : state) {
    for (Eigen::Index t = 0; t < numFrames; ++t) {
      const Eigen::MatrixXd logB = c->model.emissionLogLikelihoods(c->frames.col(t));
      benchmark::DoNotOptimize(logB.data());
    }
  }
  state.counters["frames"] = static_cast<double>(numFrames);
}

// One call for the whole block (training, batch decoding).
void benchEmissionsBatch(benchmark::State& state, const FrameCase* c) {
  for (auto _ : state) {
    const Eigen::MatrixXd logB = c->model.emissionLogLikelihoods(c->frames);
    benchmark::DoNotOptimize(logB.data());
  }
  state.counters["frames"] = static_cast<double>(c->frames.cols());
}

// The last two dimensions as the visual block, the rest as audio: the papers' mouth model (121 + 2).
th::hmm::HmmModel withAudioVisualBlocks(th::hmm::HmmModel model) {
  const int d = model.dimension();
  model.blocks = {{"audio", 0, d - 2}, {"visual", d - 2, 2}};
  return model;
}

// Windowed inversion (state(0) frames per window; 0 = MMSE) over the whole sample, per frame.
void benchInversion(benchmark::State& state, const FrameCase* c) {
  const int window = static_cast<int>(state.range(0));
  const th::hmm::HmmInverter inverter(withAudioVisualBlocks(c->model), {.windowFrames = window});
  const Eigen::MatrixXd audio = c->frames.topRows(c->frames.rows() - 2);
  for (auto _ : state) {
    const Eigen::MatrixXd visual = window > 0 ? inverter.invert(audio).visual : inverter.mmse(audio);
    benchmark::DoNotOptimize(visual.data());
  }
  state.counters["frames"] = static_cast<double>(audio.cols());
}

struct Measured {
  double seconds = 0.0;  // per iteration: CPU for ours, the manual (reported) time for numpy
  double frames = 0.0;
};

// Passes every report on to the display reporter and keeps what the summary needs.
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
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name != "median") continue;
      const std::string name = run.run_name.function_name;
      if (run.run_type != Run::RT_Aggregate && medianSeen_.count(name) > 0) continue;
      if (run.run_type == Run::RT_Aggregate) medianSeen_[name] = true;
      const double toSeconds = 1.0 / benchmark::GetTimeUnitMultiplier(run.time_unit);
      Measured m;
      const bool manualTime = name.rfind("bw_numpy/", 0) == 0;  // the reference's own CPU seconds
      m.seconds = (manualTime ? run.GetAdjustedRealTime() : run.GetAdjustedCPUTime()) * toSeconds;
      const auto frames = run.counters.find("frames");
      if (frames != run.counters.end()) m.frames = frames->second.value;
      results_[name] = m;
    }
  }
  int errors() const { return errors_; }
  std::optional<Measured> find(const std::string& name) const {
    const auto it = results_.find(name);
    return it == results_.end() ? std::nullopt : std::optional<Measured>(it->second);
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

void printSummary(const SummaryReporter& reporter, const std::vector<std::unique_ptr<BaumWelchCase>>& cases,
                  const std::vector<std::pair<std::string, std::string>>& frameRows, std::ostream& out) {
  char line[256];
  out << "\nSummary (one core; CPU time). One Baum-Welch iteration, ours vs the numpy reference "
         "(tools/hmm_reference.py):\n";
  std::snprintf(line, sizeof line, "  %-34s %12s %12s %11s  %s\n", "case", "ours", "numpy", "numpy/ours", "target");
  out << line;
  std::string numpyNote;
  for (const auto& c : cases) {
    const auto ours = reporter.find("bw_ours/" + c->name);
    const auto numpy = reporter.find("bw_numpy/" + c->name);
    if (!ours || !numpy) continue;
    const double ratio = numpy->seconds / ours->seconds;
    std::snprintf(line, sizeof line, "  %-34s %9.1f ms %9.1f ms %10.1fx  >= %.0fx %s\n",
                  (c->size.describe() + ", T=" + std::to_string(c->numFrames)).c_str(), ours->seconds * 1e3,
                  numpy->seconds * 1e3, ratio, kTargetRatio, ratio >= kTargetRatio ? "met" : "NOT MET");
    out << line;
    const auto run = numpyRuns.find(c->name);
    if (run != numpyRuns.end()) {
      const std::string& blas = run->second.blas;
      const std::string kind = blas.find("openblas") != std::string::npos ? "OpenBLAS"
                               : blas.find("/blas/") != std::string::npos
                                   ? "the netlib reference BLAS/LAPACK (Debian's default libblas3)"
                                   : "an unrecognised BLAS";
      numpyNote = "numpy " + run->second.numpyVersion + ", BLAS threads " + run->second.blasThreads + ", on " + kind +
                  ":\n    " + blas;
    }
  }
  if (!numpyNote.empty()) out << "  " << numpyNote << "\n";
  out << "Per frame (budget " << kFrameBudgetMs << " ms per frame for decoding, on one core):\n";
  for (const auto& [name, what] : frameRows) {
    const auto m = reporter.find(name);
    if (!m || m->frames <= 0.0) continue;
    std::snprintf(line, sizeof line, "  %-58s %9.2f us/frame\n", what.c_str(), m->seconds / m->frames * 1e6);
    out << line;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const BenchArguments arguments = parseBenchArguments(argc, argv, "hmm_bench");
  if (!arguments.ok) return 1;
  const bool quick = arguments.quick;
  const std::string& format = arguments.format;

  try {
    // The papers' sizes: head model N=12 single full Gaussians on d=4 prosody; mouth model N=4 M=2 full (or
    // N=19 M=3 diagonal) on d=123 (11 MFCCs with ±5 frames of context, plus the visual components).
    std::vector<std::unique_ptr<BaumWelchCase>> cases;
    cases.push_back(std::make_unique<BaumWelchCase>("N12_M1_d4_full_T100000",
                                                    ModelSize{12, 1, 4, CovarianceType::kFull}, 100000, 11));
    cases.push_back(std::make_unique<BaumWelchCase>("N4_M2_d123_full_T20000",
                                                    ModelSize{4, 2, 123, CovarianceType::kFull}, 20000, 12));
    const int numpyRepeat = quick ? 1 : 3;
    for (const auto& c : cases) {
      auto* ours = benchmark::RegisterBenchmark(("bw_ours/" + c->name).c_str(), benchOurBaumWelch, c.get());
      ours->Unit(benchmark::kMillisecond);
      if (quick) {
        ours->Iterations(1);
      } else {
        ours->MinTime(3.0);
      }
      benchmark::RegisterBenchmark(("bw_numpy/" + c->name).c_str(), benchNumpyBaumWelch, c.get())
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime()
          ->Iterations(numpyRepeat);
    }

    const int numFrames = 3000;  // 100 s at 30 fps
    std::map<std::string, std::unique_ptr<FrameCase>> frameCases;
    const auto frameCase = [&](const ModelSize& size) -> const FrameCase* {
      auto& slot = frameCases[size.describe()];
      if (!slot) slot = std::make_unique<FrameCase>(size, numFrames, 21 + static_cast<unsigned>(frameCases.size()));
      return slot.get();
    };
    std::vector<std::pair<std::string, std::string>> frameRows;
    const auto registerFrameBench = [&](const std::string& name, const std::string& what, auto function,
                                        const FrameCase* c) {
      auto* b = benchmark::RegisterBenchmark(name.c_str(), function, c);
      b->Unit(benchmark::kMicrosecond);
      if (quick) {
        b->Iterations(1);
      } else {
        b->MinTime(1.0);
      }
      frameRows.emplace_back(name, what);
    };
    const std::string lag = " (max lag " + std::to_string(kMaxLagFrames) + ")";
    for (const ModelSize& size :
         {ModelSize{12, 1, 4, CovarianceType::kFull}, ModelSize{20, 1, 123, CovarianceType::kFull}}) {
      registerFrameBench("online_viterbi/N" + std::to_string(size.numStates),
                         "OnlineViterbi::acceptFrame, N=" + std::to_string(size.numStates) + lag, benchOnlineViterbi,
                         frameCase(size));
    }
    for (const ModelSize& size :
         {ModelSize{12, 1, 4, CovarianceType::kFull}, ModelSize{4, 2, 123, CovarianceType::kFull},
          ModelSize{19, 3, 123, CovarianceType::kDiagonal}}) {
      std::string id = size.describe();
      for (char& ch : id) ch = ch == ' ' || ch == '=' ? '_' : ch;
      registerFrameBench("emissions_one_frame/" + id, "emissions, one frame per call, " + size.describe(),
                         benchEmissionsPerFrame, frameCase(size));
      registerFrameBench("emissions_block/" + id,
                         "emissions, " + std::to_string(numFrames) + " frames per call, " + size.describe(),
                         benchEmissionsBatch, frameCase(size));
    }

    for (const ModelSize& size :
         {ModelSize{4, 2, 123, CovarianceType::kFull}, ModelSize{19, 3, 123, CovarianceType::kDiagonal}}) {
      std::string id = size.describe();
      for (char& ch : id) ch = ch == ' ' || ch == '=' ? '_' : ch;
      for (int window : {0, 10, 30}) {
        const std::string name = "inversion/" + id + "/" + std::to_string(window);
        const std::string what = (window == 0 ? std::string("MMSE estimate, ")
                                              : "inversion, window " + std::to_string(window) + " frames, ") +
                                 size.describe();
        auto* b = benchmark::RegisterBenchmark(name.c_str(), benchInversion, frameCase(size));
        b->Arg(window)->Unit(benchmark::kMillisecond);
        if (quick) {
          b->Iterations(1);
        } else {
          b->MinTime(1.0);
        }
        frameRows.emplace_back(name, what);
      }
    }

    SummaryReporter reporter(makeDisplayReporter(format));
    benchmark::RunSpecifiedBenchmarks(&reporter);
    printSummary(reporter, cases, frameRows, format == "console" ? std::cout : std::cerr);
    benchmark::Shutdown();
    if (reporter.errors() > 0) {
      std::cerr << "hmm_bench: " << reporter.errors() << " benchmark(s) failed\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "hmm_bench: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
