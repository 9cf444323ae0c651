// The torus and CSG solids of the contract's "beyond the seed" section: the
// torus's crossings against a brute-force march of its implicit function,
// CSG's operations against the sets they describe (coincident faces, a
// camera inside, nesting with transforms at every level), shading on both
// through the formula, and the loader's refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/geometry/csg.h"
#include "glint/geometry/torus.h"
#include "glint/image/image.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

// (|q|^2 + R^2 - r^2)^2 - 4 R^2 |q across the axis|^2: negative inside.
double implicit(const Torus& t, const Vec3& p) {
  const Vec3 q = p - t.center;
  const double h = dot(q, t.axis);
  const double qq = dot(q, q);
  const double a = qq + t.major_radius * t.major_radius - t.minor_radius * t.minor_radius;
  return a * a - 4 * t.major_radius * t.major_radius * (qq - h * h);
}

// The crossings a fine march along the ray finds (sign changes, then bisection).
std::vector<double> march(const Torus& t, const Ray& ray, double t0, double t1, int steps) {
  std::vector<double> out;
  double prev_t = t0, prev = implicit(t, ray.at(t0));
  for (int i = 1; i <= steps; ++i) {
    const double x = t0 + (t1 - t0) * i / steps;
    const double v = implicit(t, ray.at(x));
    if ((v < 0) != (prev < 0)) {
      double lo = prev_t, hi = x;
      for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        ((implicit(t, ray.at(mid)) < 0) == (prev < 0) ? lo : hi) = mid;
      }
      out.push_back(0.5 * (lo + hi));
    }
    prev_t = x;
    prev = v;
  }
  return out;
}

Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(2 * rng.next_double() - 1, 2 * rng.next_double() - 1, 2 * rng.next_double() - 1);
    const double l = length(v);
    if (l > 0.1 && l < 1) return v / l;
  }
}

TEST(Torus, CrossingsAgreeWithABruteForceMarch) {
  Rng rng(7);
  int compared = 0;
  for (int k = 0; k < 400; ++k) {
    Torus t;
    t.center = Vec3(rng.next_double(), rng.next_double(), rng.next_double()) * 4.0 - Vec3(2.0);
    t.axis = random_unit(rng);
    t.major_radius = 0.5 + 2 * rng.next_double();
    t.minor_radius = t.major_radius * (0.05 + 0.9 * rng.next_double());
    // From far or near, aimed at a point near the torus.
    const double far = k % 4 == 0 ? 1e3 : 10;
    const Vec3 target = t.center + random_unit(rng) * (t.major_radius * rng.next_double() * 1.2);
    Ray ray;
    ray.origin = target + random_unit(rng) * far;
    ray.direction = (target - ray.origin) * (0.5 + rng.next_double());  // not unit length
    double got[4];
    const int n = torus_crossings(t, ray, got);
    EXPECT_EQ(n % 2, 0);
    const double scale = (t.major_radius + t.minor_radius) / length(ray.direction);
    const double mid = dot(t.center - ray.origin, ray.direction) / dot(ray.direction, ray.direction);
    const std::vector<double> want = march(t, ray, mid - 2 * scale, mid + 2 * scale, 20000);
    // Where the march sees crossings clearly apart, the counts and values agree.
    bool clear = true;
    for (size_t i = 1; i < want.size(); ++i) clear = clear && want[i] - want[i - 1] > 1e-3 * scale;
    if (!clear) continue;
    ASSERT_EQ(static_cast<size_t>(n), want.size()) << "torus " << k;
    for (int i = 0; i < n; ++i) EXPECT_NEAR(got[i], want[static_cast<size_t>(i)], 1e-9 * (std::abs(mid) + scale));
    ++compared;
  }
  EXPECT_GT(compared, 300);
}

