// Packets through the object BVH (scenes of many objects: BvhAccelerator's
// intersect_packet and occluded_packet trace the tree once for up to 16
// rays and test each leaf for the rays whose own box test reaches it): the
// same hits, field by field and bit for bit, and the same shadow answers as
// intersect() and occluded() ray by ray, for every kind of object
// (transformed too, and meshes inside the tree), coherent and incoherent
// packets, partial packets, t_min above zero, finite t_max, and every state
// of the shadow cache.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/camera.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

// "[x, y, z]"
std::string vec(double x, double y, double z) {
  std::ostringstream out;
  out.precision(17);
  out << '[' << x << ", " << y << ", " << z << ']';
  return out.str();
}

// A 12 x 12 grid of objects cycling through every kind, some transformed,
// two instances of the bunny (so the tree holds meshes), and a floor plane.
Scene many_objects_scene() {
  Rng rng(11);
  std::ostringstream o;
  o.precision(17);
  o << R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]})";
  o << R"(, {"type": "mesh", "file": "bunny.obj", "transform": {"scale": 2, "translate": [-3, 0, -4]}})";
  o << R"(, {"type": "mesh", "file": "bunny.obj", "transform": {"rotate": {"axis": [0, 1, 0], "angle": 70}, "scale": 1.5, "translate": [4, 0.2, 3]}})";
  for (int k = 0; k < 144; ++k) {
    const double x = (k % 12) - 5.5 + 0.3 * (rng.next_double() - 0.5);
    const double z = (k / 12) - 5.5 + 0.3 * (rng.next_double() - 0.5);
    const double y = 0.2 + 1.5 * rng.next_double();
    const double r = 0.15 + 0.25 * rng.next_double();
    o << ", ";
    switch (k % 9) {
      case 0:
      case 1:
        o << R"({"type": "sphere", "center": )" << vec(x, y, z) << R"(, "radius": )" << r << "}";
        break;
      case 2:
        o << R"({"type": "box", "min": )" << vec(x - r, y - r, z - r) << R"(, "max": )" << vec(x + r, y + r, z + r)
          << "}";
        break;
      case 3:
        o << R"({"type": "triangle", "vertices": [)" << vec(x - r, y, z) << ", " << vec(x + r, y, z + 0.1) << ", "
          << vec(x, y + 2 * r, z - r) << "]}";
        break;
      case 4:
        o << R"({"type": "polygon", "vertices": [)" << vec(x - r, y, z - r) << ", " << vec(x + r, y, z - r) << ", "
          << vec(x + r, y + r, z + r) << ", " << vec(x - r, y + r, z + r) << "]}";
        break;
      case 5:
        o << R"({"type": "cylinder", "base": )" << vec(x, y - r, z) << R"(, "apex": )" << vec(x + 0.1, y + r, z)
          << R"(, "radius": )" << 0.6 * r << "}";
        break;
      case 6:
        o << R"({"type": "cone", "base": )" << vec(x, y - r, z) << R"(, "apex": )" << vec(x, y + r, z + 0.1)
          << R"(, "base_radius": )" << r << R"(, "apex_radius": 0})";
        break;
      case 7:
        o << R"({"type": "disk", "center": )" << vec(x, y, z) << R"(, "normal": [0.3, 1, 0.2], "radius": )" << r << "}";
        break;
      case 8:  // transformed: the ray goes to the object's space
        o << R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": {"scale": )"
          << vec(r, 0.5 * r, 1.3 * r) << R"(, "rotate": {"axis": [1, 1, 0], "angle": 30}, "translate": )"
          << vec(x, y, z) << "}}";
        break;
    }
  }
  std::ostringstream json;
  json << R"({
  "render": {"width": 64, "height": 48},
  "camera": {"position": [0, 6, 14], "look_at": [0, 0.5, 0], "fov_y": 50},
  "lights": [{"type": "point", "position": [-4, 12, 6]}],
  "objects": [)" << o.str() << R"(]
})";
  return parse_scene(json.str(), "many-objects.json", fs::path(GLINT_SOURCE_DIR) / "scenes" / "meshes");
}

bool same_bits(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }

// intersect_packet against intersect() ray by ray; returns the rays hit.
int expect_same_hits(const Accelerator& accel, const Ray* rays, int count, const char* what) {
  std::optional<Hit> got[kPacketSize];
  accel.intersect_packet(rays, count, got);
  int hits = 0;
  for (int i = 0; i < count; ++i) {
    const std::optional<Hit> want = accel.intersect(rays[i]);
    EXPECT_EQ(got[i].has_value(), want.has_value()) << what << " ray " << i;
    if (!got[i] || !want) continue;
    ++hits;
    EXPECT_TRUE(same_bits(got[i]->t, want->t)) << what << " ray " << i << ": " << got[i]->t << " vs " << want->t;
    EXPECT_EQ(got[i]->object, want->object) << what << " ray " << i;
    EXPECT_TRUE(same_bits(got[i]->b1, want->b1) && same_bits(got[i]->b2, want->b2)) << what << " ray " << i;
    EXPECT_EQ(got[i]->face, want->face) << what << " ray " << i;
    EXPECT_EQ(got[i]->primitive, want->primitive) << what << " ray " << i;
    for (int v = 0; v < 3; ++v)
      EXPECT_TRUE(got[i]->vertices[v].x == want->vertices[v].x && got[i]->vertices[v].y == want->vertices[v].y &&
                  got[i]->vertices[v].z == want->vertices[v].z)
          << what << " ray " << i;
  }
  return hits;
}

// occluded_packet against occluded() ray by ray, with the shadow cache
// empty, out of range, naming a plane, an object blocking some ray, and an
// object blocking none; a cache the call changes names an object that
// blocks a ray it found blocked. Returns the rays blocked.
int expect_same_shadows(const Accelerator& accel, const Scene& scene, const Ray* rays, int count, Rng& rng,
                        const char* what) {
  bool want[kPacketSize];
  int blocked_count = 0;
  uint32_t blocker_of_some = kNoShadowBlocker;
  for (int i = 0; i < count; ++i) {
    want[i] = accel.occluded(rays[i]);
    blocked_count += want[i];
    if (want[i]) blocker_of_some = *accel.first_blocker(rays[i]);
  }
  const auto objects = static_cast<uint32_t>(scene.objects.size());
  const uint32_t caches[] = {kNoShadowBlocker, objects + 5, 0 /* the plane */, blocker_of_some,
                             static_cast<uint32_t>(rng.next_double() * objects)};
  for (const uint32_t start : caches) {
    uint32_t cache = start;
    bool got[kPacketSize];
    accel.occluded_packet(rays, count, got, cache);
    bool some_blocked_by_cache = cache == start;
    for (int i = 0; i < count; ++i) {
      EXPECT_EQ(got[i], want[i]) << what << " ray " << i << ", cache " << start;
      if (got[i] && cache != start && occludes_object(scene, cache, rays[i])) some_blocked_by_cache = true;
    }
    EXPECT_TRUE(some_blocked_by_cache) << what << ": cache " << start << " -> " << cache;
  }
  return blocked_count;
}

