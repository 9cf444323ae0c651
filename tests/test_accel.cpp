// The accelerators on triangles: the watertight ray/triangle test on edges,
// vertices and parallel rays; no ray escapes a sealed sphere mesh from inside
// (double test, our float mesh BVH, Embree); the mesh BVH against brute force
// on random rays; and both backends giving the same image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <map>
#include <memory>

#include "glint/accel/accelerator.h"
#include "glint/accel/huge_pages.h"
#include "glint/accel/mesh_bvh.h"
#include "glint/accel/ray_packets.h"
#include "glint/geometry/polygon.h"
#include "glint/geometry/shapes.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/camera.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

Ray make_ray(const Vec3& origin, const Vec3& direction) {
  Ray r;
  r.origin = origin;
  r.direction = direction;
  return r;
}

// --- ray/triangle edge cases -------------------------------------------------

TEST(WatertightTriangle, HitsInsideAndReportsBarycentrics) {
  const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const auto h = intersect_triangle(tri, make_ray({0.25, 0.5, 2}, {0, 0, -1}));
  ASSERT_TRUE(h);
  EXPECT_DOUBLE_EQ(h->t, 2.0);
  EXPECT_DOUBLE_EQ(h->b1, 0.25);
  EXPECT_DOUBLE_EQ(h->b2, 0.5);
}

TEST(WatertightTriangle, BothSidesAreHit) {
  const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(intersect_triangle(tri, make_ray({0.2, 0.2, 1}, {0, 0, -1})));
  EXPECT_TRUE(intersect_triangle(tri, make_ray({0.2, 0.2, -1}, {0, 0, 1})));
}

TEST(WatertightTriangle, EdgesAndVerticesCountAsInside) {
  const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (const Vec3 p :
       {Vec3(0.5, 0, 0), Vec3(0, 0.5, 0), Vec3(0.5, 0.5, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)})
    EXPECT_TRUE(intersect_triangle(tri, make_ray(p + Vec3(0, 0, 3), {0, 0, -1}))) << "point " << p.x << " " << p.y;
  EXPECT_FALSE(intersect_triangle(tri, make_ray({0.5000001, 0.5, 3}, {0, 0, -1})));
  EXPECT_FALSE(intersect_triangle(tri, make_ray({-1e-9, 0.5, 3}, {0, 0, -1})));
}

TEST(WatertightTriangle, RaysInTheTrianglesPlaneMiss) {
  const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_FALSE(intersect_triangle(tri, make_ray({-1, 0.2, 0}, {1, 0, 0})));  // through it, edge-on
  EXPECT_FALSE(intersect_triangle(tri, make_ray({-1, 0.2, 1}, {1, 0, 0})));  // parallel above it
  EXPECT_EQ(triangle_plane_hit(tri, make_ray({-1, 0.2, 0}, {1, 0, 0})).t, kInfinity);
}

TEST(WatertightTriangle, RespectsTheOpenInterval) {
  const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  Ray r = make_ray({0.2, 0.2, 1}, {0, 0, -1});
  r.t_max = 1.0;  // the hit is at exactly t = 1: outside (t_min, t_max)
  EXPECT_FALSE(intersect_triangle(tri, r));
  r.t_max = 1.0 + 1e-12;
  EXPECT_TRUE(intersect_triangle(tri, r));
  r.t_min = 1.0;
  EXPECT_FALSE(intersect_triangle(tri, r));
}

TEST(WatertightTriangle, SharedEdgeOfTwoTrianglesHasNoCrack) {
  // Two triangles sharing the diagonal of a skewed quad; rays aimed exactly
  // at points of the diagonal (in double, as the mesh vertices are) from many
  // directions must hit one or the other.
  const Vec3 a(0.1, 0.3, 0.7), b(2.3, 0.2, 0.9), c(2.1, 1.9, 0.4), d(0.05, 2.2, 0.6);
  const Triangle t1{a, b, c}, t2{a, c, d};
  Rng rng(7);
  int misses = 0;
  for (int i = 0; i < 20000; ++i) {
    const double s = rng.next_double();
    const Vec3 target = a + s * (c - a);
    const Vec3 origin(rng.next_double() * 4 - 2, rng.next_double() * 4 - 2, 3 + rng.next_double() * 3);
    const Ray r = make_ray(origin, target - origin);
    if (!intersect_triangle(t1, r) && !intersect_triangle(t2, r)) ++misses;
  }
  EXPECT_EQ(misses, 0);
}

// --- a sealed sphere mesh ------------------------------------------------------

