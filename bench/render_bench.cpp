// Off-screen rendering speed (OSMesa, llvmpipe). Counter `fps` is frames per second of wall time (llvmpipe
// rasterises on its own threads: CPU time of the calling thread would flatter it).
//
//   build/bench/render_bench [--quick]        (not under taskset -c 0: llvmpipe uses every core,
//   LP_NUM_THREADS)
//
// render/...: the ICT FaceKit head alone, one frame = new positions uploaded (normals recomputed on the CPU) +
// the draw + the read-back into an RGB image (deform-free: the positions are the neutral ones, so this measures
// the renderer alone). 640x480 and 1280x720 with the default 4x MSAA; 1280x720 with FXAA instead (samples = 1,
// fxaa), and with no anti-aliasing at all. At 1280x720 the export needs 60 fps for twice real time at 30 fps.
//
// speaking/...: our face and the two test characters (../shared/data/face/avatars: brunette-t.glb, Ready
// Player Me; vroid.glb, VRoid) posed by a moving frame each time (the jaw, the lids, the head turning), as the
// programs draw them:
// - window: the live window's path at 1280x720 (its picture 1280 minus the panel's 440 columns wide, drawn
//   straight into framebuffer 0 from column 440, one sample: renderToWindow), waited for with glFinish; a
//   1280x720 off-screen default framebuffer stands in for the window (no swap);
// - export: the export's path at 1280x720 (one sample and FXAA): drawn, read back and finished into Y'CbCr (the
//   export finishes on another thread; here one after the other).
// Counters: pose_ms (the face's deformation; a character's rig), deform_ms (a character's morph targets and
// skinning), upload_ms, draw_ms (to glFinish), read_ms, finish_ms, and ms a frame in all (frame_ms; cpu_ms:
// the CPU time of every thread, llvmpipe's too, the fairer figure on a busy machine); at the end, each
// character's time a frame over our face's, per path ("ratio"). 60 frames a second is 16.7 ms.
#include <glad/gl.h>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "avatar/avatar_model.h"
#include "avatar/avatar_pose.h"
#include "bench_arguments.h"
#include "core/cpu_time.h"
#include "core/data_path.h"
#include "face/face_model.h"
#include "face/feature_points.h"
#include "face/mesh.h"
#include "render/animated_avatar.h"
#include "render/animated_face.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"

namespace {

constexpr int kWindowWidth = 1280;
constexpr int kWindowHeight = 720;
constexpr int kPanelWidth = 440;  // app/live/panel.h: LivePanel::widthFor(1280)

const th::face::Mesh& neutral() {
  static const th::face::Mesh mesh = th::face::loadObjMesh(th::face::ictFaceDirectory() / "generic_neutral_mesh.obj");
  return mesh;
}

// Its default framebuffer as large as the live window, for the window's path.
th::render::OffscreenContext& context() {
  static th::render::OffscreenContext c(kWindowWidth, kWindowHeight);
  return c;
}

void renderFrames(benchmark::State& state, int width, int height, int samples, bool fxaa) {
  th::render::FaceRenderer renderer(context(), neutral(),
                                    {.width = width, .height = height, .samples = samples, .fxaa = fxaa});
  const th::render::OrbitCamera camera =
      th::render::frameHead(neutral().positions, static_cast<double>(width) / static_cast<double>(height));
  th::render::Image image;
  // One frame untimed: llvmpipe compiles each shader variant when it is first used.
  renderer.render(camera);
  renderer.readPixels(image);
  const double cpuStart = th::processCpuSeconds();
  for (auto _ : state) {
    renderer.setPositions(neutral().positions);
    renderer.render(camera);
    renderer.readPixels(image);
    benchmark::DoNotOptimize(image.pixels.data());
  }
  const double cpuSeconds = th::processCpuSeconds() - cpuStart;
  state.counters["cpu_ms"] =
      1e3 * cpuSeconds / static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["samples"] = renderer.samples();
}

// ---- speaking: our face and the characters, in the window's and the export's paths ----

enum class Path { kWindow, kExport };

// Frame f of a speaker: the jaw opening and closing about three times a second, a blink every 3 s, the head
// nodding and turning (up to 15° to each side) over a few seconds.
th::face::FapFrame speakingFrame(int f) {
  th::face::FapFrame faps{};
  faps[3] = 600.0 * (1.0 + std::sin(2.0 * M_PI * f / 9.0));  // open_jaw
  faps[19] = faps[20] = f % 90 < 4 ? 1024.0 : 0.0;           // the lids
  const double degree = M_PI / 180.0 / 1e-5;                 // FAP units of the head's rotation
  faps[48] = 4.0 * degree * std::sin(2.0 * M_PI * f / 70.0);
  faps[49] = 15.0 * degree * std::sin(2.0 * M_PI * f / 90.0);
  faps[50] = 3.0 * degree * std::sin(2.0 * M_PI * f / 50.0);
  return faps;
}

using Clock = std::chrono::steady_clock;
double millisecondsSince(Clock::time_point& from) {
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - from).count();
  from = now;
  return ms;
}

