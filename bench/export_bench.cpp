// Speed of the MP4 export at 640x480 and 1280x720, 30 fps: the whole export on 10 s of real speech (animation,
// off-screen rendering, encoding: export/face/...), the same at 1280x720 with each test character instead of our
// face (../shared/data/face/avatars: export/character/brunette|vroid/..., the character read from its file in
// each pass, as `talkinghead export --avatar` does), and its encoding alone, H.264 (libx264, the default preset
// and quality) + AAC through Mp4Writer, on synthetic frames (export/WxH/gradient|textured/...). At the end, each
// character's export time over our face's at 1280x720 ("ratio").
//
//   build/bench/export_bench            # ~3 min; NOT pinned to one core: x264 is multi-threaded
//   build/bench/export_bench --quick    # one short pass, a smoke check
//
// realtime_factor = seconds of video per wall-clock second (UseRealTime: libx264 runs its own threads), for
// the whole writer: RGB->YUV conversion, both encoders, muxing and the final faststart rewrite. The frames are
// made before timing (see Content: x264 is unrealistically fast on constant frames and unrealistically slow on
// noise). threads:auto lets FFmpeg choose (all cores); threads:1 is one x264 thread, for comparison; faster
// presets than the default (veryfast) show the speed/size trade-off. realtime_factor_per_core = video seconds
// per CPU second of all threads: what one dedicated core would do, a fair figure on a busy machine.
// Budget: the whole export >= 2x real time including rendering, so this alone should be >= 8x at 720p on two
// cores. Thread contract: run alone; the numbers depend on the cores free.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <future>
#include <map>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "audio/media_audio.h"
#include "avatar/avatar_model.h"
#include "bench_arguments.h"
#include "core/cpu_time.h"
#include "core/data_path.h"
#include "core/temporary_file.h"
#include "face/face_model.h"
#include "face/feature_points.h"
#include "formats/mp4_writer.h"
#include "pipeline/offline.h"
#include "pipeline/video_export.h"

namespace {

constexpr double kFps = 30.0;
constexpr int kAudioRateHz = 16000;
constexpr int kDistinctFrames = 60;  // made once, then cycled (2 s: longer than x264's reference window)

// What the frames show. kGradient: a diagonal gradient that moves across the whole frame and a lit, shaded
// disc circling over it (smooth shading and an edge, as a rendered head on a background has). kTextured adds
// soft diagonal ripples that move at their own speed, which motion search cannot follow: a harder case.
enum class Content { kGradient, kTextured };

// Frame f of the synthetic clip, RGB24, top row first.
std::vector<std::uint8_t> syntheticFrame(int width, int height, int f, Content content) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  const double phase = 2.0 * std::numbers::pi * f / kDistinctFrames;
  const double cx = width * (0.5 + 0.2 * std::cos(phase));
  const double cy = height * (0.5 + 0.15 * std::sin(phase));
  const double radius = height / 4.0;
  std::size_t at = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double r = 40.0 + 150.0 * (x + y + 4.0 * f) / (width + height + 4.0 * kDistinctFrames);
      double g = 60.0 + 100.0 * y / height;
      double b = content == Content::kTextured ? 128.0 + 50.0 * std::sin((x + 2.0 * y) / 37.0 + 0.2 * f) : 128.0;
      const double dx = (x - cx) / radius;
      const double dy = (y - cy) / radius;
      const double d2 = dx * dx + dy * dy;
      if (d2 < 1.0) {  // a lit sphere: skin colour, brighter towards the upper left
        const double shade = 0.55 + 0.45 * std::sqrt(1.0 - d2) - 0.15 * (dx + dy);
        r = 230.0 * shade;
        g = 180.0 * shade;
        b = 150.0 * shade;
      }
      rgb[at++] = static_cast<std::uint8_t>(std::clamp(r, 0.0, 255.0));
      rgb[at++] = static_cast<std::uint8_t>(std::clamp(g, 0.0, 255.0));
      rgb[at++] = static_cast<std::uint8_t>(std::clamp(b, 0.0, 255.0));
    }
  }
  return rgb;
}

struct Case {
  int width;
  int height;
  Content content;
  std::string preset;
  int threads;  // 0: FFmpeg decides
};

