// Cylinders, cones and disks (docs/scene-format.md, objects): hits and
// normals computed here from the shapes' equations, from outside and inside,
// caps on and off, rays through the rim, annuli, non-uniform scales, the BVH
// against brute force, both backends, and a render checked against the
// shading formula.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glint/accel/accelerator.h"
#include "glint/geometry/shapes.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/integrator.h"
#include "glint/render/renderer.h"
#include "glint/render/texture.h"

namespace glint {
namespace {

constexpr double kTol = 1e-12;

void expect_vec(const Vec3& got, const Vec3& want, double tol, const char* what = "") {
  EXPECT_NEAR(got.x, want.x, tol) << what;
  EXPECT_NEAR(got.y, want.y, tol) << what;
  EXPECT_NEAR(got.z, want.z, tol) << what;
}

// One object in a scene, and what a ray finds on it.
struct Probe {
  Scene scene;
  std::optional<Hit> hit;
  SurfacePoint sp;
  bool trace(const Ray& ray) {
    const auto accel = build_brute_force(scene);
    hit = accel->intersect(ray);
    if (hit) sp = evaluate_hit(scene, ray, *hit);
    return hit.has_value();
  }
};

Probe cylinder_probe(bool caps, const std::optional<Transform>& xf = std::nullopt) {
  Probe p;
  add_cone(p.scene, make_cone({0, 0, 0}, {0, 2, 0}, 1, 1, caps), 0, xf, true);
  return p;
}

TEST(Cylinder, SideFromOutsideAndInside) {
  Probe p = cylinder_probe(true);
  ASSERT_TRUE(p.trace({{0, 1, 5}, {0, 0, -1}}));
  EXPECT_NEAR(p.hit->t, 4.0, kTol);
  EXPECT_EQ(p.hit->face, kConeSide);
  expect_vec(p.sp.p, {0, 1, 1}, kTol);
  expect_vec(p.sp.geometric_normal, {0, 0, 1}, kTol);
  // From the axis: the far side, whose outward normal points along the ray.
  ASSERT_TRUE(p.trace({{0, 1, 0}, {0.6, 0, -0.8}}));
  EXPECT_NEAR(p.hit->t, 1.0, kTol);
  expect_vec(p.sp.geometric_normal, {0.6, 0, -0.8}, kTol);
  // An oblique ray: |o + t d| across the axis = 1, solved here.
  const Vec3 o{3, 0.5, 1}, d{-1, 0.2, -0.1};
  const double a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z - 1;
  const double t = (-b - std::sqrt(b * b - a * c)) / a;
  ASSERT_TRUE(p.trace({o, d}));
  EXPECT_NEAR(p.hit->t, t, kTol);
  const Vec3 q = o + t * d;
  expect_vec(p.sp.geometric_normal, normalize({q.x, 0, q.z}), 1e-12);
}

TEST(Cylinder, CapsPointAwayFromTheSolidAndCanBeLeftOff) {
  Probe p = cylinder_probe(true);
  ASSERT_TRUE(p.trace({{0.5, 5, 0}, {0, -1, 0}}));
  EXPECT_NEAR(p.hit->t, 3.0, kTol);
  EXPECT_EQ(p.hit->face, kConeApexCap);
  expect_vec(p.sp.geometric_normal, {0, 1, 0}, 0);  // apex cap: base -> apex
  ASSERT_TRUE(p.trace({{0.5, -3, 0.2}, {0, 1, 0}}));
  EXPECT_NEAR(p.hit->t, 3.0, kTol);
  EXPECT_EQ(p.hit->face, kConeBaseCap);
  expect_vec(p.sp.geometric_normal, {0, -1, 0}, 0);  // base cap: the opposite
  // From inside, the cap ahead is still the outward normal.
  ASSERT_TRUE(p.trace({{0.2, 1, 0}, {0, 1, 0}}));
  EXPECT_NEAR(p.hit->t, 1.0, kTol);
  expect_vec(p.sp.geometric_normal, {0, 1, 0}, 0);

  Probe open = cylinder_probe(false);
  EXPECT_FALSE(open.trace({{0.5, 5, 0}, {0, -1, 0}}));  // straight down the open tube
  // A slanted ray through the open top meets the inside of the wall.
  ASSERT_TRUE(open.trace({{0, 3, 0}, {1, -2, 0}}));
  EXPECT_NEAR(open.hit->t, 1.0, kTol);
  expect_vec(open.sp.p, {1, 1, 0}, 1e-12);
  expect_vec(open.sp.geometric_normal, {1, 0, 0}, 1e-12);
  // Open: a ray through the top and out the bottom, missing the wall, hits nothing.
  EXPECT_FALSE(open.trace({{0.1, 3, 0}, {0.1, -1, 0}}));
}

TEST(Cylinder, RespectsTheOpenInterval) {
  Probe p = cylinder_probe(true);
  Ray r{{0, 1, 5}, {0, 0, -1}};
  r.t_max = 4.0;  // exactly the hit: outside the open interval
  EXPECT_FALSE(p.trace(r));
  r.t_max = 5.5;
  r.t_min = 4.0;  // the first hit excluded: the far side at 6 is out of range too
  EXPECT_FALSE(p.trace(r));
  r.t_max = 7;
  ASSERT_TRUE(p.trace(r));
  EXPECT_NEAR(p.hit->t, 6.0, kTol);
}

TEST(Cylinder, GrazingRays) {
  Probe p = cylinder_probe(true);
  // Tangent to the side: the touching point, or nothing, never a wild t.
  if (p.trace({{1, 1, 5}, {0, 0, -1}})) {
    EXPECT_NEAR(p.hit->t, 5.0, 1e-6);
  }
  EXPECT_FALSE(p.trace({{1 + 1e-9, 1, 5}, {0, 0, -1}}));
  ASSERT_TRUE(p.trace({{1 - 1e-9, 1, 5}, {0, 0, -1}}));
  EXPECT_NEAR(p.hit->t, 5.0 - std::sqrt(1 - (1 - 1e-9) * (1 - 1e-9)), 1e-12);
  // Along the side, just outside and just inside the wall: the caps decide.
  EXPECT_FALSE(p.trace({{1 + 1e-12, 5, 0}, {0, -1, 0}}));
  ASSERT_TRUE(p.trace({{1 - 1e-12, 5, 0}, {0, -1, 0}}));
  EXPECT_EQ(p.hit->face, kConeApexCap);
  // A far camera (1e6 away) still gets the hit to 1e-9.
  ASSERT_TRUE(p.trace({{0.3, 1, 1e6}, {0, 0, -1}}));
  EXPECT_NEAR(p.hit->t, 1e6 - std::sqrt(1 - 0.09), 1e-9);
}

// Rays aimed at points of the rim where side and cap meet, from the outside
// corner (above the cap and outside the side): each must enter the solid
// there, through the side or the cap, never through a crack between them.
TEST(Cylinder, RaysThroughTheRimAlwaysHit) {
  Rng rng(7);
  for (const bool apex_end : {true, false}) {
    Probe p;
    const Vec3 base{0.3, -1.1, 0.7}, apex{1.3, 2.9, -0.4};
    add_cone(p.scene, make_cone(base, apex, 0.8, 0.8, true), 0, std::nullopt, true);
    const Cone& c = p.scene.cones[0];
    const Vec3 w = cross(c.axis, c.ref_u);
    const auto accel = build_brute_force(p.scene);
    int misses = 0;
    for (int i = 0; i < 20000; ++i) {
      const double phi = 2 * std::numbers::pi * rng.next_double();
      const Vec3 out = std::cos(phi) * c.ref_u + std::sin(phi) * w;
      const Vec3 rim = (apex_end ? apex : base) + 0.8 * out;
      const Vec3 along = apex_end ? c.axis : -c.axis;
      const Vec3 from = rim + (0.05 + 3 * rng.next_double()) * out + (0.05 + 3 * rng.next_double()) * along;
      const auto h = accel->intersect({from, rim - from});
      if (!h) {
        ++misses;
        continue;
      }
      EXPECT_NEAR(h->t, 1.0, 1e-9);
    }
    EXPECT_EQ(misses, 0) << (apex_end ? "apex" : "base") << " rim";
  }
}

TEST(Cone, SideNormalIsTheQuadricsOutwardNormal) {
  Probe p;
  // Radius 1 at y = 0 narrowing to 0.5 at y = 2: r(y) = 1 - y/4.
  add_cone(p.scene, make_cone({0, 0, 0}, {0, 2, 0}, 1, 0.5, true));
  ASSERT_TRUE(p.trace({{5, 1, 0}, {-1, 0, 0}}));
  EXPECT_NEAR(p.hit->t, 5 - 0.75, kTol);
  expect_vec(p.sp.geometric_normal, normalize({1, 0.25, 0}), 1e-12);
  // From inside, toward the side at 45 degrees in x-z.
  ASSERT_TRUE(p.trace({{0, 1, 0}, {1, 0, 1}}));
  EXPECT_NEAR(p.hit->t, 0.75 / std::sqrt(2.0), kTol);
  expect_vec(p.sp.geometric_normal, normalize({1 / std::sqrt(2.0), 0.25, 1 / std::sqrt(2.0)}), 1e-12);
  // Caps: radius 0.5 on top, 1 at the bottom.
  ASSERT_TRUE(p.trace({{0.45, 4, 0}, {0, -1, 0}}));
  EXPECT_EQ(p.hit->face, kConeApexCap);
  EXPECT_NEAR(p.hit->t, 2.0, kTol);
  // Just outside the top cap's radius the ray meets the sloping side below it.
  ASSERT_TRUE(p.trace({{0.55, 4, 0}, {0, -1, 0}}));
  EXPECT_EQ(p.hit->face, kConeSide);
  EXPECT_NEAR(p.hit->t, 4 - 4 * (1 - 0.55), kTol);  // y = 4 (1 - x)
}

TEST(Cone, PointedConeAndItsInside) {
  Probe p;
  // A pointed cone standing on its base: r(y) = 1 - y/2, no apex cap.
  add_cone(p.scene, make_cone({0, 0, 0}, {0, 2, 0}, 1, 0, true));
  ASSERT_TRUE(p.trace({{0.25, 5, 0}, {0, -1, 0}}));
  EXPECT_NEAR(p.hit->t, 5 - 1.5, kTol);  // y = 2 (1 - x)
  EXPECT_EQ(p.hit->face, kConeSide);
  expect_vec(p.sp.geometric_normal, normalize({1, 0.5, 0}), 1e-12);
  // Above the apex along the second nappe's region: nothing there.
  EXPECT_FALSE(p.trace({{5, 4, 0}, {-1, 0, 0}}));
  // From inside looking down: the base cap, normal -y.
  ASSERT_TRUE(p.trace({{0.1, 0.5, 0}, {0, -1, 0}}));
  EXPECT_EQ(p.hit->face, kConeBaseCap);
  expect_vec(p.sp.geometric_normal, {0, -1, 0}, 0);
  // Upside down (apex below base) and open: rays up the inside meet the wall.
  Probe q;
  add_cone(q.scene, make_cone({0, 2, 0}, {0, 0, 0}, 1, 0, false));
  ASSERT_TRUE(q.trace({{0.5, 5, 0}, {0, -1, 0}}));
  EXPECT_NEAR(q.hit->t, 5 - 1.0, kTol);  // the wall at x = y / 2
  expect_vec(q.sp.geometric_normal, normalize({1, -0.5, 0}), 1e-12);
}

TEST(Cone, RaysThroughTheRimAlwaysHit) {
  Rng rng(11);
  Probe p;
  const Vec3 base{0, 0, 0}, apex{0.4, 1.7, 0.2};
  add_cone(p.scene, make_cone(base, apex, 1.2, 0.3, true));
  const Cone& c = p.scene.cones[0];
  const Vec3 w = cross(c.axis, c.ref_u);
  const double k = (c.apex_radius - c.base_radius) / c.length;
  const auto accel = build_brute_force(p.scene);
  int misses = 0;
  for (int i = 0; i < 20000; ++i) {
    const bool apex_end = i % 2 == 0;
    const double phi = 2 * std::numbers::pi * rng.next_double();
    const Vec3 out = std::cos(phi) * c.ref_u + std::sin(phi) * w;
    const Vec3 rim = (apex_end ? apex : base) + (apex_end ? 0.3 : 1.2) * out;
    // From outside, in a direction that enters the solid through the rim:
    // against both the side's and the cap's outward normals.
    const Vec3 side_n = normalize(out - k * c.axis);
    const Vec3 cap_n = apex_end ? c.axis : -c.axis;
    const Vec3 dir = -(rng.next_double() * side_n + rng.next_double() * cap_n);
    if (!(dot(dir, side_n) < -0.01 && dot(dir, cap_n) < -0.01)) continue;
    const Vec3 from = rim - (0.1 + 3 * rng.next_double()) * dir;
    const auto h = accel->intersect({from, rim - from});
    if (!h) {
      ++misses;
      continue;
    }
    EXPECT_NEAR(h->t, 1.0, 1e-9);
  }
  EXPECT_EQ(misses, 0);
}

TEST(Disk, AnnulusAndItsNormal) {
  Probe p;
  add_disk(p.scene, Disk{{0, 1, 0}, {0, 1, 0}, 2, 1});
  ASSERT_TRUE(p.trace({{1.5, 3, 0}, {0, -1, 0}}));
  EXPECT_NEAR(p.hit->t, 2, kTol);
  expect_vec(p.sp.geometric_normal, {0, 1, 0}, 0);
  ASSERT_TRUE(p.trace({{0, -1, 1.5}, {0, 1, 0}}));  // from below: still its `normal`
  expect_vec(p.sp.geometric_normal, {0, 1, 0}, 0);
  EXPECT_FALSE(p.trace({{0.5, 3, 0}, {0, -1, 0}}));  // the hole
  EXPECT_FALSE(p.trace({{2.5, 3, 0}, {0, -1, 0}}));  // outside
  EXPECT_FALSE(p.trace({{1.5, 3, 0}, {1, 0, 0}}));   // parallel
  ASSERT_TRUE(p.trace({{0, 3, 0}, {1, -1, 0}}));     // slanted, lands at x = 2 (the edge)
  EXPECT_NEAR(p.hit->t, 2, kTol);
  // A tilted full disk: the hit where the plane is, within the radius.
  Probe q;
  const Vec3 n = normalize({1, 2, 3});
  add_disk(q.scene, Disk{{1, 1, 1}, n, 0.5, 0});
  ASSERT_TRUE(q.trace({Vec3(1, 1, 1) + 4.0 * n, -n}));
  EXPECT_NEAR(q.hit->t, 4, kTol);
  expect_vec(q.sp.geometric_normal, n, 1e-15);
}

TEST(Transforms, NonUniformScaleOfACylinder) {
  // Radius 1 scaled by (2, 1, 0.5): x^2/4 + 4 z^2 = 1 across, y from 0 to 2.
  Probe p = cylinder_probe(true, Transform::scale({2, 1, 0.5}));
  ASSERT_TRUE(p.trace({{5, 1, 0}, {-1, 0, 0}}));
  EXPECT_NEAR(p.hit->t, 3, kTol);
  expect_vec(p.sp.geometric_normal, {1, 0, 0}, 1e-12);
  ASSERT_TRUE(p.trace({{0, 1, 5}, {0, 0, -1}}));
  EXPECT_NEAR(p.hit->t, 4.5, kTol);
  // At (2 cos f, y, 0.5 sin f) the normal is the gradient (x/2, 0, 8 z), i.e. (cos f, 0, 4 sin f).
  for (double f : {0.3, 1.1, 2.5, 4.0}) {
    const Vec3 q{2 * std::cos(f), 0.7, 0.5 * std::sin(f)};
    const Vec3 want = normalize({std::cos(f), 0, 4 * std::sin(f)});
    ASSERT_TRUE(p.trace({q + 3.0 * want, -want}));
    EXPECT_NEAR(p.hit->t, 3, 1e-12);
    expect_vec(p.sp.p, q, 1e-12);
    expect_vec(p.sp.geometric_normal, want, 1e-12);
  }
  // The cap under a rotation and scale: its normal is the transformed axis.
  const Transform xf = compose(Transform::rotate({0, 0, 1}, 90), Transform::scale({1, 3, 1}));
  Probe r = cylinder_probe(true, xf);  // now along -x, from 0 to -6
  ASSERT_TRUE(r.trace({{-10, 0.5, 0}, {1, 0, 0}}));
  EXPECT_NEAR(r.hit->t, 4, kTol);
  EXPECT_EQ(r.hit->face, kConeApexCap);
  expect_vec(r.sp.geometric_normal, {-1, 0, 0}, 1e-12);
}

TEST(Transforms, ScaledDiskIsAnEllipse) {
  Probe p;
  add_disk(p.scene, Disk{{0, 0, 0}, {0, 0, 1}, 1, 0}, 0, Transform::scale({3, 1, 1}));
  ASSERT_TRUE(p.trace({{2.9, 0, 5}, {0, 0, -1}}));
  expect_vec(p.sp.geometric_normal, {0, 0, 1}, 0);
  EXPECT_FALSE(p.trace({{0, 1.1, 5}, {0, 0, -1}}));
}

// Many random shapes with random transforms: our BVH finds exactly the
// brute-force hits.
Scene random_shapes(uint64_t seed, int count) {
  Rng rng(seed);
  Scene scene;
  const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * rng.next_double(); };
  const auto point = [&](double s) { return Vec3(uniform(-s, s), uniform(-s, s), uniform(-s, s)); };
  for (int i = 0; i < count; ++i) {
    std::optional<Transform> xf;
    if (i % 3 == 0)
      xf = compose(Transform::translate(point(1)),
                   compose(Transform::rotate(normalize(point(1) + Vec3(0.01)), uniform(0, 360)),
                           Transform::scale({uniform(0.3, 2), uniform(0.3, 2), uniform(0.3, 2)})));
    const Vec3 c = point(10);
    switch (i % 4) {
      case 0:
        add_cone(scene, make_cone(c, c + point(2), uniform(0.1, 1), uniform(0.1, 1), i % 8 == 0), 0, xf, false);
        break;
      case 1: add_cone(scene, make_cone(c, c + point(2), 0.5, 0.5, i % 8 != 1), 0, xf, true); break;
      case 2: add_disk(scene, Disk{c, normalize(point(1) + Vec3(0.01)), 1, i % 8 == 2 ? 0.5 : 0}, 0, xf); break;
      case 3: add_cone(scene, make_cone(c, c + point(2), 0, uniform(0.2, 1), true), 0, xf, false); break;
    }
  }
  return scene;
}

TEST(QuadricBvh, SameHitsAsBruteForce) {
  const Scene scene = random_shapes(3, 400);
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  Rng rng(5);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 o{rng.next_double() * 30 - 15, rng.next_double() * 30 - 15, rng.next_double() * 30 - 15};
    const Vec3 d{rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5};
    const Ray ray{o, d};
    const auto a = bvh->intersect(ray), b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << i;
    if (a) {
      ++hits;
      EXPECT_EQ(a->object, b->object);
      EXPECT_EQ(a->t, b->t);
      EXPECT_EQ(a->face, b->face);
    }
    EXPECT_EQ(bvh->occluded(ray), brute->occluded(ray));
  }
  EXPECT_GT(hits, 1000);  // the test means something
}