// Milliseconds a frame of each case, for the ratios printed at the end.
std::map<std::string, double>& frameMs() {
  static std::map<std::string, double> times;
  return times;
}

struct Phases {
  double pose = 0, deform = 0, upload = 0, draw = 0, read = 0, finish = 0;
  double cpu = 0;  // the process's CPU time, every thread's (llvmpipe's too), ms
  double total() const { return pose + deform + upload + draw + read + finish; }
};

void report(benchmark::State& state, const std::string& name, const Phases& sum) {
  const double frames = static_cast<double>(std::max<benchmark::IterationCount>(state.iterations(), 1));
  state.counters["pose_ms"] = sum.pose / frames;
  state.counters["deform_ms"] = sum.deform / frames;
  state.counters["upload_ms"] = sum.upload / frames;
  state.counters["draw_ms"] = sum.draw / frames;
  state.counters["read_ms"] = sum.read / frames;
  state.counters["finish_ms"] = sum.finish / frames;
  state.counters["frame_ms"] = sum.total() / frames;
  state.counters["cpu_ms"] = sum.cpu / frames;
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  frameMs()[name] = sum.total() / frames;
}

int pictureWidth(Path path) {
  return path == Path::kWindow ? kWindowWidth - kPanelWidth : kWindowWidth;
}

void speakingFace(benchmark::State& state, Path path, const std::string& name) {
  static const th::face::FaceModel model = th::face::FaceModel::buildDefault();
  const int width = pictureWidth(path);
  th::render::AnimatedFace face(model, context(),
                                {.width = width, .height = kWindowHeight, .samples = 1, .fxaa = path == Path::kExport});
  th::render::RawFrame raw;
  th::render::Yuv420Image yuv;
  Phases sum;
  int f = 0;
  const auto frame = [&](Phases& into) {
    Clock::time_point at = Clock::now();
    face.pose(speakingFrame(f++));
    into.pose += millisecondsSince(at);
    if (path == Path::kWindow) {
      face.renderer().renderToWindow(face.camera(), kPanelWidth);
      glFinish();
      into.draw += millisecondsSince(at);
      return;
    }
    face.render();
    glFinish();
    into.draw += millisecondsSince(at);
    face.renderer().readRaw(raw);
    into.read += millisecondsSince(at);
    face.renderer().finish(raw, yuv, true);
    into.finish += millisecondsSince(at);
  };
  Phases warm;
  for (int k = 0; k < 3; ++k) frame(warm);  // shaders compiled
  const double cpuStart = th::processCpuSeconds();
  for (auto _ : state) frame(sum);
  sum.cpu = 1e3 * (th::processCpuSeconds() - cpuStart);
  report(state, name, sum);
}

