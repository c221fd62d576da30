// Speed of the animation models on BEAT2 (realtime_factor = seconds of animation per second of CPU):
// - head: training the head model, and synthesising head motion from prosody with every variant, batch and online;
// - mouth: training the default mouth model exactly as `talkinghead train mouth` does (N = 5, M = 2, full
//   covariance, tc = 2, on the first 75 % of the take; counter `frames`), and synthesising the mouth's visual
//   components from the held-out part's MFCC by batch inversion from the conditional-mean start (ours) and from
//   the random start (the paper's), by windowed (streaming) inversion with `eval mouth --window`'s default of
//   30 frames, and by the MMSE estimate. The mouth model is trained in-process, not read from models/mouth.json.
// - articulation: the shipped models/articulation*.json on the take's last 16 s of sound, from samples to the
//   visemes and the closed lips (the speech subframes, the network, the class HMM, the lips: what the articulation
//   adds to animate), batch and as the live stream decodes it frame by frame (with articulation_live.json).
//
//   taskset -c 0 build/bench/animation_bench [--quick]      (scripts/bench.sh animation)
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>

#include "animation/articulation.h"
#include "animation/head_data.h"
#include "animation/head_model.h"
#include "animation/mouth_data.h"
#include "animation/mouth_model.h"
#include "animation/online_stages.h"
#include "audio/audio_file.h"
#include "bench_arguments.h"
#include "core/data_path.h"
#include "eval/head_corpus.h"
#include "eval/mouth_corpus.h"