// An icosphere: 20 * 4^levels triangles sharing their vertices.
Mesh icosphere(int levels, double radius) {
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, p, 0},  {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                         {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                             4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                             6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (Vec3& x : v) x = normalize(x);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t i, uint32_t j) {
      const auto key = std::minmax(i, j);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(normalize(v[i] + v[j]));
      return mid[key] = static_cast<uint32_t>(v.size() - 1);
    };
    std::vector<uint32_t> next;
    for (size_t t = 0; t < f.size(); t += 3) {
      const uint32_t a = f[t], b = f[t + 1], c = f[t + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = std::move(next);
  }
  Mesh mesh;
  mesh.file = "icosphere";
  for (const Vec3& x : v)
    mesh.positions.push_back(
        Vec3f{static_cast<float>(radius * x.x), static_cast<float>(radius * x.y), static_cast<float>(radius * x.z)});
  mesh.indices = f;
  mesh.triangle_material.assign(f.size() / 3, 0);
  return mesh;
}

// Directions toward vertices and edge midpoints (where cracks show) and random ones.
std::vector<Vec3> probe_targets(const Mesh& mesh, Rng& rng, int random_count) {
  std::vector<Vec3> targets;
  for (const Vec3f& p : mesh.positions) targets.push_back(to_vec3(p));
  for (size_t t = 0; t < mesh.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k)
      targets.push_back(0.5 * (to_vec3(mesh.positions[mesh.indices[t + k]]) +
                               to_vec3(mesh.positions[mesh.indices[t + (k + 1) % 3]])));
  for (int i = 0; i < random_count; ++i)
    targets.push_back(Vec3(rng.next_double() * 2 - 1, rng.next_double() * 2 - 1, rng.next_double() * 2 - 1));
  return targets;
}

TEST(SealedSphere, NoRayEscapesFromInside) {
  Scene scene;
  add_mesh_object(scene, add_mesh(scene, icosphere(3, 1.0)), 0, true);  // 1280 triangles
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  std::unique_ptr<Accelerator> embree;
  if (embree_available()) embree = build_embree_accelerator(scene, AcceleratorOptions{1, AccelBackend::embree});
  Rng rng(11);
  const std::vector<Vec3> targets = probe_targets(scene.meshes[0], rng, 2000);
  int escaped_bvh = 0, escaped_brute = 0, escaped_embree = 0, rays = 0;
  for (const Vec3 origin : {Vec3(0, 0, 0), Vec3(0.3, -0.2, 0.1), Vec3(-0.55, 0.4, 0.3)}) {
    for (const Vec3& target : targets) {
      const Ray r = make_ray(origin, target - origin);
      ++rays;
      escaped_bvh += !bvh->intersect(r).has_value();
      escaped_brute += !brute->intersect(r).has_value();
      if (embree) escaped_embree += !embree->intersect(r).has_value();
    }
  }
  EXPECT_GT(rays, 10000);
  EXPECT_EQ(escaped_bvh, 0);
  EXPECT_EQ(escaped_brute, 0);
  // Embree's robust mode (which its backend uses) is nearly watertight: in
  // its default mode 615 of these rays escaped, in robust mode 1 (aimed
  // exactly at a vertex). Ours lets none through.
  EXPECT_LE(escaped_embree, rays / 5000) << escaped_embree << " of " << rays;
}

TEST(SealedSphere, FarCamerasSeeTheSameHitsAsBruteForce) {
  // A small mesh (radius 0.01) seen from up to 10^5 radii away: the float
  // slab test rounds `plane - origin` at the origin's magnitude, far more
  // than the boxes' padding (2^-20 of the mesh's extent); the widening of
  // the far distances by a few ulps of t has to cover it. Rays aim just
  // inside the corners of the triangles that face the origin (no grazing
  // rays, where float and double tests may differ), which is where their
  // leaf boxes' faces are.
  Scene scene;
  add_mesh_object(scene, add_mesh(scene, icosphere(3, 0.01)), 0, true);
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const auto brute = build_brute_force(scene);
  const Mesh& mesh = scene.meshes[0];
  int rays = 0, mismatches = 0;
  for (const double distance : {1.0, 100.0, 1000.0})
    for (const Vec3 dir : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0.6, 0.8, 0), Vec3(-1, 2, 3), Vec3(3, -1, 0.5)}) {
      const Vec3 origin = distance * normalize(dir);
      for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        const Triangle tri = mesh_triangle(mesh, t);
        const Vec3 centroid = (tri.v0 + tri.v1 + tri.v2) / 3.0;
        const Vec3 normal = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
        if (std::abs(dot(normal, normalize(origin - centroid))) < 0.5 || dot(centroid, origin - centroid) < 0) continue;
        for (const Vec3& corner : {tri.v0, tri.v1, tri.v2}) {
          const Ray r = make_ray(origin, corner + 0.02 * (centroid - corner) - origin);
          const auto got = bvh->intersect(r), want = brute->intersect(r);
          ++rays;
          // Near a shared vertex the float kernel may pick a neighbour of the
          // double test's triangle (positions relative to an origin 10^4
          // radii away are rounded to ~4e-6); its refined distance is then
          // within float precision. A culled box would show as a miss or as
          // the sphere's far side, 2e-4 of t further.
          if (got.has_value() != want.has_value() || (got && std::abs(got->t - want->t) > 1e-6 * want->t)) ++mismatches;
        }
      }
    }
  EXPECT_GT(rays, 3000);
  EXPECT_EQ(mismatches, 0) << "of " << rays << " rays";
}

// --- the mesh BVH against brute force ------------------------------------------

// A triangle soup: `count` triangles, overlapping and intersecting, each
// around a center in [-half_extent, half_extent]^3 and within a cube of side
// size(i) (which may draw from `rng` too).
template <class SizeFn>
Mesh triangle_soup(Rng& rng, int count, double half_extent, SizeFn size) {
  Mesh soup;
  soup.file = "soup";
  const double extent = 2 * half_extent;
  for (int i = 0; i < count; ++i) {
    const Vec3 c(rng.next_double() * extent - half_extent, rng.next_double() * extent - half_extent,
                 rng.next_double() * extent - half_extent);
    const double side = size(i);
    for (int k = 0; k < 3; ++k) {
      soup.positions.push_back(Vec3f{static_cast<float>(c.x + side * (rng.next_double() - 0.5)),
                                     static_cast<float>(c.y + side * (rng.next_double() - 0.5)),
                                     static_cast<float>(c.z + side * (rng.next_double() - 0.5))});
      soup.indices.push_back(static_cast<uint32_t>(soup.positions.size() - 1));
    }
  }
  soup.triangle_material.assign(soup.triangle_count(), 0);
  return soup;
}

TEST(MeshBvh, SameClosestHitsAsBruteForceOnRandomRays) {
  // Of all sizes.
  Rng rng(5);
  Mesh soup = triangle_soup(rng, 3000, 5.0, [&](int i) { return 0.05 + rng.next_double() * (i % 50 == 0 ? 4.0 : 0.6); });
  Scene scene;
  add_mesh_object(scene, add_mesh(scene, std::move(soup)), 0, true);
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  int hits = 0, mismatches = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 o(rng.next_double() * 14 - 7, rng.next_double() * 14 - 7, rng.next_double() * 14 - 7);
    const Vec3 d = normalize(Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5));
    Ray r = make_ray(o, d);
    if (i % 3 == 0) r.t_max = 4.0;  // bounded rays too
    const auto a = bvh->intersect(r), b = brute->intersect(r);
    ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i;
    EXPECT_EQ(bvh->occluded(r), b.has_value()) << "ray " << i;
    if (!a) continue;
    ++hits;
    // The same triangle, unless two are hit at (float-)equal distances.
    if (a->primitive != b->primitive && std::abs(a->t - b->t) > 1e-5 * b->t) ++mismatches;
    EXPECT_NEAR(a->t, b->t, 1e-5 * b->t) << "ray " << i;
  }
  EXPECT_GT(hits, 2000);
  EXPECT_EQ(mismatches, 0);
}

