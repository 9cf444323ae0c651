// The accelerator benchmark (issue: meshes at scale). In one run it generates
// height-field terrains of ~100k, 1M and 10M triangles (deterministic), builds
// our BVH and the Embree backend over each, and measures, at 1 and 2 threads:
// build time, bytes per triangle, and Mrays/s for camera rays (1920x1080
// pinhole), shadow rays toward a point light from the camera hits, and
// incoherent rays (mirror directions from those hits). Secondary rays are made
// once from our BVH's hits, so every kernel traces the same rays.
//
// "embree" is Embree called directly on one triangle mesh (rtcIntersect1 /
// rtcOccluded1, and rtcIntersect16 packets for camera rays): the reference.
// "glint-kernel" is our mesh BVH called directly in the same way (float hits,
// 16-ray packets): the like-for-like comparison. "glint-bvh" and
// "glint-embree" are glint's two backends through the Accelerator interface
// (instancing, double refinement of every hit), what `glint render --accel
// bvh|embree` uses.
//
// Usage: glint_bench_accel [--sizes 100000,1000000,10000000] [--threads 1,2]
//                          [--width 1920 --height 1080] [--repeat 3]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/accel/mesh_bvh.h"
#include "glint/accel/ray_packets.h"
#include "glint/accel/wide_bvh.h"
#include "glint/render/camera.h"
#include "glint/scene/scene.h"

#if GLINT_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

namespace {

using glint::Vec3;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// --- memory: the kernel's resident-set high-water mark, reset per build -----
long read_status_kb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::char_traits<char>::length(key);
  while (std::getline(in, line))
    if (line.compare(0, n, key) == 0) return std::atol(line.c_str() + n + 1);
  return 0;
}
// Writing 5 to clear_refs resets VmHWM to the current RSS (Linux >= 4.0).
long reset_peak_rss_kb() {
  std::ofstream("/proc/self/clear_refs") << "5";
  return read_status_kb("VmRSS:");
}
long peak_rss_kb() { return read_status_kb("VmHWM:"); }

// --- the terrain ------------------------------------------------------------
double height(double x, double z) {
  return 0.18 * std::sin(2.1 * x + 0.4) * std::cos(1.7 * z) + 0.06 * std::sin(7.3 * x + 3.1 * z) +
         0.025 * std::sin(19.0 * x - 13.0 * z) + 0.01 * std::cos(47.0 * x + 31.0 * z) +
         0.004 * std::sin(113.0 * x - 97.0 * z);
}

