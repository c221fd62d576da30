// What the live decoder costs per audio block, as an AudioWorklet calls it: a recording at 16 kHz taken up to the
// context's rate (the engine's sinc resampler), then fed in blocks of 128 samples through the resampler back to
// 16 kHz, the live decoder with a preset's models and the display's idle motion, each frame made into the avatar
// frame the outputs send. Each block is timed with the steady clock, in each of --passes passes over the recording
// (a new decoder each: the same work block for block), and its cost is the least of its passes: what the block
// costs, without what slows it from outside (the scheduler, another process, a slower second of a shared machine).
// The p99 of the slowest pass, timed as it came, is reported beside it. The web package's benchmark page runs the
// same steps in WebAssembly, alike; tests/web puts both side by side.
//
//   build/bench/block_cost WAV [--preset default] [--rate 48000] [--block 128] [--passes 5]
//
// Prints one JSON line: {"blocks": N, "passes": P, "median_ms": ..., "p99_ms": ..., "max_ms": ..., "mean_ms": ...,
// "slowest_pass_p99_ms": ...}.
// (A plain program, as latency_bench: it measures a distribution of wall-clock times, not a loop's speed.)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include "audio/audio_file.h"
#include "audio/sinc_resampler.h"
#include "core/error.h"
#include "outputs/avatar_frame.h"
#include "outputs/live_display.h"
#include "pipeline/live_decoder.h"
#include "pipeline/options.h"

namespace {

int run(int argc, char** argv) {
  std::string wav, preset = "default";
  double rate = 48000.0;
  std::size_t block = 128;
  int passes = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw th::Error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--preset")
      preset = value();
    else if (arg == "--rate")
      rate = std::stod(value());
    else if (arg == "--block")
      block = std::stoul(value());
    else if (arg == "--passes")
      passes = std::stoi(value());
    else if (wav.empty())
      wav = arg;
    else
      throw th::Error("usage: block_cost WAV [--preset P] [--rate HZ] [--block N] [--passes N]");
  }
  if (wav.empty() || block < 1 || block > 4096 || passes < 1 || passes > 100)
    throw th::Error("usage: block_cost WAV [--preset P] [--rate HZ] [--block N] [--passes N]");
  const th::audio::AudioClip clip = th::audio::readAudioFile(wav);
  const std::vector<float> input = th::audio::sincResample(clip.samples, clip.sampleRateHz, rate);

  th::pipeline::LiveSettings settings;
  th::pipeline::applyLivePreset(settings, preset);
  settings.check();
  const th::pipeline::AnimationModels models = th::pipeline::loadModels(settings);
  std::vector<std::vector<double>> perPass;
  float sink = 0.0f;
  for (int pass = 0; pass < passes; ++pass) {
    th::pipeline::LiveDecoder decoder(models.head.get(), models.mouth.get(), settings.decoderOptions(),
                                      models.visemes.get(), models.articulation.get());
    th::outputs::LiveDisplay display(settings.idle, settings.live.blinks, settings.live.gaze);
    th::audio::SincResampler resampler(rate, 16000.0);
    std::vector<float> resampled(resampler.maxOutput(block));
    th::pipeline::AnimationFrame frame;
    std::vector<double>& times = perPass.emplace_back();
    for (std::size_t at = 0; at + block <= input.size(); at += block) {
      const auto start = std::chrono::steady_clock::now();
      const std::size_t n = resampler.process(std::span<const float>(input).subspan(at, block), resampled);
      decoder.acceptWaveform(std::span<const float>(resampled.data(), n));
      while (decoder.next(frame)) {
        display.present(frame, frame.timeSeconds);
        sink += th::outputs::avatarFrameOf(frame).jawOpen();
      }
      times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
  }
  std::vector<double> costs(perPass.front().size());
  for (std::size_t b = 0; b < costs.size(); ++b) {
    costs[b] = perPass.front()[b];
    for (const auto& pass : perPass) costs[b] = std::min(costs[b], pass[b]);
  }
  if (costs.empty()) throw th::Error(wav + ": shorter than a block");
  const auto quantile = [](std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
  };
  double slowestPass = 0.0;
  for (const auto& pass : perPass) slowestPass = std::max(slowestPass, quantile(pass, 0.99));
  double sum = 0.0;
  for (const double c : costs) sum += c;
  std::printf(
      "{\"blocks\": %zu, \"passes\": %d, \"median_ms\": %.5f, \"p99_ms\": %.5f, \"max_ms\": %.5f, \"mean_ms\": %.5f, "
      "\"slowest_pass_p99_ms\": %.5f, \"jaw\": %.3f}\n",
      costs.size(), passes, quantile(costs, 0.5), quantile(costs, 0.99), *std::max_element(costs.begin(), costs.end()),
      sum / static_cast<double>(costs.size()), slowestPass, static_cast<double>(sink));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::cerr << "block_cost: " << error.what() << '\n';
    return 1;
  }
}