// A scene of one mesh takes the accelerator's shortcut (the mesh's own tree,
// no top level): with a transform, rays go to the mesh's space first. The
// same hits as brute force, single rays and packets, on a rotated, scaled
// and moved soup.
TEST(MeshBvh, OneTransformedMeshMatchesBruteForce) {
  Rng rng(7);
  Mesh soup = triangle_soup(rng, 2000, 2.0, [](int) { return 0.4; });
  Scene scene;
  const Transform moved =
      compose(Transform::translate({1, -2, 0.5}),
              compose(Transform::rotate(normalize(Vec3(1, 2, 3)), 40.0), Transform::scale({2, 0.5, 1.5})));
  add_mesh_object(scene, add_mesh(scene, std::move(soup)), 0, true, moved);
  add_plane(scene, Plane{{0, -2.5, 0}, {0, 1, 0}});  // below most of the soup: some rays meet it first
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const auto brute = build_brute_force(scene);
  int hits = 0, plane_hits = 0;
  for (int i = 0; i < 4000; i += kPacketSize) {
    // A packet of rays from one point toward neighbouring directions (of 12
    // rays every other time).
    const int count = i % (2 * kPacketSize) == 0 ? kPacketSize : 12;
    const Vec3 o(rng.next_double() * 16 - 8, rng.next_double() * 16 - 8, 10);
    const Vec3 toward = Vec3(1, -2, 0.5) - o;
    Ray rays[kPacketSize];
    for (int k = 0; k < count; ++k)
      rays[k] = make_ray(o, toward + Vec3(rng.next_double() * 4 - 2, rng.next_double() * 4 - 2, 0));
    std::optional<Hit> packet[kPacketSize];
    bvh->intersect_packet(rays, count, packet);
    for (int k = 0; k < count; ++k) {
      const auto a = bvh->intersect(rays[k]), b = brute->intersect(rays[k]);
      ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i + k;
      ASSERT_EQ(packet[k].has_value(), b.has_value()) << "ray " << i + k;
      if (!a) continue;
      ++hits;
      plane_hits += a->object == 1;
      EXPECT_EQ(packet[k]->object, a->object) << "ray " << i + k;
      EXPECT_EQ(packet[k]->primitive, a->primitive) << "ray " << i + k;
      EXPECT_EQ(packet[k]->t, a->t) << "ray " << i + k;
      EXPECT_EQ(packet[k]->b1, a->b1) << "ray " << i + k;
      EXPECT_EQ(packet[k]->b2, a->b2) << "ray " << i + k;
      EXPECT_EQ(a->object, b->object) << "ray " << i + k;
      // The same triangle, unless two are hit at (float-)equal distances:
      // the same distance either way.
      EXPECT_NEAR(a->t, b->t, 1e-5 * b->t) << "ray " << i + k;
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(plane_hits, 50);
}

// The build's threads (parallel subtrees, refs filled in parts, the root's
// subtrees collapsed at once) change nothing: the same nodes and blocks
// (their bytes' digest) and the same hits, to the bit, for any thread count.
// (Through the library: the tree's own types depend on its SIMD width, which
// this file is not compiled for.)
TEST(MeshBvh, SameTreeForEveryThreadCount) {
  Rng rng(11);
  Mesh soup;
  soup.file = "soup";
  for (int i = 0; i < 40000; ++i) {
    const Vec3 c(rng.next_double() * 10, rng.next_double() * 3, rng.next_double() * 10);
    for (int k = 0; k < 3; ++k) {
      soup.positions.push_back(Vec3f{static_cast<float>(c.x + 0.2 * rng.next_double()),
                                     static_cast<float>(c.y + 0.2 * rng.next_double()),
                                     static_cast<float>(c.z + 0.2 * rng.next_double())});
      soup.indices.push_back(static_cast<uint32_t>(soup.positions.size() - 1));
    }
  }
  soup.triangle_material.assign(soup.triangle_count(), 0);
  Scene scene;
  add_mesh_object(scene, add_mesh(scene, std::move(soup)), 0, true);
  BvhBuildOptions one_thread;
  one_thread.threads = 1;
  const uint64_t digest = mesh_bvh_digest(scene.meshes[0], one_thread);
  const auto reference = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  std::vector<Ray> rays;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 o(rng.next_double() * 14 - 2, rng.next_double() * 6 - 1.5, rng.next_double() * 14 - 2);
    rays.push_back(make_ray(o, Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5)));
  }
  for (int threads : {2, 3, 8}) {
    BvhBuildOptions options;
    options.threads = threads;
    EXPECT_EQ(mesh_bvh_digest(scene.meshes[0], options), digest) << threads << " threads";
    const auto bvh = build_accelerator(scene, AcceleratorOptions{threads, AccelBackend::bvh});
    EXPECT_EQ(bvh->memory_bytes(), reference->memory_bytes()) << threads << " threads";
    int hits = 0;
    for (const Ray& r : rays) {
      const auto a = bvh->intersect(r), b = reference->intersect(r);
      ASSERT_EQ(a.has_value(), b.has_value()) << threads << " threads";
      EXPECT_EQ(bvh->occluded(r), reference->occluded(r));
      if (!a) continue;
      ++hits;
      EXPECT_EQ(a->t, b->t);
      EXPECT_EQ(a->primitive, b->primitive);
    }
    EXPECT_GT(hits, 1000);
  }
}

// The collapse into wide nodes is planned by the surface area heuristic over
// every way of spreading a subtree over a node's slots, so nodes near the
// leaves are not left part empty: there are at most 1.5 times as many wide
// nodes as the fewest that could hold the leaves (1.43 on the height field
// with 8 slots; the greedy collapse before the plan made 1.9 times as many
// on the bench's 1M terrain). Also where every box has zero area (collinear
// triangles), where each split ties with a node of its own. A plan that opens
// no child beyond a node's own two, or keeps zero-area nodes whole, fails.
BvhShape shape_of(const Mesh& mesh, int threads) {
  BvhBuildOptions options;
  options.threads = threads;
  return mesh_bvh_shape(mesh, options);
}
void expect_well_filled(const BvhShape& shape, const char* what) {
  ASSERT_GT(shape.nodes, 1u) << what;
  ASSERT_GE(shape.width, 4) << what;
  const double fewest = std::ceil(static_cast<double>(shape.leaves - 1) / (shape.width - 1));
  EXPECT_LE(shape.nodes, 1.5 * fewest) << what << ": " << shape.nodes << " nodes for " << shape.leaves << " leaves";
}

TEST(MeshBvh, WideNodesAreWellFilled) {
  Mesh terrain;
  terrain.file = "terrain";
  const int n = 200;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      terrain.positions.push_back(
          Vec3f{static_cast<float>(i), static_cast<float>(std::sin(0.11 * i) * std::cos(0.07 * j) * 5.0),
                static_cast<float>(j)});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
      terrain.indices.insert(terrain.indices.end(), {a, b, d, a, d, c});
    }
  terrain.triangle_material.assign(terrain.triangle_count(), 0);
  Mesh line;  // degenerate triangles along the x axis: every box has zero area
  line.file = "line";
  for (int i = 0; i < 20000; ++i) {
    for (float dx : {0.0f, 0.5f, 1.0f}) line.positions.push_back(Vec3f{static_cast<float>(i) + dx, 0.0f, 0.0f});
    line.indices.insert(line.indices.end(), {3u * i, 3u * i + 1, 3u * i + 2});
  }
  line.triangle_material.assign(line.triangle_count(), 0);
  for (int threads : {1, 2}) {
    expect_well_filled(shape_of(terrain, threads), "height field");
    expect_well_filled(shape_of(line, threads), "collinear triangles");
  }
}