void exportClip(benchmark::State& state, const Case& c, double seconds) {
  const int width = c.width;
  const int height = c.height;
  std::vector<std::vector<std::uint8_t>> frames;
  for (int f = 0; f < kDistinctFrames; ++f) frames.push_back(syntheticFrame(width, height, f, c.content));
  std::vector<float> audio(static_cast<std::size_t>(seconds * kAudioRateHz));
  for (std::size_t n = 0; n < audio.size(); ++n) {
    const double t = static_cast<double>(n) / kAudioRateHz;
    audio[n] = static_cast<float>(0.3 * std::sin(2.0 * std::numbers::pi * 180.0 * t) * (0.6 + 0.4 * std::sin(7.0 * t)));
  }
  const auto frameCount = th::formats::videoFramesFor(audio.size(), kAudioRateHz, kFps);
  th::formats::Mp4Options options;
  options.width = width;
  options.height = height;
  options.framesPerSecond = kFps;
  options.audioSampleRateHz = kAudioRateHz;
  options.threads = c.threads;
  options.preset = c.preset;
  th::TemporaryFolder folder;
  std::uintmax_t bytes = 0;
  double cpuSeconds = 0.0;
  for (auto _ : state) {
    const double cpuBefore = th::processCpuSeconds();
    const auto path = folder.path() / "bench.mp4";
    th::formats::Mp4Writer writer(path, options);
    const std::size_t perFrame = audio.size() / static_cast<std::size_t>(frameCount) + 1;
    for (std::int64_t f = 0; f < frameCount; ++f) {
      writer.addVideoFrame(frames[static_cast<std::size_t>(f % kDistinctFrames)].data(), width * 3);
      const std::size_t begin = std::min(audio.size(), static_cast<std::size_t>(f) * perFrame);
      writer.addAudio(std::span<const float>(audio).subspan(begin, std::min(perFrame, audio.size() - begin)));
    }
    writer.finish();
    bytes = std::filesystem::file_size(path);
    cpuSeconds += th::processCpuSeconds() - cpuBefore;
  }
  const double videoSeconds = static_cast<double>(frameCount) / kFps;
  state.counters["realtime_factor"] = benchmark::Counter(videoSeconds, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(frameCount), benchmark::Counter::kIsIterationInvariantRate);
  // Video seconds per CPU second of all threads: what one dedicated core would do, whatever else is running.
  state.counters["realtime_factor_per_core"] =
      videoSeconds * static_cast<double>(state.iterations()) / std::max(cpuSeconds, 1e-9);
  state.counters["kbit_per_s"] = static_cast<double>(bytes) * 8.0 / 1000.0 / videoSeconds;
}

// Seconds a pass of the whole export, by case name, for the ratios printed at the end.
std::map<std::string, double>& exportSeconds() {
  static std::map<std::string, double> seconds;
  return seconds;
}

// The whole export as `talkinghead export` runs it, on real speech: the face model built (on another thread)
// while the animation comes from the shipped models, every frame rendered off-screen (llvmpipe), finished and encoded
// (exportVideo, with its default settings: FXAA, x264 veryfast with subme=1, CRF 20). Only reading the recording is
// left out. With `character` (a file in ../shared/data/face/avatars), that character is read and drawn instead of
// our face. realtime_factor: seconds of video per wall-clock second.
void exportFace(benchmark::State& state, int width, int height, double seconds, const std::string& character,
                const std::string& name) {
  th::audio::AudioClip clip = th::audio::readRecording(th::sharedDataPath("beat2/audio_only/2_scott_0_2_2.wav"));
  clip.samples.resize(std::min(clip.samples.size(), static_cast<std::size_t>(seconds * clip.sampleRateHz)));
  const auto head = th::animation::loadHeadModel(std::string(TALKINGHEAD_SOURCE_DIR) + "/models/head.json");
  const auto mouth = th::animation::loadMouthModel(std::string(TALKINGHEAD_SOURCE_DIR) + "/models/mouth.json");
  th::TemporaryFolder folder;
  double cpuSeconds = 0.0;
  int frames = 0;
  const auto wallStart = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const double cpuBefore = th::processCpuSeconds();
    // As `talkinghead export` does: the face model built on another thread while the recording is animated.
    std::future<th::face::FaceModel> building =
        std::async(std::launch::async, [] { return th::face::FaceModel::buildDefault(); });
    std::optional<th::avatar::Avatar> avatar;
    if (!character.empty()) avatar = th::avatar::loadAvatar(th::sharedDataPath("face/avatars") / character);
    const th::face::FapTrack animation = th::pipeline::animate(clip.samples, &head, &mouth, {});
    const th::face::FaceModel face = building.get();
    frames = th::pipeline::exportVideo(face, animation, clip.samples, clip.sampleRateHz, folder.path() / "face.mp4",
                                       {.width = width, .height = height, .avatar = avatar ? &*avatar : nullptr});
    cpuSeconds += th::processCpuSeconds() - cpuBefore;
  }
  const double wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
  exportSeconds()[name] = wallSeconds / static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
  const double videoSeconds = static_cast<double>(frames) / kFps;
  state.counters["realtime_factor"] = benchmark::Counter(videoSeconds, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["realtime_factor_per_core"] =
      videoSeconds * static_cast<double>(state.iterations()) / std::max(cpuSeconds, 1e-9);
}