TEST(ObjectPackets, SameHitsAndShadowsAsRayByRay) {
  const Scene scene = many_objects_scene();
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const Vec3 light = scene.lights[0].position;
  Rng rng(5);
  int rays = 0, hits = 0, shadows = 0, blocked = 0;

  // Camera rays in rows of 16 (as the renderer makes them), from two
  // cameras: looking down on the grid, and grazing over it.
  for (const Vec3& position : {Vec3(0, 6, 14), Vec3(-9, 0.8, -8)}) {
    Camera camera = scene.camera;
    camera.position = position;
    const int w = 96, h = 64;
    const CameraFrame frame = make_camera_frame(camera, w, h);
    for (int y = 0; y < h; ++y)
      for (int x0 = 0; x0 < w; x0 += kPacketSize) {
        const int n = std::min(kPacketSize, w - x0 + (y % 3 == 0 ? -5 : 0));  // some partial packets
        Ray camera_rays[kPacketSize], shadow[kPacketSize];
        for (int i = 0; i < n; ++i) camera_rays[i] = generate_camera_ray(frame, (x0 + i + 0.5) / w, (y + 0.5) / h);
        hits += expect_same_hits(*bvh, camera_rays, n, "camera");
        rays += n;
        // Their shadow rays toward the light, from a little before each hit
        // (as the renderer's start above the surface).
        int m = 0;
        for (int i = 0; i < n; ++i) {
          const auto hit = bvh->intersect(camera_rays[i]);
          if (!hit) continue;
          shadow[m].origin = camera_rays[i].origin + (hit->t - 1e-4) * camera_rays[i].direction;
          shadow[m].direction = light - shadow[m].origin;
          shadow[m].t_max = 1.0;
          ++m;
        }
        blocked += expect_same_shadows(*bvh, scene, shadow, m, rng, "shadow");
        shadows += m;
      }
  }

  for (int k = 0; k < 400; ++k) {
    // Coherent: from points spread over the scene toward one far target
    // (every direction's signs alike), some with t_min > 0 or a finite t_max.
    Ray coherent[kPacketSize];
    const Vec3 target(rng.next_double() * 40 - 20, 4 + rng.next_double() * 10, rng.next_double() * 40 - 20);
    const double spread = k % 2 ? 0.5 : 6.0;
    const Vec3 center(rng.next_double() * 10 - 5, 0.1 + rng.next_double() * 2, rng.next_double() * 10 - 5);
    for (Ray& r : coherent) {
      r.origin = center + spread * Vec3(rng.next_double() - 0.5, 0.2 * rng.next_double(), rng.next_double() - 0.5);
      r.direction = (k % 4 < 2 ? target : -target) - r.origin;
      r.t_min = rng.next_double() < 0.3 ? 0.05 : 0.0;
      r.t_max = rng.next_double() < 0.5 ? 0.3 + rng.next_double() : kInfinity;
    }
    hits += expect_same_hits(*bvh, coherent, kPacketSize, "coherent");
    blocked += expect_same_shadows(*bvh, scene, coherent, kPacketSize, rng, "coherent");
    // Incoherent: random directions (the packet is refused: ray by ray).
    Ray mixed[kPacketSize];
    for (Ray& r : mixed) {
      r.origin = Vec3(rng.next_double() * 12 - 6, rng.next_double() * 3, rng.next_double() * 12 - 6);
      r.direction = Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5);
      r.t_max = 1 + 10 * rng.next_double();
    }
    hits += expect_same_hits(*bvh, mixed, kPacketSize, "incoherent");
    blocked += expect_same_shadows(*bvh, scene, mixed, kPacketSize, rng, "incoherent");
    rays += 2 * kPacketSize;
    shadows += 2 * kPacketSize;
  }
  // Enough of each answer for the comparisons to mean something.
  EXPECT_GT(hits, rays / 4);
  EXPECT_LT(hits, rays - rays / 10);
  EXPECT_GT(blocked, shadows / 10);
  EXPECT_LT(blocked, shadows - shadows / 10);
}

// A scene whose only finite objects sit in one leaf, and one of planes only:
// the packet paths' edge cases (a root that is a leaf; no tree at all).
TEST(ObjectPackets, TinyTreesAndPlanesOnly) {
  for (const std::string& objects :
       {std::string(R"({"type": "sphere", "center": [0, 1, 0], "radius": 1}, {"type": "sphere", "center": [2, 1, 0], "radius": 0.5})"),
        std::string(R"({"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}, {"type": "plane", "point": [0, 0, -3], "normal": [0, 0, 1]})")}) {
    const Scene scene = parse_scene(R"({"camera": {"position": [0, 2, 8], "look_at": [0, 1, 0]},
      "lights": [{"type": "point", "position": [3, 6, 4]}], "objects": [)" + objects + "]}",
                                    "tiny.json", fs::path(GLINT_SOURCE_DIR));
    const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
    const CameraFrame frame = make_camera_frame(scene.camera, 64, 48);
    Rng rng(2);
    int hits = 0;
    for (int y = 0; y < 48; ++y)
      for (int x0 = 0; x0 < 64; x0 += kPacketSize) {
        Ray rays[kPacketSize];
        for (int i = 0; i < kPacketSize; ++i) rays[i] = generate_camera_ray(frame, (x0 + i + 0.5) / 64, (y + 0.5) / 48);
        hits += expect_same_hits(*bvh, rays, kPacketSize, "tiny");
        for (Ray& r : rays) {
          r.origin = r.origin + 7.0 * r.direction;
          r.direction = scene.lights[0].position - r.origin;
          r.t_max = 1.0;
        }
        expect_same_shadows(*bvh, scene, rays, kPacketSize, rng, "tiny");
      }
    EXPECT_GT(hits, 100);
  }
}