TEST(MeshBvh, AxisParallelRaysMatchBruteForce) {
  // Axis-aligned cubes on a lattice, and rays along the axes (two direction
  // components zero, of either sign) from points on the cubes' face planes,
  // their edges and between them: the slab test's parallel-ray cases, where a
  // zero direction gives an inverse of +-2^100 and the origin may sit on a
  // box's plane.
  Mesh cubes;
  cubes.file = "cubes";
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const auto base = static_cast<uint32_t>(cubes.positions.size());
        for (int c = 0; c < 8; ++c)
          cubes.positions.push_back(Vec3f{static_cast<float>(i + (c & 1)), static_cast<float>(j + (c >> 1 & 1)),
                                          static_cast<float>(k + (c >> 2 & 1))});
        // Two triangles per face of the unit cube at (i, j, k); corner c has bits x, y, z.
        const uint32_t faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                      {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
        for (const auto& f : faces)
          for (const uint32_t v : {f[0], f[1], f[2], f[0], f[2], f[3]}) cubes.indices.push_back(base + v);
      }
  cubes.triangle_material.assign(cubes.triangle_count(), 0);
  Scene scene;
  add_mesh_object(scene, add_mesh(scene, std::move(cubes)), 0, false);
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const auto brute = build_brute_force(scene);
  const double zero = 0.0;
  const Vec3 directions[] = {{1, zero, zero},   {-1, zero, -zero}, {-zero, 1, zero},
                             {zero, -1, -zero}, {zero, -zero, 1},  {-zero, zero, -1}};
  const double coords[] = {-0.5, 0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 3.5};
  int rays = 0, hits = 0;
  for (const Vec3& d : directions)
    for (const double a : coords)
      for (const double b : coords)
        for (const double start : {-1.0, 0.0, 1.0, 1.5, 4.0}) {
          // Along the axis where d is non-zero from `start`, at (a, b) on the others.
          const int axis = d.x != 0 ? 0 : (d.y != 0 ? 1 : 2);
          Vec3 o;
          o[axis] = start;
          o[(axis + 1) % 3] = a;
          o[(axis + 2) % 3] = b;
          const Ray r = make_ray(o, d);
          const auto got = bvh->intersect(r), want = brute->intersect(r);
          ++rays;
          ASSERT_EQ(got.has_value(), want.has_value()) << "o " << o.x << " " << o.y << " " << o.z << " axis " << axis;
          EXPECT_EQ(bvh->occluded(r), want.has_value());
          if (!got) continue;
          ++hits;
          EXPECT_EQ(got->t, want->t);
        }
  EXPECT_GT(hits, rays / 4);
}

TEST(MeshBvh, HugeOriginsWithAxisParallelRays) {
  // Far from the world's origin, a ray with zero direction components: their
  // inverse is 2^100, and origin * inverse overflows a float beyond 2^28.
  // The fused slab distances would all be infinities of one sign then, and
  // every box was culled (found in review); such rays take the plain form.
  for (const double cx : {1e3, 2.6e8, 2.7e8, 1e9}) {  // (at 1e12 the quad is not a quad in float)
    Mesh quad;
    quad.file = "quad";
    for (const double x : {cx - 1000, cx + 1000})
      for (const double y : {-1000.0, 1000.0})
        quad.positions.push_back(Vec3f{static_cast<float>(x), static_cast<float>(y), 0.0f});
    quad.indices = {0, 1, 3, 0, 3, 2};
    quad.triangle_material.assign(2, 0);
    // The quad alone (its own BVH is the whole tree; packets take the mesh
    // kernel), and with two spheres beside it (the BVH over objects).
    Scene alone, with_spheres;
    add_mesh_object(alone, add_mesh(alone, Mesh(quad)), 0, false);
    add_mesh_object(with_spheres, add_mesh(with_spheres, std::move(quad)), 0, false);
    add_sphere(with_spheres, Sphere{{cx + 1500, 0, 0}, 10.0});
    add_sphere(with_spheres, Sphere{{cx + 1600, 0, 0}, 10.0});
    for (const Scene* scene : {&alone, &with_spheres}) {
      const auto bvh = build_accelerator(*scene, AcceleratorOptions{1, AccelBackend::bvh});
      const auto brute = build_brute_force(*scene);
      for (const double dx : {0.0, -0.0, 1e-32}) {
        for (const double x : {cx, cx + 1500.0}) {
          const Ray r = make_ray({x, 0, 100}, {dx, 0, -1});
          const auto want = brute->intersect(r);
          if (!want) continue;  // no sphere in `alone`
          const auto got = bvh->intersect(r);
          ASSERT_TRUE(got) << cx << " " << x << " " << dx;
          EXPECT_EQ(got->object, want->object);
          EXPECT_NEAR(got->t, want->t, 1e-6 * want->t);
          EXPECT_TRUE(bvh->occluded(r)) << cx << " " << x << " " << dx;
        }
        const Ray rays[2] = {make_ray({cx, 0, 100}, {dx, 0, -1}), make_ray({cx + 1, 0, 100}, {dx, 0, -1})};
        std::optional<Hit> got[2];
        bvh->intersect_packet(rays, 2, got);
        EXPECT_TRUE(got[0] && got[1]) << cx;
      }
    }
  }
}

// --- packets ----------------------------------------------------------------

// --- the shadow cache ---------------------------------------------------------

// Three unit spheres on the x axis (x = 0, 3, 6) and a floor plane under them.
constexpr const char* kThreeSpheres = R"({
  "render": {"width": 8, "height": 8},
  "camera": {"position": [3, 2, 10], "look_at": [3, 0, 0], "fov_y": 50},
  "lights": [{"type": "point", "position": [3, 5, 0]}],
  "objects": [
    {"type": "sphere", "center": [0, 0, 0], "radius": 1},
    {"type": "sphere", "center": [3, 0, 0], "radius": 1},
    {"type": "sphere", "center": [6, 0, 0], "radius": 1},
    {"type": "plane", "point": [0, -2, 0], "normal": [0, 1, 0]}
  ]
})";

Ray segment(const Vec3& from, const Vec3& to) {
  Ray r = make_ray(from, to - from);
  r.t_max = 1.0;
  return r;
}