// "10s", or "0.25s" for the smoke pass's clips.
std::string secondsLabel(double seconds) {
  char label[32];
  std::snprintf(label, sizeof label, "%gs", seconds);
  return label;
}

void printRatios(double seconds) {
  const auto& times = exportSeconds();
  const std::string speech = "/1280x720/speech/" + secondsLabel(seconds);
  const auto face = times.find("export/face" + speech + "/export_defaults");
  if (face == times.end()) return;
  std::printf("export of %g s of speech at 1280x720: our face %.2f s", seconds, face->second);
  for (const char* character : {"brunette", "vroid"})
    if (const auto it = times.find(std::string("export/character/") + character + speech); it != times.end())
      std::printf("; %s %.2f s, ratio %.2f", character, it->second, it->second / face->second);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  const BenchArguments arguments = parseBenchArguments(argc, argv, "export_bench");
  if (!arguments.ok) return 1;
  // The smoke pass exports a quarter of a second (a few frames through every stage), enough to prove each case runs.
  const double seconds = arguments.quick ? 0.25 : 10.0;
  const Case cases[] = {
      {640, 480, Content::kGradient, "veryfast", 0},   {1280, 720, Content::kGradient, "veryfast", 0},
      {1280, 720, Content::kGradient, "veryfast", 1},  {1280, 720, Content::kTextured, "veryfast", 0},
      {1280, 720, Content::kGradient, "superfast", 0}, {1280, 720, Content::kGradient, "ultrafast", 0},
  };
  for (const Case& c : cases) {
    const std::string name = "export/" + std::to_string(c.width) + "x" + std::to_string(c.height) + "/" +
                             (c.content == Content::kGradient ? "gradient" : "textured") + "/" + secondsLabel(seconds) +
                             "/" + c.preset +
                             "/threads:" + (c.threads == 0 ? std::string("auto") : std::to_string(c.threads));
    benchmark::RegisterBenchmark(name.c_str(), exportClip, c, seconds)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(arguments.quick ? 1 : 3);
  }
  for (const auto& [width, height] : {std::pair{640, 480}, std::pair{1280, 720}}) {
    const std::string name = "export/face/" + std::to_string(width) + "x" + std::to_string(height) + "/speech/" +
                             secondsLabel(seconds) + "/export_defaults";
    benchmark::RegisterBenchmark(name.c_str(), exportFace, width, height, seconds, std::string(), name)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(arguments.quick ? 1 : 3);
  }
  for (const auto& [file, character] : {std::pair{"brunette-t.glb", "brunette"}, std::pair{"vroid.glb", "vroid"}}) {
    const std::string name = std::string("export/character/") + character + "/1280x720/speech/" + secondsLabel(seconds);
    benchmark::RegisterBenchmark(name.c_str(), exportFace, 1280, 720, seconds, std::string(file), name)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(arguments.quick ? 1 : 3);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  printRatios(seconds);
  return 0;
}