void speakingCharacter(benchmark::State& state, Path path, const std::string& file, const std::string& name) {
  static std::map<std::string, th::avatar::Avatar> loaded;
  if (!loaded.count(file)) loaded.emplace(file, th::avatar::loadAvatar(th::sharedDataPath("face/avatars") / file));
  const th::avatar::Avatar& avatar = loaded.at(file);
  const int width = pictureWidth(path);
  // As AnimatedAvatar does it, step by step.
  const th::avatar::AvatarRig rig = th::avatar::rigAvatar(avatar);
  const th::avatar::MovingVertices moving = th::avatar::movingVertices(avatar, rig);
  th::render::AvatarRenderer renderer(
      context(), avatar, {.width = width, .height = kWindowHeight, .samples = 1, .fxaa = path == Path::kExport});
  renderer.setMovingVertices(moving);
  th::avatar::AvatarPose pose;
  th::avatar::poseAvatar(avatar, rig, th::avatar::AvatarInput{}, pose);  // at rest, the arms lowered
  std::vector<th::avatar::DeformedMesh> meshes;
  th::avatar::deformAvatar(avatar, pose, meshes);
  renderer.setMeshes(meshes);
  const th::render::OrbitCamera camera =
      th::render::frameAvatarHead(avatar, meshes, static_cast<double>(width) / kWindowHeight);
  th::render::RawFrame raw;
  th::render::Yuv420Image yuv;
  Phases sum;
  int f = 0;
  const auto frame = [&](Phases& into) {
    Clock::time_point at = Clock::now();
    th::avatar::poseAvatar(avatar, rig, th::avatar::avatarInputOf(speakingFrame(f++), nullptr), pose);
    into.pose += millisecondsSince(at);
    th::avatar::deformAvatar(avatar, pose, meshes, &moving);
    into.deform += millisecondsSince(at);
    renderer.setMeshes(meshes, &moving);
    into.upload += millisecondsSince(at);
    if (path == Path::kWindow) {
      renderer.renderToWindow(camera, kPanelWidth);
      glFinish();
      into.draw += millisecondsSince(at);
      return;
    }
    renderer.render(camera);
    glFinish();
    into.draw += millisecondsSince(at);
    renderer.readRaw(raw);
    into.read += millisecondsSince(at);
    renderer.finish(raw, yuv, true);
    into.finish += millisecondsSince(at);
  };
  Phases warm;
  for (int k = 0; k < 3; ++k) frame(warm);  // shaders compiled
  const double cpuStart = th::processCpuSeconds();
  for (auto _ : state) frame(sum);
  sum.cpu = 1e3 * (th::processCpuSeconds() - cpuStart);
  state.counters["triangles"] = renderer.trianglesDrawn();
  report(state, name, sum);
}

void printRatios() {
  const auto& times = frameMs();
  for (const char* path : {"window", "export"}) {
    const auto face = times.find(std::string("speaking/") + path + "/face");
    if (face == times.end()) continue;
    std::printf("%s path, 1280x720: our face %.1f ms a frame", path, face->second);
    for (const char* character : {"brunette", "vroid"})
      if (const auto it = times.find(std::string("speaking/") + path + "/" + character); it != times.end())
        std::printf("; %s %.1f ms, ratio %.2f", character, it->second, it->second / face->second);
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const BenchArguments arguments = parseBenchArguments(argc, argv, "render_bench");
  if (!arguments.ok) return 1;
  try {
    std::cerr << "render_bench: " << context().description() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "render_bench: " << e.what() << "\n";
    return 1;
  }
  const double minTime = arguments.quick ? 0.01 : 3.0;
  const struct {
    int width, height, samples;
    bool fxaa;
  } cases[] = {{640, 480, 4, false}, {1280, 720, 4, false}, {1280, 720, 1, true}, {1280, 720, 1, false}};
  for (const auto& c : cases) {
    const std::string antialiasing =
        c.samples > 1 ? "msaa" + std::to_string(c.samples) : std::string(c.fxaa ? "fxaa" : "none");
    const std::string name = "render/" + std::to_string(c.width) + "x" + std::to_string(c.height) + "/" + antialiasing;
    benchmark::RegisterBenchmark(name.c_str(), renderFrames, c.width, c.height, c.samples, c.fxaa)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(minTime);
  }
  for (const Path path : {Path::kWindow, Path::kExport}) {
    const std::string prefix = std::string("speaking/") + (path == Path::kWindow ? "window" : "export") + "/";
    benchmark::RegisterBenchmark((prefix + "face").c_str(), speakingFace, path, prefix + "face")
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(minTime);
    for (const auto& [file, character] : {std::pair{"brunette-t.glb", "brunette"}, std::pair{"vroid.glb", "vroid"}})
      benchmark::RegisterBenchmark((prefix + character).c_str(), speakingCharacter, path, std::string(file),
                                   prefix + character)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(minTime);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  printRatios();
  return 0;
}