TEST(ShadowCache, AsksTheCachedBlockerFirstAndKeepsTheLastOne) {
  const Scene scene = parse_scene(kThreeSpheres, "three.json");
  const auto accel = build_accelerator(scene);
  uint32_t cache = kNoShadowBlocker;
  // Through the sphere at x = 3 (object 1), from above to below it.
  EXPECT_TRUE(accel->occluded_cached(segment({3, 5, 0}, {3, -1.5, 0}), cache));
  EXPECT_EQ(cache, 1u);
  // The cached sphere is not in the way of this one (through x = 6): the
  // traversal finds object 2, which becomes the cached blocker.
  EXPECT_TRUE(accel->occluded_cached(segment({6, 5, 0}, {6, -1.5, 0}), cache));
  EXPECT_EQ(cache, 2u);
  // Nothing in the way (between the spheres, stopping above the floor): the cache stays.
  EXPECT_FALSE(accel->occluded_cached(segment({1.5, 5, 0}, {1.5, -1.5, 0}), cache));
  EXPECT_EQ(cache, 2u);
  // The floor plane blocks too (object 3); an index past the objects is ignored.
  cache = 99;
  EXPECT_TRUE(accel->occluded_cached(segment({1.5, 5, 0}, {1.5, -3, 0}), cache));
  EXPECT_EQ(cache, 3u);
}

TEST(ShadowCache, SameAnswersAsOccludedWhateverIsCached) {
  const Scene scene = parse_scene(kThreeSpheres, "three.json");
  const auto accel = build_accelerator(scene);
  Rng rng(7);
  int blocked = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 from(rng.next_double() * 10 - 2, rng.next_double() * 6 - 2.5, rng.next_double() * 4 - 2);
    const Vec3 to(rng.next_double() * 10 - 2, rng.next_double() * 6 - 2.5, rng.next_double() * 4 - 2);
    const Ray r = segment(from, to);
    const bool want = accel->occluded(r);
    blocked += want;
    for (uint32_t c : {kNoShadowBlocker, 0u, 1u, 2u, 3u}) {
      uint32_t cache = c;
      EXPECT_EQ(accel->occluded_cached(r, cache), want) << "ray " << i << " cache " << c;
      if (want && c == kNoShadowBlocker) {
        EXPECT_EQ(cache, *accel->first_blocker(r));
      }
    }
  }
  EXPECT_GT(blocked, 200);  // both answers are exercised
  EXPECT_LT(blocked, 1800);
}

// The BVH's leaves test untransformed spheres from their own array: the same
// closest hits (object and t, bit for bit) and the same occlusion answers as
// testing every object, on spheres of many sizes, some of them transformed,
// from rays inside, outside and grazing.
TEST(SphereLeaves, SameAnswersAsBruteForce) {
  Scene scene;
  Rng rng(41);
  for (int i = 0; i < 600; ++i) {
    const Sphere s{{rng.next_double() * 20 - 10, rng.next_double() * 20 - 10, rng.next_double() * 20 - 10},
                   0.05 + rng.next_double() * (i % 7 == 0 ? 3.0 : 0.6)};
    std::optional<Transform> xf;
    if (i % 11 == 0) xf = Transform::scale({1, 0.5 + rng.next_double(), 1});
    add_sphere(scene, s, 0, xf);
  }
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  int hits = 0, blocked = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 from(rng.next_double() * 30 - 15, rng.next_double() * 30 - 15, rng.next_double() * 30 - 15);
    Ray ray{from, {rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5}};
    if (i % 3 == 0) {
      // Aimed at a sphere's rim: grazing rays.
      const Sphere& s = scene.spheres[static_cast<size_t>(rng.next_double() * scene.spheres.size())];
      const Vec3 d = normalize(s.center - from);
      const Vec3 across = normalize(cross(d, Vec3(0.3, 1, 0.1)));
      ray.direction = (s.center + (s.radius * (1 + 1e-9 * (rng.next_double() - 0.5))) * across) - from;
    }
    const auto a = bvh->intersect(ray), b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i;
    if (a) {
      ++hits;
      EXPECT_EQ(a->object, b->object) << "ray " << i;
      EXPECT_EQ(a->t, b->t) << "ray " << i;
    }
    ray.t_max = 0.2 + rng.next_double();  // a shadow ray's segment
    const bool occluded = brute->occluded(ray);
    blocked += occluded;
    EXPECT_EQ(bvh->occluded(ray), occluded) << "ray " << i;
  }
  EXPECT_GT(hits, 2000);
  EXPECT_GT(blocked, 500);
}

// Leaves of plain triangles (triangle objects, polygons of one triangle) get
// their edge functions four at a time first: the same hits as brute force
// (object, t, barycentrics, bit for bit) and the same occlusion, on the SPD's
// tetra (triangles sharing edges and vertices: rays through them) and on
// random triangles, polygons and transformed ones.
TEST(TriangleLeaves, SameAnswersAsBruteForce) {
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/bench/spd/tetra.nff");
  Rng rng(43);
  for (int i = 0; i < 300; ++i) {
    const Vec3 c(rng.next_double() * 20 - 10, rng.next_double() * 20 - 10, rng.next_double() * 20 - 10);
    const auto corner = [&] {
      return c + Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5);
    };
    const Triangle t{corner(), corner(), corner()};
    if (i % 3 == 0) {
      add_triangle(scene, t, 0, i % 9 == 0 ? std::optional<Transform>(Transform::scale({1, 2, 1})) : std::nullopt);
    } else {
      PolygonBuild b = make_polygon({t.v0, t.v1, t.v2}, {});
      ASSERT_EQ(b.error, "");
      add_polygon(scene, std::move(b.polygon), 0,
                  i % 7 == 0 ? std::optional<Transform>(Transform::translate({0, 1, 0})) : std::nullopt);
    }
  }
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  int hits = 0, blocked = 0, ties = 0;
  for (int i = 0; i < 8000; ++i) {
    Vec3 from(rng.next_double() * 30 - 15, rng.next_double() * 30 - 15, rng.next_double() * 30 - 15);
    Vec3 to(rng.next_double() * 2 - 1, rng.next_double() * 2 - 1, rng.next_double() * 2 - 1);
    if (i % 4 == 0) {
      // Through a vertex or along an edge of one of tetra's triangles.
      const Polygon& p = scene.polygons[static_cast<size_t>(rng.next_double() * 4096)];
      to = i % 8 == 0 ? p.vertices[0] : p.vertices[0] + rng.next_double() * (p.vertices[1] - p.vertices[0]);
      from = to + Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5) * 8.0;
    }
    Ray ray{from, to - from};
    const auto a = bvh->intersect(ray), b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i;
    if (a) {
      ++hits;
      EXPECT_EQ(a->t, b->t) << "ray " << i;
      // Through a shared vertex or edge several triangles are hit at the
      // same t: the tree and the list may each keep another one of them.
      if (a->object == b->object) {
        EXPECT_EQ(a->b1, b->b1) << "ray " << i;
        EXPECT_EQ(a->b2, b->b2) << "ray " << i;
        EXPECT_EQ(a->primitive, b->primitive) << "ray " << i;
      } else {
        ++ties;
      }
    }
    ray.t_max = 0.3 + rng.next_double() * 0.7;
    const bool occluded = brute->occluded(ray);
    blocked += occluded;
    EXPECT_EQ(bvh->occluded(ray), occluded) << "ray " << i;
  }
  EXPECT_GT(hits, 1600);
  EXPECT_LT(ties, hits / 10);
  EXPECT_GT(blocked, 200);
}

