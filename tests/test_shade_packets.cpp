// Camera rays shaded as packets (Integrator::cast_camera_packet) and shadow
// rays asked as packets (Accelerator::occluded_packet): the same colors, bit
// for bit, the same ray counts and the same shadow answers as ray by ray, on
// the example scenes and on one-mesh scenes (the BVH's packet path), with
// and without a transform, planes, every kind of point-like light and an
// unlit material.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <utility>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/camera.h"
#include "glint/render/integrator.h"
#include "glint/render/passes.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

// One bunny (3,674 triangles) on a mirror floor, four kinds of light.
std::string one_bunny(const std::string& transform, const std::string& more_objects = "") {
  return R"({
  "render": {"width": 96, "height": 64, "max_depth": 3, "background": [0.1, 0.2, 0.3]},
  "camera": {"position": [0, 5, 14], "look_at": [0, 2, 0], "fov_y": 40},
  "materials": {
    "clay": {"ambient": 0.1, "diffuse": [0.7, 0.6, 0.5], "specular": 0.4, "shininess": 30},
    "floor": {"ambient": 0.05, "diffuse": 0.5, "specular": 0.3, "shininess": 80, "reflectivity": 0.4}
  },
  "lights": [
    {"type": "ambient", "ambient": 0.5},
    {"type": "point", "position": [-6, 10, 8], "color": 0.8},
    {"type": "spot", "position": [5, 8, 4], "direction": [-0.5, -0.8, -0.3], "cutoff": 25, "falloff": 2},
    {"type": "directional", "direction": [0.3, -1, -0.4], "color": 0.3}
  ],
  "objects": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "mesh", "file": "bunny.obj", "material": "clay")" +
         transform + "}" + more_objects + R"(
  ]
})";
}

Scene load_one_bunny(const std::string& transform, const std::string& more_objects = "") {
  return parse_scene(one_bunny(transform, more_objects), "one-bunny.json", fs::path(GLINT_SOURCE_DIR) / "scenes" / "meshes");
}

bool same_bits(const Color& a, const Color& b) {
  return std::bit_cast<uint64_t>(a.x) == std::bit_cast<uint64_t>(b.x) &&
         std::bit_cast<uint64_t>(a.y) == std::bit_cast<uint64_t>(b.y) &&
         std::bit_cast<uint64_t>(a.z) == std::bit_cast<uint64_t>(b.z);
}

// Every pixel's center ray, in packets of up to 16 along each row (as the
// renderer makes them): cast_camera_packet against cast_ray_with_hit.
// Returns the number of pixels that hit something.
int expect_same_colors(const Scene& scene, const Accelerator& accel, const std::string& what) {
  const Integrator integrator(scene, accel);
  EXPECT_TRUE(integrator.shades_packets()) << what;
  const int w = scene.render.width, h = scene.render.height;
  const CameraFrame frame = make_camera_frame(scene.camera, w, h);
  TraceContext packet_ctx{Rng(0), {}}, single_ctx{Rng(0), {}};
  int hits = 0, differ = 0;
  for (int y = 0; y < h; ++y) {
    for (int x0 = 0; x0 < w; x0 += kPacketSize) {
      const int n = std::min(kPacketSize, w - x0);
      Ray rays[kPacketSize];
      std::optional<Hit> found[kPacketSize];
      for (int i = 0; i < n; ++i) rays[i] = generate_camera_ray(frame, (x0 + i + 0.5) / w, (y + 0.5) / h);
      accel.intersect_packet(rays, n, found);
      Color colors[kPacketSize];
      integrator.cast_camera_packet(rays, found, n, packet_ctx, colors);
      for (int i = 0; i < n; ++i) {
        hits += found[i].has_value();
        const Color want = integrator.cast_ray_with_hit(rays[i], found[i], 1, single_ctx);
        if (!same_bits(colors[i], want) && differ++ < 5)
          ADD_FAILURE() << what << ": pixel " << x0 + i << "," << y << " differs";
      }
    }
  }
  EXPECT_EQ(differ, 0) << what;
  EXPECT_EQ(packet_ctx.stats.camera_hits, single_ctx.stats.camera_hits) << what;
  EXPECT_EQ(packet_ctx.stats.shadow, single_ctx.stats.shadow) << what;
  EXPECT_EQ(packet_ctx.stats.reflection, single_ctx.stats.reflection) << what;
  EXPECT_EQ(packet_ctx.stats.refraction, single_ctx.stats.refraction) << what;
  return hits;
}

