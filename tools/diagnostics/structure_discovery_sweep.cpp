// Structure discovery over many draws: 3 samples of 20 000 frames from the sparse 6-state HMM x 4 k-means++
// seeds, 20 fully connected starting states, the annealed entropic prior at Z = fraction x frames (default 0.1),
// with and without state merging. Prints one line per run and a summary. Not a test (it takes minutes); the
// structure-discovery figures in docs/hmm.md come from it.
//
//   build/tools/diagnostics/structure_discovery_sweep [fraction ...]
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "hmm/entropic_training.h"
#include "structure_report.h"

namespace {

struct Run {
  unsigned dataSeed;
  unsigned initSeed;
  double fraction;
  int mergeCandidates;
  th::test::StructureReport report{};
  int iterations = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> fractions;
  for (int i = 1; i < argc; ++i) fractions.push_back(std::atof(argv[i]));
  if (fractions.empty()) fractions = {0.1};
  const th::hmm::HmmModel truth = th::test::sparseSixStateModel();
  std::vector<Run> runs;
  for (double fraction : fractions) {
    for (int merges : {0, 8}) {
      for (unsigned dataSeed : {2024u, 1u, 2u}) {
        for (unsigned initSeed : {5u, 1u, 2u, 3u}) runs.push_back({dataSeed, initSeed, fraction, merges});
      }
    }
  }
  std::mutex mutex;
  size_t next = 0;
  auto worker = [&] {
    for (;;) {
      size_t index = 0;
      {
        const std::lock_guard lock(mutex);
        if (next == runs.size()) return;
        index = next++;
      }
      Run& run = runs[index];
      std::mt19937 random(run.dataSeed);
      const th::hmm::Sample sample = th::hmm::sampleHmm(truth, 20000, random);
      th::hmm::TrainingOptions options;
      options.numStates = 20;
      options.maxIterations = 150;
      options.seed = run.initSeed;
      const double z = run.fraction * static_cast<double>(sample.frames.cols());
      const th::hmm::TrainingResult result =
          th::hmm::trainHmm({sample.frames}, options,
                            th::hmm::entropicHooks({.multinomialWeight = z,
                                                    .warmupIterations = 10,
                                                    .rampIterations = 20,
                                                    .mergeCandidates = run.mergeCandidates}));
      run.report = th::test::compareStructure(truth, result.model, sample);
      run.iterations = static_cast<int>(result.history.size()) - 1;
      const std::lock_guard lock(mutex);
      std::printf(
          "Z = %.3f T, merging %-3s, data seed %4u, k-means seed %u: %2d states, %2d transitions, %d of 9 true "
          "edges, %d spurious, %3d iterations\n",
          run.fraction, run.mergeCandidates > 0 ? "on" : "off", run.dataSeed, run.initSeed, run.report.liveStates,
          run.report.transitions, run.report.recoveredEdges, run.report.spuriousEdges, run.iterations);
      std::fflush(stdout);
    }
  };
  std::vector<std::thread> threads;
  const unsigned numThreads = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned i = 0; i < numThreads; ++i) threads.emplace_back(worker);
  for (auto& thread : threads) thread.join();

  std::printf("\nsummary (runs with at most 8 states / exactly the true 6 states and 15 transitions / all 9 edges):\n");
  for (double fraction : fractions) {
    for (int merges : {0, 8}) {
      int total = 0;
      int small = 0;
      int exact = 0;
      int edges = 0;
      for (const Run& run : runs) {
        if (run.fraction != fraction || run.mergeCandidates != merges) continue;
        ++total;
        small += run.report.liveStates <= 8;
        exact += run.report.liveStates == 6 && run.report.transitions == 15;
        edges += run.report.recoveredEdges == 9;
      }
      std::printf("Z = %.3f T, merging %-3s: %2d / %d at most 8 states, %2d / %d exact, %2d / %d all true edges\n",
                  fraction, merges > 0 ? "on" : "off", small, total, exact, total, edges, total);
    }
  }
  return 0;
}