glint::Mesh make_terrain(size_t target_triangles) {
  const int n = std::max(2, static_cast<int>(std::lround(std::sqrt(target_triangles / 2.0))));
  glint::Mesh mesh;
  mesh.file = "terrain";
  mesh.positions.reserve(static_cast<size_t>(n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1.5 + 3.0 * i / n, z = -1.5 + 3.0 * j / n;
      mesh.positions.push_back(
          glint::Vec3f{static_cast<float>(x), static_cast<float>(height(x, z)), static_cast<float>(z)});
    }
  mesh.indices.reserve(6 * static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
      for (uint32_t v : {a, c, b, b, c, d}) mesh.indices.push_back(v);
    }
  mesh.triangle_material.assign(mesh.triangle_count(), 0);
  return mesh;
}

glint::Scene make_scene(size_t target_triangles) {
  glint::Scene scene;
  scene.camera.position = Vec3(0.0, 1.3, 2.4);
  scene.camera.look_at = Vec3(0.0, -0.1, 0.0);
  scene.camera.fov_y = 55.0;
  const uint32_t mesh = glint::add_mesh(scene, make_terrain(target_triangles));
  glint::add_mesh_object(scene, mesh, 0, false);
  return scene;
}

const Vec3 kLight(2.0, 3.0, 1.5);

// --- rays -------------------------------------------------------------------
struct RaySet {
  std::vector<glint::Ray> camera, shadow, mirror;
};

// Runs `body(i)` for i in [0, n) on `threads` threads, in chunks.
void parallel_for(size_t n, int threads, const std::function<void(size_t, size_t)>& body) {
  std::atomic<size_t> next{0};
  constexpr size_t kChunk = 1024;
  static_assert(kChunk % 16 == 0);  // the packet kernels' 16 rays never straddle two chunks
  auto worker = [&] {
    for (;;) {
      const size_t begin = next.fetch_add(kChunk);
      if (begin >= n) return;
      body(begin, std::min(n, begin + kChunk));
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

// Camera rays in 4x4 pixel blocks (the order packets use too).
std::vector<glint::Ray> camera_rays(const glint::Scene& scene, int width, int height) {
  const glint::CameraFrame frame = glint::make_camera_frame(scene.camera, width, height);
  std::vector<glint::Ray> rays;
  rays.reserve(static_cast<size_t>(width) * height);
  for (int by = 0; by < height; by += 4)
    for (int bx = 0; bx < width; bx += 4)
      for (int y = by; y < std::min(height, by + 4); ++y)
        for (int x = bx; x < std::min(width, bx + 4); ++x)
          rays.push_back(glint::generate_camera_ray(frame, (x + 0.5) / width, (y + 0.5) / height));
  return rays;
}

RaySet make_rays(const glint::Scene& scene, const glint::Accelerator& accel, int width, int height) {
  RaySet set;
  set.camera = camera_rays(scene, width, height);
  const glint::Mesh& mesh = scene.meshes[0];
  const double eps = glint::auto_epsilon(scene);
  for (const glint::Ray& ray : set.camera) {
    const auto hit = accel.intersect(ray);
    if (!hit) continue;
    const glint::Triangle tri = glint::mesh_triangle(mesh, hit->primitive);
    Vec3 n = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    if (dot(n, ray.direction) > 0) n = -n;
    const Vec3 p = ray.at(hit->t);
    glint::Ray shadow;
    shadow.origin = p;
    shadow.direction = normalize(kLight - p);
    shadow.t_min = eps;
    shadow.t_max = length(kLight - p);
    set.shadow.push_back(shadow);
    glint::Ray mirror;
    mirror.origin = p;
    mirror.direction = ray.direction - 2.0 * dot(ray.direction, n) * n;
    mirror.t_min = eps;
    set.mirror.push_back(mirror);
  }
  return set;
}

// --- kernels ----------------------------------------------------------------
struct Kernel {
  std::string name;
  double build_seconds = 0;
  double bytes_per_triangle = 0;       // geometry + acceleration structure
  double peak_bytes_per_triangle = 0;  // resident-set growth while building
  std::function<uint64_t(const std::vector<glint::Ray>&, size_t, size_t)> closest;  // returns hits
  std::function<uint64_t(const std::vector<glint::Ray>&, size_t, size_t)> any;
  std::function<uint64_t(const std::vector<glint::Ray>&, size_t, size_t)> closest_packets;  // optional
};

std::unique_ptr<glint::Accelerator> g_keep_ours, g_keep_embree_backend;

// The mesh's own vertex and index bytes.
double geometry_bytes(const glint::Mesh& mesh) {
  return static_cast<double>(mesh.positions.size() * sizeof(glint::Vec3f) + mesh.indices.size() * sizeof(uint32_t));
}

Kernel accelerator_kernel(const std::string& name, const glint::Scene& scene, glint::AccelBackend backend,
                          std::unique_ptr<glint::Accelerator>& keep) {
  Kernel k;
  k.name = name;
  const long rss0 = reset_peak_rss_kb();
  const auto t0 = Clock::now();
  keep = glint::build_accelerator(scene, glint::AcceleratorOptions{2, backend});
  k.build_seconds = seconds_since(t0);
  const double tris = static_cast<double>(scene.meshes[0].triangle_count());
  // Embree copies the vertices and shares our index buffer (counted once).
  k.bytes_per_triangle = (geometry_bytes(scene.meshes[0]) + keep->memory_bytes()) / tris;
  k.peak_bytes_per_triangle = (peak_rss_kb() - rss0) * 1024.0 / tris;
  const glint::Accelerator* accel = keep.get();
  k.closest = [accel](const std::vector<glint::Ray>& rays, size_t b, size_t e) {
    uint64_t hits = 0;
    for (size_t i = b; i < e; ++i) hits += accel->intersect(rays[i]).has_value();
    return hits;
  };
  k.any = [accel](const std::vector<glint::Ray>& rays, size_t b, size_t e) {
    uint64_t hits = 0;
    for (size_t i = b; i < e; ++i) hits += accel->occluded(rays[i]);
    return hits;
  };
  k.closest_packets = [accel](const std::vector<glint::Ray>& rays, size_t b, size_t e) {
    uint64_t hits = 0;
    std::optional<glint::Hit> out[glint::kPacketSize];
    for (size_t i = b; i < e; i += glint::kPacketSize) {
      const int n = static_cast<int>(std::min<size_t>(glint::kPacketSize, e - i));
      accel->intersect_packet(&rays[i], n, out);
      for (int j = 0; j < n; ++j) hits += out[j].has_value();
    }
    return hits;
  };
  return k;
}

// Our mesh BVH called directly, as bare Embree is: the closest hit in float
// (triangle, distance, vertices) without the Accelerator interface and the
// double refinement of the hit that glint's shading gets through it.
std::unique_ptr<glint::MeshBvh> g_keep_kernel;

Kernel mesh_bvh_kernel(const glint::Scene& scene) {
  Kernel k;
  k.name = "glint-kernel";
  const glint::Mesh& mesh = scene.meshes[0];
  const long rss0 = reset_peak_rss_kb();
  const auto t0 = Clock::now();
  glint::BvhBuildOptions options;
  options.threads = 2;
  g_keep_kernel = std::make_unique<glint::MeshBvh>(glint::build_mesh_bvh(mesh, options));
  k.build_seconds = seconds_since(t0);
  const double tris = static_cast<double>(mesh.triangle_count());
  k.bytes_per_triangle = (geometry_bytes(mesh) + g_keep_kernel->memory_bytes()) / tris;
  k.peak_bytes_per_triangle = (peak_rss_kb() - rss0) * 1024.0 / tris;
  const glint::MeshBvh* bvh = g_keep_kernel.get();
  k.closest = [bvh](const std::vector<glint::Ray>& rays, size_t b, size_t e) {
    uint64_t hits = 0;
    for (size_t i = b; i < e; ++i) {
      uint32_t triangle, slot;
      float t;
      hits += glint::intersect_mesh_bvh(*bvh, rays[i], triangle, t, slot);
    }
    return hits;
  };
  k.any = [bvh](const std::vector<glint::Ray>& rays, size_t b, size_t e) {
    uint64_t hits = 0;
    for (size_t i = b; i < e; ++i) hits += glint::occluded_mesh_bvh(*bvh, rays[i]);
    return hits;
  };
  k.closest_packets = [bvh](const std::vector<glint::Ray>& rays, size_t b, size_t e) {
    uint64_t hits = 0;
    for (size_t i = b; i < e; i += glint::kPacketSize) {
      const int n = static_cast<int>(std::min<size_t>(glint::kPacketSize, e - i));
      glint::RayPacket packet = glint::make_ray_packet(&rays[i], n);
      if (glint::intersect_mesh_packet(*bvh, packet)) {
        for (int j = 0; j < n; ++j) hits += packet.triangle[j] != glint::kNoTriangle;
      } else {
        for (int j = 0; j < n; ++j) {
          uint32_t triangle, slot;
          float t;
          hits += glint::intersect_mesh_bvh(*bvh, rays[i + j], triangle, t, slot);
        }
      }
    }
    return hits;
  };
  return k;
}

#if GLINT_HAVE_EMBREE
struct EmbreeRaw {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<int64_t> bytes{0};
  ~EmbreeRaw() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};
std::unique_ptr<EmbreeRaw> g_keep_embree;

void to_rtc(const glint::Ray& ray, RTCRay& r) {
  r.org_x = static_cast<float>(ray.origin.x);
  r.org_y = static_cast<float>(ray.origin.y);
  r.org_z = static_cast<float>(ray.origin.z);
  r.dir_x = static_cast<float>(ray.direction.x);
  r.dir_y = static_cast<float>(ray.direction.y);
  r.dir_z = static_cast<float>(ray.direction.z);
  r.tnear = static_cast<float>(ray.t_min);
  r.tfar = ray.t_max >= 3e38 ? INFINITY : static_cast<float>(ray.t_max);
  r.time = 0;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
}

std::unique_ptr<EmbreeRaw> g_keep_embree_robust;

// Bare Embree on the mesh; `robust`: its watertight mode (what our backend uses).
Kernel embree_kernel(const glint::Scene& scene, bool robust = false) {
  Kernel k;
  k.name = robust ? "embree-robust" : "embree";
  auto& keep = robust ? g_keep_embree_robust : g_keep_embree;
  keep = std::make_unique<EmbreeRaw>();
  EmbreeRaw& e = *keep;
  const glint::Mesh& mesh = scene.meshes[0];
  const long rss0 = reset_peak_rss_kb();
  const auto t0 = Clock::now();
  e.device = rtcNewDevice("threads=2");
  rtcSetDeviceMemoryMonitorFunction(
      e.device,
      [](void* p, ssize_t bytes, bool) {
        static_cast<EmbreeRaw*>(p)->bytes += bytes;
        return true;
      },
      &e);
  e.scene = rtcNewScene(e.device);
  if (robust) rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), mesh.positions.size()));
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    v[3 * i] = mesh.positions[i].x;
    v[3 * i + 1] = mesh.positions[i].y;
    v[3 * i + 2] = mesh.positions[i].z;
  }
  auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(uint32_t), mesh.triangle_count()));
  std::copy(mesh.indices.begin(), mesh.indices.end(), idx);
  rtcCommitGeometry(g);
  rtcAttachGeometry(e.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e.scene);
  k.build_seconds = seconds_since(t0);
  const double tris = static_cast<double>(mesh.triangle_count());
  k.bytes_per_triangle = e.bytes.load() / tris;  // vertices, indices and BVH are all Embree's
  k.peak_bytes_per_triangle = (peak_rss_kb() - rss0) * 1024.0 / tris;
  RTCScene s = e.scene;
  k.closest = [s](const std::vector<glint::Ray>& rays, size_t b, size_t end) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    uint64_t hits = 0;
    for (size_t i = b; i < end; ++i) {
      RTCRayHit rh;
      to_rtc(rays[i], rh.ray);
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(s, &ctx, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    return hits;
  };
  k.any = [s](const std::vector<glint::Ray>& rays, size_t b, size_t end) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    uint64_t hits = 0;
    for (size_t i = b; i < end; ++i) {
      RTCRay r;
      to_rtc(rays[i], r);
      rtcOccluded1(s, &ctx, &r);
      hits += r.tfar < 0;
    }
    return hits;
  };
  k.closest_packets = [s](const std::vector<glint::Ray>& rays, size_t b, size_t end) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    uint64_t hits = 0;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    for (size_t i = b; i < end; i += 16) {
      for (int j = 0; j < 16; ++j) {
        valid[j] = i + j < end ? -1 : 0;
        const glint::Ray& r = rays[std::min(end - 1, i + j)];
        rh.ray.org_x[j] = static_cast<float>(r.origin.x);
        rh.ray.org_y[j] = static_cast<float>(r.origin.y);
        rh.ray.org_z[j] = static_cast<float>(r.origin.z);
        rh.ray.dir_x[j] = static_cast<float>(r.direction.x);
        rh.ray.dir_y[j] = static_cast<float>(r.direction.y);
        rh.ray.dir_z[j] = static_cast<float>(r.direction.z);
        rh.ray.tnear[j] = 0.0f;
        rh.ray.tfar[j] = INFINITY;
        rh.ray.time[j] = 0;
        rh.ray.mask[j] = ~0u;
        rh.ray.id[j] = 0;
        rh.ray.flags[j] = 0;
        rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, s, &ctx, &rh);
      for (int j = 0; j < 16; ++j) hits += valid[j] && rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID;
    }
    return hits;
  };
  return k;
}
#endif

