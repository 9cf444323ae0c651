// What a torus and a CSG solid cost per ray next to a sphere (issue #34's
// targets: a torus at most 4x a sphere, a CSG of two spheres at most 2x).
// Each test meets the same 4096 rays, aimed from a sphere of radius 10 at
// random points inside the shapes' common bounding sphere (radius 1.25), so
// most rays hit: the work the renderer does per ray that reaches the shape
// (the BVH has already culled those that pass by).
//
// Usage: build/bench/glint_bench_solids (cmake --build build --target benchmarks)
#include <benchmark/benchmark.h>

#include <vector>

#include "glint/geometry/csg.h"
#include "glint/geometry/shapes.h"
#include "glint/geometry/torus.h"
#include "glint/math/rng.h"

namespace {

using glint::Ray;
using glint::Vec3;

Vec3 random_unit(glint::Rng& rng) {
  for (;;) {
    const Vec3 v(2 * rng.next_double() - 1, 2 * rng.next_double() - 1, 2 * rng.next_double() - 1);
    const double l = glint::length(v);
    if (l > 0.1 && l < 1) return v / l;
  }
}

const std::vector<Ray>& rays() {
  static const std::vector<Ray> r = [] {
    glint::Rng rng(42);
    std::vector<Ray> out;
    for (int i = 0; i < 4096; ++i) {
      const Vec3 target = random_unit(rng) * (1.25 * rng.next_double());
      Ray ray;
      ray.origin = random_unit(rng) * 10.0;
      ray.direction = glint::normalize(target - ray.origin);
      out.push_back(ray);
    }
    return out;
  }();
  return r;
}

void BM_Sphere(benchmark::State& state) {
  const glint::Sphere s{{0, 0, 0}, 1.25};
  for (auto _ : state)
    for (const Ray& ray : rays()) benchmark::DoNotOptimize(glint::intersect_sphere(s, ray));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays().size()));
}
BENCHMARK(BM_Sphere);

void BM_Torus(benchmark::State& state) {
  const glint::Torus t{{0, 0, 0}, glint::normalize(Vec3(0.3, 1, 0.2)), 1.0, 0.25};
  for (auto _ : state)
    for (const Ray& ray : rays()) benchmark::DoNotOptimize(glint::intersect_torus(t, ray));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays().size()));
}
BENCHMARK(BM_Torus);

// Two overlapping spheres of radius 0.75 whose union spans the same bounds.
glint::Csg two_spheres(glint::CsgOp op) {
  glint::Csg csg;
  csg.nodes.push_back({false, op, 0, 0, 2});
  csg.child_nodes = {1, 2};
  csg.nodes.push_back({true, op, 0, 0, 0});
  csg.nodes.push_back({true, op, 1, 0, 0});
  glint::CsgLeaf a, b;
  a.sphere = {{-0.5, 0, 0}, 0.75};
  b.sphere = {{0.5, 0, 0}, 0.75};
  csg.leaves = {a, b};
  csg.bounds = glint::csg_bounds(csg);
  return csg;
}

void BM_CsgTwoSpheres(benchmark::State& state) {
  const glint::Csg csg = two_spheres(static_cast<glint::CsgOp>(state.range(0)));
  for (auto _ : state)
    for (const Ray& ray : rays()) benchmark::DoNotOptimize(glint::intersect_csg(csg, ray));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rays().size()));
}
BENCHMARK(BM_CsgTwoSpheres)->Arg(0)->Arg(1)->Arg(2)->ArgName("op");

}  // namespace

BENCHMARK_MAIN();