TEST(QuadricBackends, EmbreeFindsTheSameHits) {
  if (!embree_available()) GTEST_SKIP() << "glint was built without Embree";
  const Scene scene = random_shapes(9, 300);
  const auto embree = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::embree});
  const auto brute = build_brute_force(scene);
  Rng rng(13);
  int differ = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 o{rng.next_double() * 30 - 15, rng.next_double() * 30 - 15, rng.next_double() * 30 - 15};
    const Ray ray{o, {rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5}};
    const auto a = embree->intersect(ray), b = brute->intersect(ray);
    if (a.has_value() != b.has_value() || (a && (a->object != b->object || std::abs(a->t - b->t) > 1e-9))) ++differ;
    EXPECT_EQ(embree->occluded(ray), brute->occluded(ray));
  }
  EXPECT_EQ(differ, 0);
}

// The figure of the new shapes (glass, shadows, caps, polygons) renders the
// same with Embree as with our BVH: both run the same double tests.
TEST(QuadricBackends, SameImageForTheFigure) {
  if (!embree_available()) GTEST_SKIP() << "glint was built without Embree";
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/figures/quadrics.json");
  scene.render.width = 320;
  scene.render.height = 180;
  const auto ours = build_accelerator(scene, AcceleratorOptions{2, AccelBackend::bvh});
  const auto embree = build_accelerator(scene, AcceleratorOptions{2, AccelBackend::embree});
  RenderOptions options;
  options.threads = 2;
  const Image a = render_image(scene, *ours, options);
  const Image b = render_image(scene, *embree, options);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) differ += std::abs(a.rgb[i] - b.rgb[i]) > 1e-5f;
  EXPECT_EQ(differ, 0u);
}