TEST(CameraPackets, SameColorsAsRayByRayOnOneMesh) {
  for (const std::string& transform :
       {std::string(), std::string(R"(, "transform": {"rotate": {"axis": [0, 1, 0], "angle": 30}, "scale": 1.5})")}) {
    Scene scene = load_one_bunny(transform);
    const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
    EXPECT_GT(expect_same_colors(scene, *bvh, "one bunny" + transform), 3000);
    // An unlit bunny (MTL illum 0): its color is Kd alone, and its pixels
    // ask no shadow rays.
    scene.materials[1].unlit = true;
    const auto unlit = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
    expect_same_colors(scene, *unlit, "unlit bunny" + transform);
  }
}

// More lights than the shadow cache has slots (kShadowCacheLights): the
// packet path asks the lights past it without a cache, as the single path.
TEST(CameraPackets, SameColorsWithMoreLightsThanCacheSlots) {
  Scene scene = load_one_bunny("");
  const Light point = scene.lights[1];
  for (int i = 0; i < 20; ++i) {
    Light more = point;
    more.position = point.position + Vec3(0.7 * i - 7, 0.1 * i, -0.3 * i);
    more.diffuse = more.specular = Color(0.05);
    scene.lights.push_back(more);
  }
  ASSERT_GT(scene.lights.size(), kShadowCacheLights);
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  expect_same_colors(scene, *bvh, "24 lights");
}

// Through the renderer: the 1-spp image and ray counts of the packet path
// (no passes asked) are those of the pixel-by-pixel path (passes asked).
TEST(CameraPackets, RenderedImageEqualsThePixelByPixelRender) {
  const Scene scene = load_one_bunny("");
  const auto accel = build_accelerator(scene, AcceleratorOptions{2, AccelBackend::bvh});
  RenderOptions options;
  options.threads = 2;
  RenderStats packet_stats, single_stats;
  const Image packets = render_image(scene, *accel, options, &packet_stats);
  Image single(scene.render.width, scene.render.height);
  PassImages passes({Pass::depth}, scene.render.width, scene.render.height);
  TileProgress tiles(scene.render.width, scene.render.height, 16);
  ASSERT_TRUE(render_tiles(scene, *accel, single, tiles, options, &single_stats, &passes));
  ASSERT_EQ(packets.rgb.size(), single.rgb.size());
  EXPECT_EQ(std::memcmp(packets.rgb.data(), single.rgb.data(), packets.rgb.size() * sizeof(float)), 0);
  EXPECT_EQ(packet_stats.rays.camera, single_stats.rays.camera);
  EXPECT_EQ(packet_stats.rays.camera_hits, single_stats.rays.camera_hits);
  EXPECT_EQ(packet_stats.rays.shadow, single_stats.rays.shadow);
  EXPECT_EQ(packet_stats.rays.reflection, single_stats.rays.reflection);
}

TEST(CameraPackets, SameColorsAsRayByRayOnTheExampleScenes) {
  int scenes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(GLINT_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    Scene scene = load_scene(entry.path());
    scene.render.width = 64;
    scene.render.height = 48;
    const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
    if (!Integrator(scene, *bvh).shades_packets()) {
      // Area lights and ambient occlusion draw each pixel's random
      // numbers: such scenes keep the pixel-by-pixel path.
      bool random = false;
      for (const Light& light : scene.lights) random |= light.type == LightType::area || light.occlusion_samples > 0;
      EXPECT_TRUE(random) << entry.path();
      continue;
    }
    ++scenes;
    expect_same_colors(scene, *bvh, entry.path().string());
    if (scene.meshes.empty()) {  // the default occluded_packet, ray by ray (meshes: slow by brute force)
      const auto brute = build_brute_force(scene);
      expect_same_colors(scene, *brute, entry.path().string() + " (brute force)");
    }
  }
  EXPECT_GE(scenes, 10);
}