TEST(Torus, KnownCrossingsAxisHoleAndNormal) {
  const Torus t{{1, 2, 3}, {0, 1, 0}, 2, 0.5};
  // Along the plane through the center: +-(R + r), +-(R - r) from it.
  const Ray across{{1 - 10, 2, 3}, {1, 0, 0}};
  double c[4];
  ASSERT_EQ(torus_crossings(t, across, c), 4);
  const double want[4] = {10 - 2.5, 10 - 1.5, 10 + 1.5, 10 + 2.5};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(c[i], want[i], 1e-12);
  // Half as long a direction: twice the t.
  const Ray half{{1 - 10, 2, 3}, {0.5, 0, 0}};
  ASSERT_EQ(torus_crossings(t, half, c), 4);
  EXPECT_NEAR(c[0], 15, 1e-12);
  // Down the axis, through the hole.
  EXPECT_EQ(torus_crossings(t, Ray{{1, 12, 3}, {0, -1, 0}}, c), 0);
  // t_min / t_max: from inside the tube, the exit.
  const Ray inside{{1 + 2, 2, 3}, {1, 0, 0}, 0, kInfinity};
  EXPECT_NEAR(*intersect_torus(t, inside), 0.5, 1e-12);
  const Ray short_ray{{1 + 2, 2, 3}, {1, 0, 0}, 0, 0.4};
  EXPECT_FALSE(intersect_torus(t, short_ray));
  // Normals: from the nearest point of the center circle.
  const Vec3 n_out = torus_normal(t, {1 + 2.5, 2, 3});
  EXPECT_NEAR(n_out.x, 1, 1e-12);
  const Vec3 n_top = torus_normal(t, {1, 2.5, 3 + 2});
  EXPECT_NEAR(n_top.y, 1, 1e-12);
  const Vec3 n_in = torus_normal(t, {1 - 1.5, 2, 3});
  EXPECT_NEAR(n_in.x, 1, 1e-12);  // the inner equator faces the axis
}

TEST(Torus, GrazingRaysFindTheTopOfTheTube) {
  // Rays just above and below the tube's top line: in at most 1e-9 above
  // it they cross, or not, but never an odd count, and the rays below
  // cross near the top.
  const Torus t{{0, 0, 0}, {0, 1, 0}, 1, 0.25};
  for (int k = -20; k <= 20; ++k) {
    const double y = 0.25 + k * 1e-7;
    double c[4];
    const int n = torus_crossings(t, Ray{{-5, y, 0}, {1, 0, 0}}, c);
    EXPECT_EQ(n % 2, 0);
    if (y < 0.25 - 1e-12) {
      EXPECT_EQ(n, 4) << y;
      if (n == 4) {
        EXPECT_NEAR(c[0], 4, 1e-2);
      }
    }
    if (y > 0.25 + 1e-12) {
      EXPECT_EQ(n, 0) << y;
    }
  }
}

// --- CSG ------------------------------------------------------------------------

Scene scene_of(const std::string& objects, const std::string& extra = "") {
  return parse_scene(R"({"camera": {"position": [0, 0, 10], "look_at": [0, 0, 0]},
    "materials": {"a": {"diffuse": [1, 0, 0]}, "b": {"diffuse": [0, 1, 0]}, "c": {"diffuse": [0, 0, 1]}},)" +
                         extra + R"("objects": [)" + objects + "]}",
                     "scene.json");
}

struct Found {
  double t = -1;
  uint32_t leaf = 0;
  bool flip = false;
  bool hit = false;
};
Found first_hit(const Scene& scene, const Vec3& origin, const Vec3& direction) {
  const Csg& csg = scene.csgs.at(0);
  Ray ray{origin, direction};
  const auto h = intersect_csg(csg, ray);
  if (!h) return {};
  return {h->t, h->leaf, h->flip, true};
}

const char* kTwoSpheres = R"({"type": "sphere", "center": [-0.5, 0, 0], "radius": 1, "material": "a"},
                             {"type": "sphere", "center": [0.5, 0, 0], "radius": 1, "material": "b"})";

