// What the live decoder costs per audio block, as an AudioWorklet calls it: a recording at 16 kHz taken up to the
// context's rate (the engine's sinc resampler), then fed in blocks of 128 samples through the resampler back to
// 16 kHz, the live decoder with a preset's models and the display's idle motion, each frame made into the avatar
// frame the outputs send. Each block is timed with the steady clock. The web package's benchmark page runs the
// same steps in WebAssembly; tests/web puts both side by side.
//
//   build/bench/block_cost WAV [--preset default] [--rate 48000] [--block 128]
//
// Prints one JSON line: {"blocks": N, "median_ms": ..., "p99_ms": ..., "max_ms": ..., "mean_ms": ...}.
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
    else if (wav.empty())
      wav = arg;
    else
      throw th::Error("usage: block_cost WAV [--preset P] [--rate HZ] [--block N]");
  }
  if (wav.empty() || block < 1 || block > 4096)
    throw th::Error("usage: block_cost WAV [--preset P] [--rate HZ] [--block N]");
  const th::audio::AudioClip clip = th::audio::readAudioFile(wav);
  const std::vector<float> input = th::audio::sincResample(clip.samples, clip.sampleRateHz, rate);

  th::pipeline::LiveSettings settings;
  th::pipeline::applyLivePreset(settings, preset);
  settings.check();
  const th::pipeline::AnimationModels models = th::pipeline::loadModels(settings);
  th::pipeline::LiveDecoder decoder(models.head.get(), models.mouth.get(), settings.decoderOptions(),
                                    models.visemes.get(), models.articulation.get());
  th::outputs::LiveDisplay display(settings.idle, settings.live.blinks, settings.live.gaze);
  th::audio::SincResampler resampler(rate, 16000.0);
  std::vector<float> resampled(resampler.maxOutput(block));
  th::pipeline::AnimationFrame frame;
  std::vector<double> costs;
  float sink = 0.0f;
  for (std::size_t at = 0; at + block <= input.size(); at += block) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t n = resampler.process(std::span<const float>(input).subspan(at, block), resampled);
    decoder.acceptWaveform(std::span<const float>(resampled.data(), n));
    while (decoder.next(frame)) {
      display.present(frame, frame.timeSeconds);
      sink += th::outputs::avatarFrameOf(frame).jawOpen();
    }
    costs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  if (costs.empty()) throw th::Error(wav + ": shorter than a block");
  std::vector<double> sorted = costs;
  std::sort(sorted.begin(), sorted.end());
  const auto quantile = [&](double q) {
    return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  };
  double sum = 0.0;
  for (const double c : costs) sum += c;
  std::printf(
      "{\"blocks\": %zu, \"median_ms\": %.5f, \"p99_ms\": %.5f, \"max_ms\": %.5f, \"mean_ms\": %.5f, \"jaw\": %.3f}\n",
      costs.size(), quantile(0.5), quantile(0.99), sorted.back(), sum / static_cast<double>(costs.size()),
      static_cast<double>(sink));
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