// The shadow rays of neighbouring pixels toward each light; coherent
// packets from points on both sides of a second plane (which blocks some
// rays of a packet, and the others go through the mesh as a packet); and
// packets of rays in every direction (which the packet kernel refuses: ray
// by ray then); against occluded() ray by ray.
TEST(OccludedPacket, SameAnswersAsOccluded) {
  const std::string wall = R"(, {"type": "plane", "point": [-1, 0, 0], "normal": [1, 0, 0]})";
  for (const std::string& transform :
       {std::string(), std::string(R"(, "transform": {"rotate": {"axis": [1, 0, 0], "angle": 15}, "translate": [0.5, 0, 0]})")}) {
    const Scene scene = load_one_bunny(transform, wall);
    // Toward each point light's position (t_max 1), and along a direction
    // (t_max infinite), as a directional light's shadow rays go.
    std::vector<std::pair<Vec3, bool>> targets = {{Vec3(-0.3, 1, 0.4), true}};
    for (const Light& light : scene.lights)
      if (light.type == LightType::point || light.type == LightType::spot) targets.push_back({light.position, false});
    const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
    const int w = 96, h = 64;
    const CameraFrame frame = make_camera_frame(scene.camera, w, h);
    Rng rng(3);
    int asked = 0, blocked_count = 0, mesh_blocked = 0;
    for (int y = 0; y < h; ++y) {
      for (int x0 = 0; x0 < w; x0 += kPacketSize) {
        for (const auto& [target, direction] : targets) {
          Ray shadow[kPacketSize];
          int n = 0;
          for (int i = 0; i < kPacketSize && x0 + i < w; ++i) {
            const Ray ray = generate_camera_ray(frame, (x0 + i + 0.5) / w, (y + 0.5) / h);
            const auto hit = bvh->intersect(ray);
            if (!hit) continue;
            const Vec3 p = ray.origin + (hit->t * (1 - 1e-9)) * ray.direction;
            shadow[n].origin = p;
            shadow[n].direction = direction ? target : target - p;
            shadow[n].t_max = direction ? kInfinity : 1.0;
            ++n;
          }
          bool blocked[kPacketSize];
          uint32_t cache = kNoShadowBlocker;
          bvh->occluded_packet(shadow, n, blocked, cache);
          for (int i = 0; i < n; ++i) {
            ++asked;
            blocked_count += blocked[i];
            EXPECT_EQ(blocked[i], bvh->occluded(shadow[i])) << x0 + i << "," << y;
          }
        }
        // Coherent (every direction's signs alike), from both sides of the
        // wall, through the bunny's box.
        Ray across[kPacketSize];
        for (Ray& r : across) {
          r.origin = Vec3(rng.next_double() * 6 - 3, 0.5 + 1.4 * rng.next_double(), rng.next_double() * 1.1 - 1);
          r.direction = Vec3(8, 2, 0.2) - r.origin;
          r.t_max = 1.0;
        }
        bool blocked_across[kPacketSize];
        uint32_t no_cache = kNoShadowBlocker;
        bvh->occluded_packet(across, kPacketSize, blocked_across, no_cache);
        for (int i = 0; i < kPacketSize; ++i) {
          const bool want = bvh->occluded(across[i]);
          EXPECT_EQ(blocked_across[i], want);
          mesh_blocked += want && across[i].origin.x > -1;
        }
        // Incoherent: from random points in random directions, some with t_min > 0.
        Ray mixed[kPacketSize];
        for (Ray& r : mixed) {
          r.origin = Vec3(rng.next_double() * 8 - 4, rng.next_double() * 6, rng.next_double() * 8 - 4);
          r.direction = Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5);
          r.t_min = rng.next_double() < 0.3 ? 0.5 : 0.0;
          r.t_max = 2 + 10 * rng.next_double();
        }
        bool blocked[kPacketSize];
        uint32_t cache = kNoShadowBlocker;
        bvh->occluded_packet(mixed, kPacketSize, blocked, cache);
        for (int i = 0; i < kPacketSize; ++i) EXPECT_EQ(blocked[i], bvh->occluded(mixed[i]));
      }
    }
    EXPECT_GT(asked, 4000);
    EXPECT_GT(blocked_count, 300);
    EXPECT_LT(blocked_count, asked - 300);
    EXPECT_GT(mesh_blocked, 100);  // rays the packet found blocked, behind rays the wall blocked
  }
}

}  // namespace
}  // namespace glint