TEST(Csg, UnionIntersectionAndDifferenceOfTwoSpheres) {
  const auto csg = [](const char* op) {
    return scene_of(std::string(R"({"type": "csg", "operation": ")") + op + R"(", "children": [)" + kTwoSpheres + "]}");
  };
  const Vec3 from(-10, 0, 0), along(1, 0, 0);
  // Along the x axis: A = [-1.5, 0.5], B = [-0.5, 1.5] (as x; t = x + 10).
  Found u = first_hit(csg("union"), from, along);
  EXPECT_NEAR(u.t, 8.5, 1e-12);
  EXPECT_EQ(u.leaf, 0u);
  // From inside both, the union's only surface ahead is B's far side.
  u = first_hit(csg("union"), {0, 0, 0}, along);
  EXPECT_NEAR(u.t, 1.5, 1e-12);
  EXPECT_EQ(u.leaf, 1u);
  const Found i = first_hit(csg("intersection"), from, along);
  EXPECT_NEAR(i.t, 9.5, 1e-12);
  EXPECT_EQ(i.leaf, 1u);
  const Found d = first_hit(csg("difference"), {10, 0, 0}, -along);
  EXPECT_NEAR(d.t, 10.5, 1e-12);  // through the cutter's surface at x = -0.5
  EXPECT_EQ(d.leaf, 1u);
  EXPECT_TRUE(d.flip);
  // Away from the overlap, the difference is A itself.
  EXPECT_NEAR(first_hit(csg("difference"), from, along).t, 8.5, 1e-12);
}

TEST(Csg, ACutterSharingAFaceOpensItCleanly) {
  // A box minus a box that shares its top face: looking down into the pocket
  // the ray meets the pocket's floor (the cutter's bottom, turned up), not
  // the top face; beside the pocket, the top face.
  const Scene s = scene_of(R"({"type": "csg", "operation": "difference", "children": [
      {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "material": "a"},
      {"type": "box", "min": [-0.5, 0, -0.5], "max": [0.5, 1, 0.5], "material": "b"}]})");
  const Found pocket = first_hit(s, {0.1, 5, 0.2}, {0, -1, 0});
  EXPECT_NEAR(pocket.t, 5, 1e-12);
  EXPECT_EQ(pocket.leaf, 1u);
  EXPECT_TRUE(pocket.flip);
  const Found top = first_hit(s, {0.8, 5, 0.2}, {0, -1, 0});
  EXPECT_NEAR(top.t, 4, 1e-12);
  EXPECT_EQ(top.leaf, 0u);
  // Two boxes that touch, as a union, have no face where they meet.
  const Scene touching = scene_of(R"({"type": "csg", "operation": "union", "children": [
      {"type": "box", "min": [-1, -1, -1], "max": [0, 1, 1]},
      {"type": "box", "min": [0, -1, -1], "max": [1, 1, 1]}]})");
  EXPECT_NEAR(first_hit(touching, {-0.5, 0, 0}, {1, 0, 0}).t, 1.5, 1e-12);
}

TEST(Csg, NestedTransformsAtEveryLevelCompose) {
  // A nested union moved by both levels' transforms lands where the
  // composition puts it.
  const Scene s = scene_of(R"({"type": "csg", "operation": "union", "children": [
      {"type": "sphere", "center": [0, 0, -50], "radius": 0.1},
      {"type": "csg", "operation": "intersection", "transform": {"translate": [0, 2, 0]}, "children": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": {"scale": 2}},
        {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "transform": {"translate": [0.5, 0, 0]}}]}]})");
  // Along y = 2: the sphere (radius 2) clipped by the box [-0.5, 1.5] in x.
  const Found f = first_hit(s, {-10, 2, 0}, {1, 0, 0});
  EXPECT_NEAR(f.t, 9.5, 1e-12);
  EXPECT_EQ(f.leaf, 2u);
  const Found back = first_hit(s, {10, 2, 0}, {-1, 0, 0});
  EXPECT_NEAR(back.t, 8.5, 1e-12);
}

TEST(Csg, NonFiniteRaysEndTheirSweep) {
  // Non-finite directions: no solid gives a span, and nothing is hit. (A
  // NaN span end, which equals nothing, not even itself, still moves the
  // sweep on: each group of equal ends holds at least its first.)
  const Scene s = scene_of(std::string(R"({"type": "csg", "operation": "union", "children": [)") + kTwoSpheres + "]}");
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Vec3& d : {Vec3(nan, 0, 0), Vec3(inf, 0, 0), Vec3(0, 0, 0)}) {
    Ray ray{{-10, 0, 0}, d};
    EXPECT_FALSE(intersect_csg(s.csgs[0], ray));
  }
}