namespace {

using th::animation::HeadVariant;

struct Data {
  th::animation::HeadRecording train;
  th::animation::HeadRecording test;
  th::animation::HeadModel model;
};

const Data& data() {
  static const Data loaded = [] {
    auto [train, test] = th::animation::splitByTime(th::eval::loadBeat2Head(), 0.75);
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
    const Eigen::MatrixXd rotations = th::animation::synthesiseHead(d.model, d.test.prosody, d.test.voiced,
                                                                    {.variant = variant, .maxLagFrames = lag});
    benchmark::DoNotOptimize(rotations.data());
  }
  const double seconds = d.test.numFrames() / d.test.framesPerSecond;
  state.counters["realtime_factor"] = benchmark::Counter(seconds, benchmark::Counter::kIsIterationInvariantRate);
}

// The defaults of `talkinghead train mouth` (app/mouth_command.cpp, MouthArguments): keep them in step.
constexpr double kMouthTrainingFraction = 0.75;
constexpr int kMouthWindowFrames = 30;  // `talkinghead eval mouth --window` default
th::animation::MouthModelOptions defaultMouthOptions() {
  return {.states = 5, .mixtures = 2, .covariance = th::hmm::CovarianceType::kFull, .contextFrames = 2};
}

struct MouthData {
  th::animation::MouthRecording train;
  th::animation::MouthRecording test;
  th::animation::MouthModel model;
};

const MouthData& mouthData() {
  static const MouthData loaded = [] {
    auto [train, test] = th::animation::splitByTime(th::eval::loadBeat2Mouth(), kMouthTrainingFraction);
    MouthData result{train, test, th::animation::trainMouthModel({train}, defaultMouthOptions())};
    return result;
  }();
  return loaded;
}

void trainMouth(benchmark::State& state) {
  const MouthData& d = mouthData();
  for (auto _ : state) {
    const th::animation::MouthModel model = th::animation::trainMouthModel({d.train}, defaultMouthOptions());
    benchmark::DoNotOptimize(model.hmm.numStates());
  }
  state.counters["frames"] = d.train.numFrames();
  state.counters["bw_iterations"] = d.model.iterations;
}

void synthesiseMouth(benchmark::State& state, th::animation::MouthSynthesisOptions options) {
  const MouthData& d = mouthData();
  for (auto _ : state) {
    const Eigen::MatrixXd components = th::animation::synthesiseMouth(d.model, d.test.speech, options);
    benchmark::DoNotOptimize(components.data());
  }
  const double seconds = d.test.numFrames() / d.test.framesPerSecond;
  state.counters["realtime_factor"] = benchmark::Counter(seconds, benchmark::Counter::kIsIterationInvariantRate);
}

struct ArticulationData {
  std::vector<float> samples;  // 16 kHz
  th::animation::MouthNetwork batch, live;
  std::vector<int> fapNumbers;
  Eigen::MatrixXd faps;  // the mouth's FAPs to articulate: the visual basis's mean on every frame
};

const ArticulationData& articulationData() {
  static const ArticulationData loaded = [] {
    ArticulationData result;
    const std::vector<float> all = th::audio::readAudioFile(th::sharedDataPath("beat2/2_scott_0_1_1.wav")).samples;
    const std::size_t last = std::min<std::size_t>(all.size(), 16 * 16000);
    result.samples.assign(all.end() - static_cast<long>(last), all.end());
    const std::string models = TALKINGHEAD_SOURCE_DIR "/models/";
    result.batch = th::animation::loadMouthNetwork(models + "articulation.json");
    result.live = th::animation::loadMouthNetwork(models + "articulation_live.json");
    result.fapNumbers = result.batch.visualFaps;
    result.faps = result.batch.basis.mean().replicate(1, static_cast<Eigen::Index>(last / 16000 * 30));
    return result;
  }();
  return loaded;
}

void articulateBatch(benchmark::State& state) {
  const ArticulationData& d = articulationData();
  for (auto _ : state) {
    const th::animation::SpeechFrames subframes = th::animation::speechSubframesOf(d.samples);
    const th::animation::MouthNetworkOutput heard = th::animation::runMouthNetwork(d.batch, subframes);
    const th::face::VisemeTrack visemes = th::animation::networkVisemes(d.batch, heard.classes, {});
    Eigen::MatrixXd faps = d.faps;
    th::animation::articulateLips(d.batch, visemes.classes, d.fapNumbers, faps, {});
    benchmark::DoNotOptimize(faps.data());
  }
  state.counters["realtime_factor"] = benchmark::Counter(static_cast<double>(d.samples.size()) / 16000.0,
                                                         benchmark::Counter::kIsIterationInvariantRate);
}

void articulateStream(benchmark::State& state) {
  const ArticulationData& d = articulationData();
  for (auto _ : state) {
    // As the live decoder wires them: subframes into the network's stage, its frames into the visemes' stage.
    th::features::OnlineFeatureExtractor extractor(th::animation::subframeFeatureOptions());
    th::animation::MouthNetworkStage network(d.live);
    th::animation::ArticulationVisemeStage visemes(d.live, {}, 0);
    std::vector<float> row(th::animation::kNetworkMfcc);
    th::animation::SpeechFrame subframe;
    subframe.mfcc.resize(th::animation::kNetworkMfcc);
    th::animation::MouthNetworkFrame heard;
    th::animation::VisemeFrame shown;
    int subframes = 0, heardFrames = 0, frames = 0;
    for (std::size_t at = 0; at < d.samples.size(); at += 160) {  // 10 ms blocks, as a sound device gives them
      extractor.acceptWaveform(
          std::span<const float>(d.samples).subspan(at, std::min<std::size_t>(160, d.samples.size() - at)));
      for (; subframes < extractor.numBaseFramesReady(); ++subframes) {
        extractor.getMfcc(subframes, row);
        for (Eigen::Index k = 0; k < subframe.mfcc.size(); ++k) subframe.mfcc[k] = row[static_cast<std::size_t>(k)];
        subframe.levelDb = extractor.getLevelDb(subframes);
        network.accept(subframe);
      }
      extractor.forgetBefore(subframes);
      for (; heardFrames < network.numFramesReady(); ++heardFrames) {
        network.getFrame(heardFrames, heard);
        visemes.accept(heard);
      }
      network.forgetBefore(heardFrames);
      for (; frames < visemes.numFramesReady(); ++frames) visemes.getFrame(frames, shown);
      visemes.forgetBefore(frames);
    }
    benchmark::DoNotOptimize(frames);
  }
  state.counters["realtime_factor"] = benchmark::Counter(static_cast<double>(d.samples.size()) / 16000.0,
                                                         benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  const BenchArguments arguments = parseBenchArguments(argc, argv, "animation_bench");
  if (!arguments.ok) return 1;
  const double minTime = arguments.quick ? 0.01 : 0.5;
  benchmark::RegisterBenchmark("head/train_on_47.7s", trainHead)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(arguments.quick ? 1 : 3);
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
  using th::animation::MouthMethod;
  using th::hmm::InversionStart;
  benchmark::RegisterBenchmark("mouth/train_default", trainMouth)
      ->Unit(benchmark::kMillisecond)
      ->Iterations(arguments.quick ? 1 : 3);
  const struct {
    std::string name;
    th::animation::MouthSynthesisOptions options;
  } mouthMethods[] = {
      {"mouth/inversion_batch_conditional_start", {.start = InversionStart::kConditionalMean}},
      {"mouth/inversion_batch_random_start", {.start = InversionStart::kRandom}},
      {"mouth/inversion_window" + std::to_string(kMouthWindowFrames), {.windowFrames = kMouthWindowFrames}},
      {"mouth/mmse", {.method = MouthMethod::kMmse}},
  };
  for (const auto& m : mouthMethods) {
    benchmark::RegisterBenchmark(m.name.c_str(), synthesiseMouth, m.options)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(minTime);
  }
  benchmark::RegisterBenchmark("articulation/batch_16s", articulateBatch)
      ->Unit(benchmark::kMillisecond)
      ->MinTime(minTime);
  benchmark::RegisterBenchmark("articulation/stream_16s", articulateStream)
      ->Unit(benchmark::kMillisecond)
      ->MinTime(minTime);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