// u around the axis from ref_u (right-hand rule), v along it; disks and caps
// cover the unit square of their plane frame.
TEST(QuadricUv, AroundAndAlongTheAxis) {
  Scene scene;
  add_cone(scene, make_cone({0, 0, 0}, {0, 4, 0}, 1, 1, true), 0, std::nullopt, true);
  add_disk(scene, Disk{{0, 0, 0}, {0, 1, 0}, 2, 0});
  Hit side;
  side.object = 0;
  side.face = kConeSide;
  // ref_u is +x for a +y axis; a quarter turn by the right-hand rule about +y is -z.
  UV uv = surface_uv(scene, side, {1, 1, 0});
  EXPECT_NEAR(uv.u, 0, kTol);
  EXPECT_NEAR(uv.v, 0.25, kTol);
  uv = surface_uv(scene, side, {0, 3, -1});
  EXPECT_NEAR(uv.u, 0.25, kTol);
  EXPECT_NEAR(uv.v, 0.75, kTol);
  uv = surface_uv(scene, side, {0, 2, 1});
  EXPECT_NEAR(uv.u, 0.75, kTol);
  Hit disk;
  disk.object = 1;
  // A floor's plane frame: e_u = +x, e_v = -z; the square of side 4 around the center.
  uv = surface_uv(scene, disk, {1, 0, -2});
  EXPECT_NEAR(uv.u, 0.75, kTol);
  EXPECT_NEAR(uv.v, 1.0, kTol);
  Hit cap = side;
  cap.face = kConeApexCap;
  uv = surface_uv(scene, cap, {-1, 4, 0});
  EXPECT_NEAR(uv.u, 0, kTol);
  EXPECT_NEAR(uv.v, 0.5, kTol);
}