// Overlapping boxes that share their top face (and spheres that touch):
// rays meet several objects at exactly the same distance. The lower object
// index wins, as in brute force, whatever order the tree's leaves are
// visited in, so a ray gives the same hit alone, in a packet of 4 x 4 (as
// the renderer makes them) and in brute force.
TEST(ObjectPackets, TiesGoToTheLowerObjectIndex) {
  std::ostringstream o;
  o << R"({"type": "plane", "point": [0, 1, 0], "normal": [0, 1, 0]})";  // the boxes' top, too
  for (int k = 0; k < 64; ++k) {
    const double x = (k % 8) - 4, z = (k / 8) - 4;
    o << R"(, {"type": "box", "min": )" << vec(x, 0, z) << R"(, "max": )" << vec(x + 2.5, 1, z + 2.5) << "}";
    o << R"(, {"type": "sphere", "center": )" << vec(x + 0.5, 1.5, z) << R"(, "radius": 0.5})";
    o << R"(, {"type": "sphere", "center": )" << vec(x + 0.5, 1.5, z + 1) << R"(, "radius": 0.5})";
  }
  std::ostringstream json;
  json << R"({"camera": {"position": [1, 9, 11], "look_at": [0, 1, 0], "fov_y": 55},
    "lights": [{"type": "point", "position": [3, 9, 4]}], "objects": [)"
       << o.str() << "]}";
  const Scene scene = parse_scene(json.str(), "ties.json", fs::path(GLINT_SOURCE_DIR));
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const auto brute = build_brute_force(scene);
  const int w = 128, h = 96;
  const CameraFrame frame = make_camera_frame(scene.camera, w, h);
  int compared = 0, ties = 0;
  for (int y0 = 0; y0 < h; y0 += 4)
    for (int x0 = 0; x0 < w; x0 += 4) {
      Ray rays[kPacketSize];
      int n = 0;
      for (int y = y0; y < y0 + 4; ++y)
        for (int x = x0; x < x0 + 4; ++x) rays[n++] = generate_camera_ray(frame, (x + 0.5) / w, (y + 0.5) / h);
      std::optional<Hit> got[kPacketSize];
      bvh->intersect_packet(rays, n, got);
      for (int i = 0; i < n; ++i) {
        const std::optional<Hit> alone = bvh->intersect(rays[i]), want = brute->intersect(rays[i]);
        ASSERT_EQ(got[i].has_value(), want.has_value());
        ASSERT_EQ(alone.has_value(), want.has_value());
        if (!want) continue;
        ++compared;
        EXPECT_EQ(got[i]->object, want->object) << "packet, pixel " << x0 + i % 4 << "," << y0 + i / 4;
        EXPECT_EQ(alone->object, want->object) << "alone, pixel " << x0 + i % 4 << "," << y0 + i / 4;
        EXPECT_TRUE(same_bits(got[i]->t, want->t) && same_bits(alone->t, want->t));
        // A tie: some other object is hit at the very same distance.
        Ray beyond = rays[i];
        beyond.t_max = std::nextafter(want->t, kInfinity);
        int at_t = 0;
        for (uint32_t k = 0; k < scene.objects.size(); ++k) {
          Hit hk;
          at_t += intersect_object(scene, k, beyond, hk) && hk.t == want->t;
        }
        ties += at_t > 1;
      }
    }
  EXPECT_GT(compared, 4000);
  EXPECT_GT(ties, 1000);  // the case this test is about
}

}  // namespace
}  // namespace glint
