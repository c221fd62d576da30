// Off-screen rendering speed of the ICT FaceKit head (OSMesa, llvmpipe): one frame = new positions uploaded
// (normals recomputed on the CPU) + the draw + the read-back into an RGB image, as the video export does it
// (deform-free: the positions are the neutral ones, so this measures the renderer alone). Counter `fps` is
// frames per second of wall time (llvmpipe rasterises on its own threads: CPU time of the calling thread
// would flatter it). At 1280x720 the export needs 60 fps for twice real time at 30 fps.
//
//   build/bench/render_bench [--quick]        (not under taskset -c 0: llvmpipe uses every core,
//   LP_NUM_THREADS)
//
// Cases: 640x480 and 1280x720 with the default 4x MSAA; 1280x720 with FXAA instead (samples = 1, fxaa), and
// with no anti-aliasing at all.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <string>

#include "bench_arguments.h"
#include "core/cpu_time.h"
#include "face/feature_points.h"
#include "face/mesh.h"
#include "render/face_renderer.h"
#include "render/gl_context.h"

namespace {

const th::face::Mesh& neutral() {
  static const th::face::Mesh mesh = th::face::loadObjMesh(th::face::ictFaceDirectory() / "generic_neutral_mesh.obj");
  return mesh;
}

th::render::OffscreenContext& context() {
  static th::render::OffscreenContext c;
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
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