// An untransformed polygon of several triangles puts each triangle in the
// tree as a primitive of its own (in the leaves of plain triangles): the
// same hits as the whole polygon tested alone (brute force) on a 144-gon (a
// fan, with a grid), a non-convex star (ear clipping) and a smooth `pp`
// hexagon, for rays through their vertices and edges too. Through an edge
// two triangles may each claim the point: then the object and t agree (to
// the ulp) and the barycentrics are the other triangle's.
TEST(PolygonTriangles, SameHitsAsTheWholePolygon) {
  Scene scene;
  std::vector<Vec3> gear, star, hexagon, normals;
  for (int k = 0; k < 144; ++k) {
    const double a = 2 * 3.141592653589793 * k / 144;
    gear.emplace_back(3 * std::cos(a), 3 * std::sin(a), 0.2 * std::cos(a));  // tilted: not axis-aligned
  }
  for (int k = 0; k < 18; ++k) {
    const double a = 2 * 3.141592653589793 * k / 18, r = k % 2 ? 1.0 : 2.5;
    star.emplace_back(5 + r * std::cos(a), 0.5, r * std::sin(a));
  }
  for (int k = 0; k < 6; ++k) {
    const double a = 2 * 3.141592653589793 * k / 6;
    hexagon.emplace_back(-5 + std::cos(a), std::sin(a), 1);
    normals.push_back(normalize(Vec3(0.3 * std::cos(a), 0.3 * std::sin(a), 1)));
  }
  for (auto [vertices, n] : {std::pair{gear, std::vector<Vec3>{}}, {star, {}}, {hexagon, normals}}) {
    PolygonBuild b = make_polygon(vertices, n);
    ASSERT_EQ(b.error, "");
    add_polygon(scene, std::move(b.polygon));
  }
  add_sphere(scene, Sphere{{0, 0, 4}, 1});
  ASSERT_GT(scene.polygons[0].triangles.size(), 100u);
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const auto brute = build_brute_force(scene);
  Rng rng(11);
  int hits = 0, blocked = 0, other_triangle = 0;
  for (int i = 0; i < 6000; ++i) {
    const Polygon& p = scene.polygons[static_cast<size_t>(i % 3)];
    const Vec3& v0 = p.vertices[static_cast<size_t>(rng.next_double() * p.vertices.size())];
    const Vec3& v1 = p.vertices[static_cast<size_t>(rng.next_double() * p.vertices.size())];
    // At a vertex, on the segment between two (an edge or across the
    // polygon), or near it.
    Vec3 to = i % 5 == 0 ? v0 : v0 + rng.next_double() * (v1 - v0);
    if (i % 3 == 0) to += Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, 0) * 0.5;
    const Vec3 from = to + Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5) * 10.0;
    Ray ray{from, to - from};
    const auto a = bvh->intersect(ray), b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i;
    if (a) {
      ++hits;
      EXPECT_EQ(a->object, b->object) << "ray " << i;
      EXPECT_NEAR(a->t, b->t, 1e-14 * b->t) << "ray " << i;
      if (a->primitive == b->primitive) {
        EXPECT_EQ(a->t, b->t) << "ray " << i;
        EXPECT_EQ(a->b1, b->b1) << "ray " << i;
        EXPECT_EQ(a->b2, b->b2) << "ray " << i;
      } else {
        ++other_triangle;
      }
    }
    ray.t_max = rng.next_double() * 1.2;
    const bool occluded = brute->occluded(ray);
    blocked += occluded;
    EXPECT_EQ(bvh->occluded(ray), occluded) << "ray " << i;
  }
  EXPECT_GT(hits, 3000);
  EXPECT_GT(blocked, 600);
  EXPECT_LT(other_triangle, hits / 20);
}

// Infinite planes are tested before the tree from their own numbers, with
// the division skipped when the crossing is behind the origin: the same
// closest hits (object, t bit for bit), occlusion and packet hits as testing
// every object, for rays from on, above and below the planes, parallel to
// them, and with negative, zero and positive t_min.
TEST(PlaneSlots, SameAnswersAsBruteForce) {
  Scene scene;
  Mesh sphere = icosphere(2, 1.0);
  add_mesh_object(scene, add_mesh(scene, std::move(sphere)), 0, true, std::nullopt);
  add_plane(scene, Plane{{0, -1.5, 0}, {0, 1, 0}});
  add_plane(scene, Plane{{0, 0, -4}, normalize(Vec3(0.2, 0.1, 1))});
  add_plane(scene, Plane{{3, 0, 0}, normalize(Vec3(-1, 0.3, 0))});
  // The loader bakes a plane's transform into its numbers; one given by hand
  // is tested through intersect_object.
  add_plane(scene, Plane{{0, 5, 0}, {0, -1, 0}});
  scene.transforms.push_back(Transform::rotate(normalize(Vec3(1, 0, 0.5)), 20.0));
  scene.objects.back().transform = static_cast<uint32_t>(scene.transforms.size() - 1);
  const auto bvh = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  const auto brute = build_brute_force(scene);
  Rng rng(7);
  int hits = 0, plane_hits = 0, blocked = 0;
  for (int i = 0; i < 4000; i += kPacketSize) {
    Ray rays[kPacketSize];
    for (int k = 0; k < kPacketSize; ++k) {
      Ray& ray = rays[k];
      ray.origin = Vec3(rng.next_double() * 8 - 4, rng.next_double() * 8 - 4, rng.next_double() * 8 - 4);
      ray.direction = Vec3(rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5);
      const int kind = (i / kPacketSize + k) % 5;
      if (kind == 1) ray.origin.y = -1.5;  // on the floor: the crossing is at t = 0
      if (kind == 2) ray.direction.y = 0;  // parallel to the floor
      if (kind == 3) ray.t_min = -2.0;     // planes behind the origin count
      if (kind == 4) ray.t_min = 0.5;
    }
    std::optional<Hit> packet[kPacketSize];
    bvh->intersect_packet(rays, kPacketSize, packet);
    for (int k = 0; k < kPacketSize; ++k) {
      Ray ray = rays[k];
      const auto a = bvh->intersect(ray), b = brute->intersect(ray);
      ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i + k;
      ASSERT_EQ(packet[k].has_value(), b.has_value()) << "ray " << i + k;
      if (b) {
        ++hits;
        plane_hits += b->object != 0;
        EXPECT_EQ(a->object, b->object) << "ray " << i + k;
        EXPECT_EQ(a->t, b->t) << "ray " << i + k;
        EXPECT_EQ(packet[k]->object, b->object) << "ray " << i + k;
        EXPECT_EQ(packet[k]->t, b->t) << "ray " << i + k;
      }
      ray.t_max = 0.5 + 3 * rng.next_double();  // a shadow ray's segment
      const bool occluded = brute->occluded(ray);
      blocked += occluded;
      EXPECT_EQ(bvh->occluded(ray), occluded) << "ray " << i + k;
    }
  }
  EXPECT_GT(plane_hits, 1500);
  EXPECT_GT(hits - plane_hits, 80);
  EXPECT_GT(blocked, 400);
}

