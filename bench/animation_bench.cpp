// Speed of the animation models on BEAT2: training the head model, and synthesising head motion from prosody
// with every variant, batch and online (realtime_factor = seconds of animation per second of CPU).
//
//   taskset -c 0 build/bench/animation_bench [--quick]      (scripts/bench.sh animation)
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>

#include "animation/head_data.h"
#include "animation/head_model.h"
#include "bench_arguments.h"

namespace {

using th::animation::HeadVariant;

struct Data {
  th::animation::HeadRecording train;
  th::animation::HeadRecording test;
  th::animation::HeadModel model;
};

const Data& data() {
  static const Data loaded = [] {
    auto [train, test] = th::animation::splitByTime(th::animation::loadBeat2Head(), 0.75);
    Data result{train, test, th::animation::trainHeadModel({train}, {})};
    return result;
  }();
  return loaded;
}

void trainHead(benchmark::State& state) {
  const Data& d = data();
  for (auto _ : state) {
    const th::animation::HeadModel model = th::animation::trainHeadModel({d.train}, {});
    benchmark::DoNotOptimize(model.hmm.numStates());
  }
  state.counters["frames"] = d.train.numFrames();
}

void synthesiseHead(benchmark::State& state, HeadVariant variant, int lag) {
  const Data& d = data();
  for (auto _ : state) {
    const Eigen::MatrixXd rotations =
        th::animation::synthesiseHead(d.model, d.test.prosody, {.variant = variant, .maxLagFrames = lag});
    benchmark::DoNotOptimize(rotations.data());
  }
  const double seconds = d.test.numFrames() / d.test.framesPerSecond;
  state.counters["realtime_factor"] = benchmark::Counter(seconds, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  const BenchArguments arguments = parseBenchArguments(argc, argv, "animation_bench");
  if (!arguments.ok) return 1;
  const double minTime = arguments.quick ? 0.01 : 0.5;
  benchmark::RegisterBenchmark("head/train_on_47.7s", trainHead)->Unit(benchmark::kMillisecond)->Iterations(arguments.quick ? 1 : 3);
  const struct {
    const char* name;
    HeadVariant variant;
  } variants[] = {{"state_means", HeadVariant::kStateMeans},
                  {"trajectory", HeadVariant::kTrajectory},
                  {"posterior_means", HeadVariant::kPosteriorMeans}};
  for (const auto& v : variants) {
    for (int lag : {-1, 6}) {
      const std::string name = std::string("head/synthesise_15.9s/") + v.name + (lag < 0 ? "/batch" : "/online_lag6");
      benchmark::RegisterBenchmark(name.c_str(), synthesiseHead, v.variant, lag)
          ->Unit(benchmark::kMillisecond)
          ->MinTime(minTime);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