TEST(Csg, TorusChildAndClosedCylinderChild) {
  const Scene s = scene_of(R"({"type": "csg", "operation": "difference", "children": [
      {"type": "torus", "center": [0, 0, 0], "axis": [0, 1, 0], "major_radius": 2, "minor_radius": 0.5},
      {"type": "cylinder", "base": [0, -1, -3], "apex": [0, -1, 3], "radius": 1}]})");
  // The cylinder (axis z, at y = -1, radius 1) cuts the tube's lower half:
  // straight down at x = 2 the ray enters the torus at y = 0.5 and leaves
  // the result at the cylinder's top (y = 0).
  const Found f = first_hit(s, {2, 5, 0}, {0, -1, 0});
  EXPECT_NEAR(f.t, 4.5, 1e-9);
  EXPECT_EQ(f.leaf, 0u);
  const Found g = first_hit(s, {0, 5, 2}, {0, -1, 0});
  EXPECT_NEAR(g.t, 4.5, 1e-9);
  Ray inside{{0, 0.25, 2}, {0, -1, 0}};
  const auto exit = intersect_csg(s.csgs[0], inside);
  ASSERT_TRUE(exit);
  EXPECT_NEAR(exit->t, 0.25, 1e-9);  // the cylinder's top, y = 0
  EXPECT_EQ(exit->leaf, 1u);
}

Color pixel_of(const Scene& scene, int x, int y) {
  const auto accel = build_accelerator(scene);
  RenderOptions o;
  o.threads = 2;
  const Image image = render_image(scene, *accel, o);
  const float* p = image.pixel(x, y);
  return {p[0], p[1], p[2]};
}

TEST(Csg, ShadedWithTheChildsMaterialAndAnOutwardNormal) {
  // A camera looking down at the pocket floor of a difference: the floor is
  // the cutter's bottom face, its normal turned up (toward the light), with
  // the cutter's material: R_a L_a + R_d L_d (n.l) exactly.
  const Scene s = parse_scene(R"({"render": {"width": 3, "height": 3},
    "camera": {"position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 1},
    "materials": {"a": {"ambient": 0.1, "diffuse": [1, 0, 0], "specular": 0},
                  "b": {"ambient": 0.2, "diffuse": [0, 0.5, 0], "specular": 0}},
    "lights": [{"type": "ambient", "ambient": 1}, {"type": "directional", "direction": [0, -1, 0]}],
    "objects": [{"type": "csg", "operation": "difference", "material": "a", "children": [
      {"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1]},
      {"type": "box", "min": [-0.5, 0, -0.5], "max": [0.5, 2, 0.5], "material": "b"}]}]})",
                              "scene.json");
  const Color c = pixel_of(s, 1, 1);
  EXPECT_NEAR(c.x, 0.2, 1e-6);
  EXPECT_NEAR(c.y, 0.2 + 0.5, 1e-6);
  EXPECT_NEAR(c.z, 0.2, 1e-6);
}

TEST(Csg, TheCameraInsideASolidSeesItsInside) {
  // Inside a union of two spheres: every pixel hits, from the inside, the
  // far surface (its normal turned toward the camera: lit by a light at the
  // camera).
  const Scene s = parse_scene(R"({"render": {"width": 5, "height": 5},
    "camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov_y": 30},
    "materials": {"m": {"ambient": 0, "diffuse": 1, "specular": 0}},
    "lights": [{"type": "point", "position": [0, 0, 0]}],
    "objects": [{"type": "csg", "operation": "union", "material": "m", "children": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 2},
      {"type": "sphere", "center": [0, 0, -1], "radius": 2}]}]})",
                              "scene.json");
  // The center ray meets the second sphere's far side at z = -3 head on.
  const Color c = pixel_of(s, 2, 2);
  EXPECT_NEAR(c.x, 1.0, 1e-6);
}