TEST(Packets, SameHitsAsSingleRays) {
  Scene scene;
  Mesh sphere = icosphere(4, 1.0);  // 5120 triangles
  add_mesh_object(scene, add_mesh(scene, std::move(sphere)), 0, true,
                  Transform::rotate(normalize(Vec3(1, 2, 3)), 30.0));
  add_plane(scene, Plane{{0, -0.5, 0}, {0, 1, 0}});
  scene.camera.position = Vec3(0.3, 0.8, 3.0);
  scene.camera.look_at = Vec3(0, 0, 0);
  const auto accel = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  // 60 pixels a row: three full packets and one of 12 rays.
  const CameraFrame frame = make_camera_frame(scene.camera, 60, 48);
  int hits = 0, packets = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x0 = 0; x0 < 60; x0 += kPacketSize) {
      const int count = x0 + kPacketSize <= 60 ? kPacketSize : 60 - x0;
      Ray rays[kPacketSize];
      for (int i = 0; i < count; ++i) rays[i] = generate_camera_ray(frame, (x0 + i + 0.5) / 60, (y + 0.5) / 48);
      std::optional<Hit> got[kPacketSize];
      accel->intersect_packet(rays, count, got);
      ++packets;
      for (int i = 0; i < count; ++i) {
        const auto want = accel->intersect(rays[i]);
        ASSERT_EQ(got[i].has_value(), want.has_value()) << x0 + i << " " << y;
        if (!want) continue;
        ++hits;
        EXPECT_EQ(got[i]->object, want->object);
        EXPECT_EQ(got[i]->primitive, want->primitive);
        EXPECT_EQ(got[i]->t, want->t);
        EXPECT_EQ(got[i]->b1, want->b1);
      }
    }
  }
  EXPECT_GT(hits, 1000);
  // A packet of rays in opposite directions is traced ray by ray, still right.
  Ray mixed[2] = {make_ray({0, 0, 3}, {0, 0, -1}), make_ray({0, 0, -3}, {0, 0, 1})};
  std::optional<Hit> got[2];
  accel->intersect_packet(mixed, 2, got);
  ASSERT_TRUE(got[0] && got[1]);
  EXPECT_NEAR(got[0]->t, 2.0, 1e-2);
  EXPECT_NEAR(got[1]->t, 2.0, 1e-2);
}

// make_ray_packet (converted and transposed in SIMD registers where the
// CPU has AVX2) against the lane-by-lane reference, byte for byte, on
// special values: zeros of both signs, infinities, NaNs, t_max at and
// around 3e38 (where clamp_to_float switches to infinity) and beyond the
// float range, denormals, directions past the inverse's clamp, and every
// packet size.
TEST(Packets, MakeRayPacketMatchesTheReference) {
  const double specials[] = {0.0,     -0.0,    1.0,      -1.0,     kInfinity, -kInfinity,  std::nan(""),
                             3.0e38,  2.9999999999999997e38, 3.0000000000000004e38, 3.4028235e38, 1e39,
                             -1e39,   1e-40,   -1e-45,   0x1p-101, -0x1p-101, 0x1p100,     1e-300};
  Rng rng(11);
  const auto value = [&] {
    const double u = rng.next_double();
    if (u < 0.4) return specials[static_cast<size_t>(rng.next_double() * std::size(specials))];
    return (rng.next_double() - 0.5) * std::pow(10.0, rng.next_double() * 12 - 6);
  };
  int compared = 0;
  for (int round = 0; round < 3000; ++round) {
    Ray rays[kPacketSize];
    for (Ray& r : rays) r = Ray{{value(), value(), value()}, {value(), value(), value()}, value(), value()};
    const int count = 1 + round % kPacketSize;
    for (const PacketTMax mode : {PacketTMax::inclusive, PacketTMax::as_is}) {
      const RayPacket got = make_ray_packet(rays, count, mode), want = make_ray_packet_reference(rays, count, mode);
      ASSERT_EQ(got.count, want.count);
      EXPECT_EQ(std::memcmp(got.origin, want.origin, sizeof got.origin), 0) << "round " << round;
      EXPECT_EQ(std::memcmp(got.direction, want.direction, sizeof got.direction), 0) << "round " << round;
      EXPECT_EQ(std::memcmp(got.inv_direction, want.inv_direction, sizeof got.inv_direction), 0) << "round " << round;
      EXPECT_EQ(std::memcmp(got.t_min, want.t_min, sizeof got.t_min), 0) << "round " << round;
      EXPECT_EQ(std::memcmp(got.t_max, want.t_max, sizeof got.t_max), 0) << "round " << round;
      EXPECT_EQ(std::memcmp(got.triangle, want.triangle, sizeof got.triangle), 0) << "round " << round;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 6000);
}

TEST(Packets, TiesOnSharedEdgesGoToTheLowerTriangleInBothKernels) {
  // A grid of 8 x 8 quads in z = 0, each split along its diagonal; rays
  // straight down through grid lines, vertices and diagonals hit two or more
  // triangles at exactly the same distance.
  Mesh grid;
  grid.file = "grid";
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) grid.positions.push_back(Vec3f{-1.0f + 0.25f * i, -1.0f + 0.25f * j, 0.0f});
  for (uint32_t j = 0; j < 8; ++j)
    for (uint32_t i = 0; i < 8; ++i) {
      const uint32_t a = j * 9 + i, b = a + 1, c = a + 9, d = c + 1;
      grid.indices.insert(grid.indices.end(), {a, b, d, a, d, c});
    }
  grid.triangle_material.assign(grid.triangle_count(), 0);
  Scene scene;
  add_mesh_object(scene, add_mesh(scene, std::move(grid)), 0, false);
  const auto accel = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::bvh});
  std::vector<Ray> rays;
  for (int j = 1; j < 8; ++j)
    for (int i = 1; i < 8; ++i) {
      const double x = -1.0 + 0.25 * i, y = -1.0 + 0.25 * j;
      for (const Vec3 p : {Vec3(x, y, 5), Vec3(x + 0.125, y, 5), Vec3(x + 0.125, y + 0.125, 5), Vec3(x, y + 0.1, 5)})
        rays.push_back(make_ray(p, {0, 0, -1}));
    }
  int ties = 0;
  for (size_t k = 0; k + kPacketSize <= rays.size(); k += kPacketSize) {
    std::optional<Hit> got[kPacketSize];
    accel->intersect_packet(&rays[k], kPacketSize, got);
    for (int i = 0; i < kPacketSize; ++i) {
      const auto want = accel->intersect(rays[k + i]);
      ASSERT_TRUE(want && got[i]);
      EXPECT_EQ(got[i]->primitive, want->primitive) << "ray " << k + i;
      // The winner is the lowest-numbered triangle hit at that distance.
      uint32_t lowest = UINT32_MAX;
      int hit_count = 0;
      for (uint32_t t = 0; t < scene.meshes[0].triangle_count(); ++t)
        if (intersect_triangle(mesh_triangle(scene.meshes[0], t), rays[k + i])) {
          lowest = std::min(lowest, t);
          ++hit_count;
        }
      ties += hit_count > 1;
      EXPECT_EQ(want->primitive, lowest) << "ray " << k + i;
    }
  }
  EXPECT_GT(ties, 100);
}

