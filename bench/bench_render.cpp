// Render throughput of whole scenes (load once, then build + render per
// iteration), at 1 and 2 threads, reported as Mrays/s over all ray kinds.
// Usage: glint_bench [--benchmark_filter=...] [GLINT_BENCH_SCENE=path.json]
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"

namespace {

std::string scene_path(const char* name) { return std::string(GLINT_SOURCE_DIR) + "/scenes/" + name; }

void render_scene(benchmark::State& state, const std::string& path) {
  glint::Scene scene = glint::load_scene(path);
  const int threads = static_cast<int>(state.range(0));
  const auto accel = glint::build_accelerator(scene);
  uint64_t rays = 0;
  for (auto _ : state) {
    glint::RenderOptions options;
    options.threads = threads;
    glint::RenderStats stats;
    const glint::Image image = glint::render_image(scene, *accel, options, &stats);
    benchmark::DoNotOptimize(image.rgb.data());
    rays += stats.rays.total();
  }
  state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(rays) / 1e6, benchmark::Counter::kIsRate);
  state.counters["rays"] = static_cast<double>(rays) / static_cast<double>(state.iterations());
}

void BM_Showcase(benchmark::State& state) { render_scene(state, scene_path("showcase.json")); }
BENCHMARK(BM_Showcase)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

void BM_Shadows(benchmark::State& state) { render_scene(state, scene_path("figures/shadows.json")); }
BENCHMARK(BM_Shadows)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CustomScene(benchmark::State& state) {
  const char* path = std::getenv("GLINT_BENCH_SCENE");
  if (!path) {
    state.SkipWithError("set GLINT_BENCH_SCENE=scene.json");
    return;
  }
  render_scene(state, path);
}
BENCHMARK(BM_CustomScene)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