TEST(Csg, ShadowsPassThroughAHoleCut) {
  // A slab with a hole cut through it, between a light above and a floor:
  // the floor under the hole is lit, beside it shadowed.
  const std::string text = R"({"render": {"width": 2, "height": 1},
    "camera": {"position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_y": 1},
    "materials": {"m": {"ambient": 0, "diffuse": 1, "specular": 0}},
    "lights": [{"type": "directional", "direction": [0, -1, 0]}],
    "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "m"},
      {"type": "csg", "operation": "difference", "transform": {"translate": [OFFSET, 0, 0]}, "children": [
        {"type": "box", "min": [-3, 1, -3], "max": [3, 1.2, 3]},
        {"type": "cylinder", "base": [0, 0, 0], "apex": [0, 2, 0], "radius": 0.5}]}]})";
  const auto with = [&](const char* offset) {
    std::string s = text;
    s.replace(s.find("OFFSET"), 6, offset);
    return pixel_of(parse_scene(s, "scene.json"), 0, 0).x;
  };
  EXPECT_NEAR(with("0"), 1.0, 1e-6);
  EXPECT_EQ(with("1.5"), 0.0f);
}

TEST(Csg, RefractionAndShadowsSeeOneSolid) {
  // A glass sphere united with a smaller sphere inside it is the sphere
  // alone: no face inside for refraction to bend at or a shadow to stop at.
  const auto scene = [](const std::string& object) {
    return parse_scene(R"({"render": {"width": 24, "height": 16, "max_depth": 8, "background": [0.2, 0.3, 0.4]},
      "camera": {"position": [0, 1, 5], "look_at": [0, 0.5, 0], "fov_y": 40},
      "materials": {"glass": {"ambient": 0, "diffuse": 0.05, "specular": 0.8, "transparency": 0.9, "ior": 1.5,
                              "fresnel": true},
                    "floor": {"diffuse": {"checker": {"even": 0.9, "odd": 0.1}}}},
      "lights": [{"type": "ambient", "ambient": 0.2}, {"type": "point", "position": [1, 5, 2]}],
      "objects": [{"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "floor"}, )" +
                           object + "]}",
                       "scene.json");
  };
  const Scene alone = scene(R"({"type": "sphere", "center": [0, 0.5, 0], "radius": 1, "material": "glass"})");
  const Scene united = scene(R"({"type": "csg", "operation": "union", "material": "glass", "children": [
      {"type": "sphere", "center": [0, 0.5, 0], "radius": 1},
      {"type": "sphere", "center": [0.2, 0.4, 0.1], "radius": 0.5}]})");
  RenderOptions o;
  o.threads = 2;
  const Image a = render_image(alone, *build_accelerator(alone), o);
  const Image b = render_image(united, *build_accelerator(united), o);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) EXPECT_NEAR(a.rgb[i], b.rgb[i], 1e-5) << i;
}

TEST(CsgLoader, Errors) {
  const auto error_of = [](const std::string& object) {
    try {
      scene_of(object);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(R"({"type": "csg", "operation": "union", "children": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1},
      {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})")
                .find("objects[0].children[1].type: a csg child must be a closed solid"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type": "csg", "operation": "union", "children": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1},
      {"type": "cylinder", "base": [0, 0, 0], "apex": [0, 1, 0], "radius": 1, "caps": false}]})")
                .find("\"caps\" cannot be false"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type": "csg", "operation": "union", "children": [
      {"type": "sphere", "center": [0, 0, 0], "radius": 1}]})")
                .find("two or more children"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type": "csg", "operation": "subtract", "children": []})").find("unknown CSG operation"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type": "torus", "center": [0, 0, 0], "axis": [0, 1, 0], "major_radius": 1,
      "minor_radius": 1})")
                .find("minor_radius: must be less than \"major_radius\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"type": "torus", "center": [0, 0, 0], "axis": [0, 0, 0], "major_radius": 1,
      "minor_radius": 0.5})")
                .find("axis: must be a non-zero vector"),
            std::string::npos);
  // Nesting beyond 64 levels.
  std::string deep = R"({"type": "sphere", "center": [0, 0, 0], "radius": 1})";
  for (int i = 0; i < 70; ++i)
    deep = R"({"type": "csg", "operation": "union", "children": [)" + deep +
           R"(, {"type": "sphere", "center": [0, 0, 0], "radius": 1}]})";
  EXPECT_NE(error_of(deep).find("nested more than 64 levels"), std::string::npos);
}

}  // namespace
}  // namespace glint