// --- both backends ---------------------------------------------------------

double fraction_within(const Image& a, const Image& b, double tolerance) {
  size_t close = 0;
  for (size_t i = 0; i < a.rgb.size(); i += 3) {
    bool ok = true;
    for (int c = 0; c < 3; ++c) ok &= std::abs(a.rgb[i + c] - b.rgb[i + c]) <= tolerance;
    close += ok;
  }
  return static_cast<double>(close) / (a.rgb.size() / 3);
}

void expect_same_image_with_both_backends(const std::string& scene_file) {
  if (!embree_available()) GTEST_SKIP() << "glint was built without Embree";
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/" + scene_file);
  scene.render.width /= 2;
  scene.render.height /= 2;
  scene.render.samples_per_pixel = 1;
  const auto ours = build_accelerator(scene, AcceleratorOptions{2, AccelBackend::bvh});
  const auto embree = build_accelerator(scene, AcceleratorOptions{2, AccelBackend::embree});
  RenderOptions options;
  options.threads = 2;
  const Image a = render_image(scene, *ours, options);
  const Image b = render_image(scene, *embree, options);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_GE(fraction_within(a, b, 1e-4), 0.999) << scene_file;
}

TEST(Backends, SameImageForTheMeshShowcase) { expect_same_image_with_both_backends("scenes/meshes/bunny.json"); }
TEST(Backends, SameImageForTheShowcase) { expect_same_image_with_both_backends("scenes/showcase.json"); }
TEST(Backends, SameImageForRefraction) { expect_same_image_with_both_backends("scenes/figures/refraction.json"); }
TEST(Backends, SameImageForCsgAndTori) {
  expect_same_image_with_both_backends("scenes/beyond/die.json");
  expect_same_image_with_both_backends("scenes/beyond/torus-knot.json");
}

TEST(Backends, EmbreeIsRefusedClearlyWhenMissing) {
  if (embree_available()) GTEST_SKIP() << "glint was built with Embree";
  Scene scene;
  EXPECT_THROW(build_accelerator(scene, AcceleratorOptions{1, AccelBackend::embree}), Error);
}

}  // namespace
}  // namespace glint

namespace glint {
namespace {

// The one big buffer kept between phases (huge_pages.h): the larger of two
// freed stays, a request takes it only when it is big enough, and
// release_recycled_buffer (which build_accelerator calls) frees it.
TEST(RecycledBuffer, KeepsTheLargerAndGivesItToARequestItFits) {
  release_recycled_buffer();
  {  // without a BufferRecycling alive nothing is kept
    void* p = std::aligned_alloc(kHugePageBytes, size_t{4} << 20);
    ASSERT_TRUE(p);
    EXPECT_FALSE(keep_recycled_buffer(p, size_t{4} << 20));
    std::free(p);
  }
  auto scope = std::make_unique<BufferRecycling>();
  constexpr size_t MiB = size_t{1} << 20;
  void* big = std::aligned_alloc(kHugePageBytes, 8 * MiB);
  void* small = std::aligned_alloc(kHugePageBytes, 4 * MiB);
  ASSERT_TRUE(big && small);
  EXPECT_EQ(take_recycled_buffer(2 * MiB), nullptr);
  EXPECT_TRUE(keep_recycled_buffer(small, 4 * MiB));
  EXPECT_TRUE(keep_recycled_buffer(big, 8 * MiB));  // frees `small`
  EXPECT_EQ(take_recycled_buffer(10 * MiB), nullptr);
  EXPECT_EQ(take_recycled_buffer(6 * MiB), big);  // the 2 MiB beyond are given back
  EXPECT_EQ(take_recycled_buffer(2 * MiB), nullptr);
  static_cast<char*>(big)[6 * MiB - 1] = 1;  // still ours
  EXPECT_TRUE(keep_recycled_buffer(big, 6 * MiB));
  void* other = std::aligned_alloc(kHugePageBytes, 4 * MiB);
  ASSERT_TRUE(other);
  EXPECT_FALSE(keep_recycled_buffer(other, 4 * MiB));  // smaller than the kept one: the caller frees it
  std::free(other);
  release_recycled_buffer();
  EXPECT_EQ(take_recycled_buffer(2 * MiB), nullptr);

  // Through HugePageVector: a freed vector's buffer serves the next.
  const char* first = nullptr;
  {
    HugePageVector<char> a(12 * MiB);
    a[12 * MiB - 1] = 7;
    first = a.data();
  }
  HugePageVector<char> b(10 * MiB);
  EXPECT_EQ(b.data(), first);
  b[10 * MiB - 1] = 3;
  b = HugePageVector<char>();  // freed: kept
  scope.reset();               // the last scope releases it
  EXPECT_EQ(take_recycled_buffer(2 * MiB), nullptr);
}

}  // namespace
}  // namespace glint