// Mrays/s of `fn` over `rays` at `threads` threads, one run.
double mrays(const std::function<uint64_t(const std::vector<glint::Ray>&, size_t, size_t)>& fn,
             const std::vector<glint::Ray>& rays, int threads) {
  std::atomic<uint64_t> hits{0};
  const auto t0 = Clock::now();
  parallel_for(rays.size(), threads, [&](size_t b, size_t e) { hits += fn(rays, b, e); });
  return rays.size() / seconds_since(t0) / 1e6;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<size_t> parse_list(const std::string& s) {
  std::vector<size_t> out;
  size_t pos = 0;
  while (pos < s.size()) {
    const size_t comma = s.find(',', pos);
    out.push_back(std::stoull(s.substr(pos, comma - pos)));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"glint_bench_accel: our BVH against Embree on generated terrains"};
  std::string sizes_arg = "100000,1000000,10000000", threads_arg = "1,2";
  int width = 1920, height = 1080, repeat = 3;
  app.add_option("--sizes", sizes_arg, "triangle counts, comma-separated");
  app.add_option("--threads", threads_arg, "thread counts, comma-separated");
  app.add_option("--width", width);
  app.add_option("--height", height);
  app.add_option("--repeat", repeat, "rounds: every kernel traces every ray set once a round")
      ->check(CLI::Range(1, 1000));
  bool only_ours = false;
  app.add_flag("--only-ours", only_ours, "measure our BVH alone (for profiling)");
  std::string kinds_arg = "camera,shadow,mirror,packets";
  app.add_option("--rays", kinds_arg, "what to measure (for profiling one): camera, shadow, mirror, packets");
  int builds = 0;
  app.add_option("--builds", builds,
                 "only build our mesh BVH this many times at the first thread count, each timed (for profiling "
                 "the build)");
  CLI11_PARSE(app, argc, argv);
  const std::vector<size_t> sizes = parse_list(sizes_arg);
  const std::vector<size_t> thread_counts = parse_list(threads_arg);
  auto wanted = [&](const char* kind) {
    return ("," + kinds_arg + ",").find("," + std::string(kind) + ",") != std::string::npos;
  };
  const bool want_camera = wanted("camera"), want_shadow = wanted("shadow"), want_mirror = wanted("mirror"),
             want_packets = wanted("packets");

  std::printf("glint_bench_accel: %dx%d camera rays, best of %d rounds (every kernel once a round); Mrays/s\n\n", width,
              height, repeat);
  // Scaling: per kernel, per size, the cost of a camera ray and a mirror ray
  // at the first thread count (1 / Mrays/s), for the curve at the end.
  std::vector<std::pair<std::string, std::vector<std::pair<size_t, std::array<double, 2>>>>> scaling;
  for (size_t target : sizes) {
    const auto t_gen = Clock::now();
    glint::Scene scene = make_scene(target);
    const size_t tris = scene.meshes[0].triangle_count();
    std::printf("== terrain, %zu triangles (generated in %.2f s) ==\n", tris, seconds_since(t_gen));
    if (builds > 0) {
      glint::BvhBuildOptions options;
      options.threads = static_cast<int>(thread_counts.at(0));
      for (int b = 0; b < builds; ++b) {
        const auto t0 = Clock::now();
        const glint::MeshBvh built = glint::build_mesh_bvh(scene.meshes[0], options);
        std::printf("build %d: %.3f s, %zu nodes, %zu blocks\n", b + 1, seconds_since(t0), built.bvh.nodes.size(),
                    built.blocks.size());
      }
      continue;
    }

    std::vector<Kernel> kernels;
    kernels.push_back(accelerator_kernel("glint-bvh", scene, glint::AccelBackend::bvh, g_keep_ours));
    const RaySet rays = make_rays(scene, *g_keep_ours, width, height);
    kernels.push_back(mesh_bvh_kernel(scene));
#if GLINT_HAVE_EMBREE
    if (!only_ours) {
      kernels.push_back(accelerator_kernel("glint-embree", scene, glint::AccelBackend::embree, g_keep_embree_backend));
      kernels.push_back(embree_kernel(scene));
      kernels.push_back(embree_kernel(scene, true));
    }
#endif
    std::printf("rays: %zu camera, %zu shadow, %zu mirror\n", rays.camera.size(), rays.shadow.size(),
                rays.mirror.size());
    std::printf("%-13s %8s %9s %9s", "kernel", "build s", "B/tri", "peak B/tri");
    for (size_t t : thread_counts) std::printf(" | %zuT: camera  shadow  mirror  cam-pkt", t);
    std::printf("\n");
    // Measured in rounds: in each round every kernel traces every ray set
    // once, so our runs and Embree's take turns and a change of the
    // machine's speed during the bench (these shared machines drift over
    // seconds) meets both alike. runs[k][4 * thread_index + kind][round],
    // kinds camera, shadow, mirror, packets; 0 where not measured (--rays).
    std::vector<std::vector<std::vector<double>>> runs(kernels.size(),
                                                       std::vector<std::vector<double>>(4 * thread_counts.size()));
    for (int round = 0; round < repeat; ++round)
      for (size_t k = 0; k < kernels.size(); ++k)
        for (size_t ti = 0; ti < thread_counts.size(); ++ti) {
          const Kernel& kernel = kernels[k];
          const int t = static_cast<int>(thread_counts[ti]);
          std::vector<double>* out = &runs[k][4 * ti];
          out[0].push_back(want_camera ? mrays(kernel.closest, rays.camera, t) : 0.0);
          out[1].push_back(want_shadow ? mrays(kernel.any, rays.shadow, t) : 0.0);
          out[2].push_back(want_mirror ? mrays(kernel.closest, rays.mirror, t) : 0.0);
          out[3].push_back(want_packets && kernel.closest_packets ? mrays(kernel.closest_packets, rays.camera, t)
                                                                  : 0.0);
        }
    for (size_t k = 0; k < kernels.size(); ++k) {
      std::vector<double> row;  // the kernel's best round
      for (const std::vector<double>& r : runs[k]) row.push_back(*std::max_element(r.begin(), r.end()));
      std::printf("%-13s %8.3f %9.1f %9.1f", kernels[k].name.c_str(), kernels[k].build_seconds,
                  kernels[k].bytes_per_triangle, kernels[k].peak_bytes_per_triangle);
      for (size_t ti = 0; ti < thread_counts.size(); ++ti)
        std::printf(" | %5s %7.2f %7.2f %7.2f %8.2f", "", row[4 * ti], row[4 * ti + 1], row[4 * ti + 2],
                    row[4 * ti + 3]);
      std::printf("\n");
      auto it = std::find_if(scaling.begin(), scaling.end(), [&](const auto& e) { return e.first == kernels[k].name; });
      if (it == scaling.end()) it = scaling.insert(scaling.end(), {kernels[k].name, {}});
      it->second.push_back({tris, {row[0], row[2]}});
    }
    // kernels: glint-bvh, glint-kernel, glint-embree, embree, embree-robust.
    if (kernels.size() >= 4) {
      const Kernel& ref = kernels[3];
      for (int row : {0, 1}) {
        const Kernel& ours = kernels[row];
        std::printf("%-13s %8.2f %9.2f %9.2f", row == 0 ? "bvh/embree" : "kernel/embree",
                    ours.build_seconds / ref.build_seconds, ours.bytes_per_triangle / ref.bytes_per_triangle,
                    ours.peak_bytes_per_triangle / ref.peak_bytes_per_triangle);
        // Each ray ratio: the median over the rounds of that round's ratio
        // (a round's two runs were taken seconds apart).
        auto ratio = [&](size_t column) {
          std::vector<double> r;
          for (int round = 0; round < repeat; ++round) {
            const double embree = runs[3][column][round];
            if (embree > 0) r.push_back(runs[row][column][round] / embree);
          }
          return median(r);
        };
        for (size_t i = 0; i < thread_counts.size(); ++i)
          std::printf(" | %5s %7.2f %7.2f %7.2f %8.2f", "", ratio(4 * i), ratio(4 * i + 1), ratio(4 * i + 2),
                      ratio(4 * i + 3));
        std::printf("\n");
      }
      std::printf(
          "(build and bytes: lower is better; rays: higher, each the median over the rounds of the round's "
          "ratio; cam-pkt: 16-ray packets, ours / Embree)\n");
    }
    std::printf("\n");
    std::fflush(stdout);
    g_keep_ours.reset();
    g_keep_kernel.reset();
    g_keep_embree_backend.reset();
#if GLINT_HAVE_EMBREE
    g_keep_embree.reset();
    g_keep_embree_robust.reset();
#endif
  }
  if (sizes.size() > 1) {
    std::printf("scaling at %zu thread(s): time per ray relative to the smallest mesh (camera / mirror)\n",
                thread_counts.front());
    for (const auto& [name, points] : scaling) {
      std::printf("%-13s", name.c_str());
      for (const auto& [tris, m] : points)
        std::printf("  %zuk: %.2f / %.2f", tris / 1000, m[0] > 0 ? points.front().second[0] / m[0] : 0.0,
                    m[1] > 0 ? points.front().second[1] / m[1] : 0.0);
      std::printf("\n");
    }
  }
  return 0;
}