// A cylinder seen head-on by an orthographic camera, lit by a directional
// light: each pixel's value from the shading formula, with the hit and the
// normal of the test's own x^2 + z^2 = r^2.
TEST(QuadricRender, PixelsFollowTheFormula) {
  Scene scene;
  scene.render.width = 40;
  scene.render.height = 20;
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 0, 10};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.view_height = 2;  // 0.1 per pixel: x from -2 to 2, y from -1 to 1
  Material m;
  m.ambient = {0.1, 0.1, 0.1};
  m.diffuse = {0.6, 0.4, 0.2};
  m.specular = {0.5, 0.5, 0.5};
  m.shininess = 10;
  const uint32_t mat = add_material(scene, m);
  add_cone(scene, make_cone({0, -5, 0}, {0, 5, 0}, 1.5, 1.5, true), mat, std::nullopt, true);
  Light sun;
  sun.type = LightType::directional;
  sun.direction = normalize({-1, -0.5, -1});
  sun.ambient = Color(0.5);
  scene.lights.push_back(sun);
  const auto accel = build_accelerator(scene);
  const Image image = render_image(scene, *accel);
  for (int i = 0; i < 40; ++i) {
    const double x = -2 + (i + 0.5) * 0.1, y = 1 - 5.5 * 0.1;
    const float* px = image.pixel(i, 5);
    if (std::abs(x) > 1.5) {
      EXPECT_EQ(px[0], 0.0f) << i;
      continue;
    }
    const double z = std::sqrt(1.5 * 1.5 - x * x);
    const Vec3 n = Vec3(x, 0, z) / 1.5, l = -sun.direction, v{0, 0, 1};
    (void)y;
    Color want = m.ambient * sun.ambient;
    const double ndl = dot(n, l);
    if (ndl > 0) {
      const Vec3 r = 2 * ndl * n - l;
      want += m.diffuse * ndl + m.specular * std::pow(std::max(0.0, dot(r, v)), m.shininess);
    }
    EXPECT_NEAR(px[0], want.x, 1e-5) << i;
    EXPECT_NEAR(px[1], want.y, 1e-5) << i;
    EXPECT_NEAR(px[2], want.z, 1e-5) << i;
  }
}

}  // namespace
}  // namespace glint
