// Polygons (docs/scene-format.md, objects): convex and non-convex ones hit
// exactly where the test's own point-in-polygon test says, no crack along
// the triangulation's inner edges, the geometric normal of the first three
// vertices, smooth normals on the fan, a 144-vertex gear printed to 6
// significant digits, and every loader error of the new object types with
// its message, JSON path and line:column.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/geometry/polygon.h"
#include "glint/geometry/shapes.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/integrator.h"
#include "glint/scene/animation.h"

namespace glint {
namespace {

constexpr const char* kFileName = "scene.json";

void expect_vec(const Vec3& got, const Vec3& want, double tol, const char* what = "") {
  EXPECT_NEAR(got.x, want.x, tol) << what;
  EXPECT_NEAR(got.y, want.y, tol) << what;
  EXPECT_NEAR(got.z, want.z, tol) << what;
}

Polygon build(std::vector<Vec3> vertices, std::vector<Vec3> normals = {}) {
  PolygonBuild b = make_polygon(std::move(vertices), std::move(normals));
  EXPECT_EQ(b.error, "");
  return b.polygon;
}

// Crossing number in the x-y plane (the test's own, independent of glint's).
bool inside_xy(const std::vector<Vec3>& v, double x, double y) {
  bool in = false;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if ((v[i].y > y) != (v[j].y > y) && x < (v[j].x - v[i].x) * (y - v[i].y) / (v[j].y - v[i].y) + v[i].x) in = !in;
  }
  return in;
}

// Distance from (x, y) to the nearest edge, in the x-y plane.
double edge_distance_xy(const std::vector<Vec3>& v, double x, double y) {
  double best = kInfinity;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    const double ex = v[i].x - v[j].x, ey = v[i].y - v[j].y;
    const double s = std::clamp(((x - v[j].x) * ex + (y - v[j].y) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    best = std::min(best, std::hypot(x - v[j].x - s * ex, y - v[j].y - s * ey));
  }
  return best;
}

// A gear outline: `teeth` teeth of 4 vertices each (root, tip, tip, root) in
// the plane z = z0, every coordinate printed with 6 significant digits as
// SPD's NFF files are.
std::vector<Vec3> gear(int teeth, double cx, double cy, double z0, double r_in, double r_out) {
  const auto six = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return std::strtod(buf, nullptr);
  };
  std::vector<Vec3> v;
  const double step = 2 * std::numbers::pi / teeth;
  for (int j = 0; j < teeth; ++j) {
    const double a = j * step;
    const double angles[4] = {a, a + 0.25 * step, a + 0.5 * step, a + 0.75 * step};
    const double radii[4] = {r_in, r_out, r_out, r_in};
    for (int k = 0; k < 4; ++k)
      v.push_back({six(cx + radii[k] * std::cos(angles[k])), six(cy + radii[k] * std::sin(angles[k])), six(z0)});
  }
  return v;
}

// Rays straight down onto the x-y plane polygon hit it exactly where
// inside_xy says (points within 1e-9 of an edge left out).
void expect_hits_match_inside(const std::vector<Vec3>& v, const Polygon& polygon, int rays, uint64_t seed) {
  Scene scene;
  add_polygon(scene, polygon);
  const Bounds3 b = scene.polygons[0].bounds;
  const auto accel = build_brute_force(scene);
  Rng rng(seed);
  int inside = 0;
  for (int i = 0; i < rays; ++i) {
    const double x = b.lo.x + (b.hi.x - b.lo.x) * rng.next_double();
    const double y = b.lo.y + (b.hi.y - b.lo.y) * rng.next_double();
    if (edge_distance_xy(v, x, y) < 1e-9) continue;
    const bool want = inside_xy(v, x, y);
    inside += want;
    const auto hit = accel->intersect({{x, y, v[0].z + 3}, {0, 0, -1}});
    ASSERT_EQ(hit.has_value(), want) << "at " << x << ", " << y;
    if (hit) {
      EXPECT_NEAR(hit->t, 3.0, 1e-12);
    }
  }
  EXPECT_GT(inside, rays / 10);
}

TEST(Polygon, ConvexPolygonIsAFan) {
  const std::vector<Vec3> v = {{0, 0, 0}, {2, 0, 0}, {3, 1, 0}, {2, 2, 0}, {0, 2, 0}};
  const Polygon p = build(v);
  ASSERT_EQ(p.triangles.size(), 3u);
  for (uint32_t i = 0; i < 3; ++i) EXPECT_EQ(p.triangles[i], (std::array<uint32_t, 3>{0, i + 1, i + 2}));
  expect_vec(p.normal, {0, 0, 1}, 0);
  expect_hits_match_inside(v, p, 3000, 1);
}

TEST(Polygon, NonConvexPolygonsHitOnlyInside) {
  // An L, a comb, and a star-shaped outline, each wound either way.
  const std::vector<std::vector<Vec3>> shapes = {
      {{0, 0, 1}, {3, 0, 1}, {3, 1, 1}, {1, 1, 1}, {1, 3, 1}, {0, 3, 1}},
      {{0, 0, 0},
       {5, 0, 0},
       {5, 3, 0},
       {4, 3, 0},
       {4, 1, 0},
       {3, 1, 0},
       {3, 3, 0},
       {2, 3, 0},
       {2, 1, 0},
       {1, 1, 0},
       {1, 3, 0},
       {0, 3, 0}},
  };
  std::vector<std::vector<Vec3>> all = shapes;
  std::vector<Vec3> star;
  for (int k = 0; k < 14; ++k) {
    const double a = k * std::numbers::pi / 7, r = k % 2 ? 0.4 : 1.0;
    star.push_back({r * std::cos(a), r * std::sin(a), -2});
  }
  all.push_back(star);
  for (size_t s = 0, n = all.size(); s < n; ++s) all.push_back({all[s].rbegin(), all[s].rend()});
  for (size_t s = 0; s < all.size(); ++s) {
    SCOPED_TRACE("shape " + std::to_string(s));
    const Polygon p = build(all[s]);
    EXPECT_EQ(p.triangles.size(), all[s].size() - 2);
    expect_hits_match_inside(all[s], p, 3000, 100 + s);
  }
}

TEST(Polygon, GeometricNormalIsThatOfTheFirstThreeVertices) {
  // The first three turn clockwise seen from +z (a reflex corner) although
  // the outline as a whole winds counterclockwise: the normal is still -z.
  const std::vector<Vec3> v = {{0, 2.5, 0}, {1, 1, 0}, {0, 2, 0}, {0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {0, 3, 0}};
  PolygonBuild b = make_polygon(v, {});
  ASSERT_EQ(b.error, "") << "shape";
  Scene scene;
  add_polygon(scene, b.polygon);
  const Ray ray{{2, 2, 4}, {0, 0, -1}};
  const auto hit = build_brute_force(scene)->intersect(ray);
  ASSERT_TRUE(hit);
  const SurfacePoint sp = evaluate_hit(scene, ray, *hit);
  expect_vec(sp.geometric_normal, {0, 0, -1}, 0);
  expect_vec(sp.p, {2, 2, 0}, 1e-15);
}

// Points on every inner edge of the triangulation (shared by two triangles),
// approached from many directions: no ray slips between the triangles.
TEST(Polygon, InnerEdgesHaveNoCrack) {
  const std::vector<Vec3> v = gear(36, 0.3, -0.2, 0.7, 0.8, 1.0);
  const Polygon p = build(v);
  Scene scene;
  add_polygon(scene, p);
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : p.triangles)
    for (int k = 0; k < 3; ++k) edges[std::minmax(t[k], t[(k + 1) % 3])]++;
  const auto accel = build_brute_force(scene);
  Rng rng(3);
  int inner = 0, misses = 0;
  for (const auto& [e, count] : edges) {
    if (count != 2) continue;
    ++inner;
    for (int i = 0; i < 20; ++i) {
      const double s = rng.next_double();
      const Vec3 q = v[e.first] + s * (v[e.second] - v[e.first]);
      const Vec3 d{rng.next_double() - 0.5, rng.next_double() - 0.5, -0.2 - rng.next_double()};
      misses += !accel->intersect({q - 3.0 * d, d}).has_value();
    }
  }
  EXPECT_EQ(inner, 141);  // 142 triangles of 144 vertices: 141 diagonals
  EXPECT_EQ(misses, 0);
}

TEST(Polygon, GearOf144VerticesAtSixDigitsIsAccepted) {
  for (const auto& [cx, cy, z] :
       std::vector<std::array<double, 3>>{{0, 0, 0}, {12.3457, -7.65432, 3.14159}, {-123.457, 456.789, -0.001234}}) {
    const std::vector<Vec3> v = gear(36, cx, cy, z, 2.1, 2.6);
    ASSERT_EQ(v.size(), 144u);
    const Polygon p = build(v);
    EXPECT_EQ(p.triangles.size(), 142u);
    expect_hits_match_inside(v, p, 2000, 7);
  }
  // The same gear standing in a y-z plane, through the loader (numbers as text).
  std::string text = R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": [
    {"type": "polygon", "vertices": [)";
  char buf[128];
  const std::vector<Vec3> v = gear(36, 1.23457, -2.34568, 9.87654, 0.9, 1.1);
  for (size_t i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s[%.6g, %.6g, %.6g]", i ? ", " : "", v[i].z, v[i].x, v[i].y);
    text += buf;
  }
  text += "]}]}";
  const Scene scene = parse_scene(text, "gear.json");
  ASSERT_EQ(scene.polygons.size(), 1u);
  EXPECT_EQ(scene.polygons[0].triangles.size(), 142u);
}

// The grid (PolygonGrid) only narrows which triangles are tested: every ray
// finds the hit, triangle and barycentrics that testing all of them in order
// finds -- rays from all directions, grazing ones, rays through vertices and
// along the triangulation's edges, and vertices up to 1e-5 of the diagonal
// off the plane (the planarity tolerance).
TEST(Polygon, GridFindsWhatEveryTriangleFinds) {
  Rng rng(29);
  int hits = 0, rays = 0;
  for (int shape = 0; shape < 6; ++shape) {
    std::vector<Vec3> v = gear(36, 1.5 * shape, -0.5, 0.25 * shape, 0.8, 1.0);
    // Tilted about x and y, and (for some) every vertex nudged off the plane.
    const Transform tilt =
        compose(Transform::rotate({1, 0, 0}, 17.0 * shape), Transform::rotate({0, 1, 0}, 29.0 * shape));
    for (size_t i = 0; i < v.size(); ++i) {
      v[i] = tilt.point(v[i]);
      if (shape % 2 && i > 2) v[i] += (0.9e-5 * 2.0 * (rng.next_double() - 0.5)) * Vec3(0.3, -0.4, 0.85);
    }
    const Polygon with = build(v);
    ASSERT_TRUE(with.grid);
    Polygon without = with;
    without.grid.reset();
    const Vec3 n = with.normal;
    const Bounds3 box = [&] {
      Bounds3 b;
      for (const Vec3& p : v) b.extend(p);
      return b;
    }();
    for (int i = 0; i < 4000; ++i) {
      // A target on the polygon's plane: inside its box, at a vertex, or on an edge of a triangle.
      Vec3 target;
      const int kind = i % 4;
      if (kind == 0) {
        target = box.lo + Vec3(rng.next_double(), rng.next_double(), rng.next_double()) * (box.hi - box.lo);
      } else {
        const auto& tri = with.triangles[static_cast<size_t>(rng.next_double() * with.triangles.size())];
        const Vec3 a = v[tri[0]], b = v[tri[1]];
        target = kind == 1 ? a : a + rng.next_double() * (b - a);
      }
      Vec3 d{rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5};
      if (i % 8 == 7) d = d - (dot(d, n) - 1e-3 * (rng.next_double() - 0.5)) * n;  // grazing
      const double back = 0.5 + 5 * rng.next_double();
      const Ray ray{target - back * d, d};
      ++rays;
      const auto a = intersect_polygon(with, ray), b = intersect_polygon(without, ray);
      ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << i << " of shape " << shape;
      if (!a) continue;
      ++hits;
      EXPECT_EQ(a->t, b->t);
      EXPECT_EQ(a->b1, b->b1);
      EXPECT_EQ(a->b2, b->b2);
      EXPECT_EQ(a->triangle, b->triangle);
    }
  }
  EXPECT_GT(hits, rays / 3);
}

TEST(Polygon, SmoothNormalsAreInterpolatedOnTheFan) {
  // A square; normals of different lengths (normalized first), under a non-uniform scale.
  const std::vector<Vec3> v = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}};
  const std::vector<Vec3> n = {normalize({0, 0, 1}), normalize({1, 0, 1}), normalize({1, 1, 2}), normalize({0, 1, 3})};
  for (const bool scaled : {false, true}) {
    SCOPED_TRACE(scaled ? "scaled" : "plain");
    Scene scene;
    const std::optional<Transform> xf = scaled ? std::optional<Transform>(Transform::scale({2, 1, 0.5})) : std::nullopt;
    add_polygon(scene, build(v, n), 0, xf);
    // Object-space point (1.5, 0.5): in the fan triangle (0, 1, 2) with
    // barycentrics (0.25, 0.5, 0.25); (0.5, 1.5): in (0, 2, 3) with (0.25, 0.25, 0.5).
    const auto expected = [&](double b0, int i1, double b1, int i2, double b2) {
      const auto t = [&](const Vec3& m) { return xf ? normalize(xf->normal(m)) : m; };
      return normalize(b0 * t(n[0]) + b1 * t(n[i1]) + b2 * t(n[i2]));
    };
    const auto trace = [&](const Vec3& obj) {
      const Vec3 p = xf ? xf->point(obj) : obj;
      const Ray ray{p + Vec3(0.1, 0.2, 2), {-0.1, -0.2, -2}};
      const auto hit = build_brute_force(scene)->intersect(ray);
      EXPECT_TRUE(hit);
      const SurfacePoint sp = evaluate_hit(scene, ray, *hit);
      expect_vec(sp.p, p, 1e-14);
      expect_vec(sp.geometric_normal, {0, 0, 1}, 1e-15);
      return sp.shading_normal;
    };
    expect_vec(trace({1.5, 0.5, 0}), expected(0.25, 1, 0.5, 2, 0.25), 1e-14, "first fan triangle");
    expect_vec(trace({0.5, 1.5, 0}), expected(0.25, 2, 0.25, 3, 0.5), 1e-14, "second fan triangle");
  }
}

TEST(Polygon, BvhAgreesWithBruteForce) {
  Scene scene;
  Rng rng(17);
  for (int i = 0; i < 120; ++i) {
    const double cx = rng.next_double() * 20 - 10, cy = rng.next_double() * 20 - 10, z = rng.next_double() * 20 - 10;
    std::optional<Transform> xf;
    if (i % 2)
      xf = compose(Transform::rotate(normalize({rng.next_double(), 1, rng.next_double()}), 360 * rng.next_double()),
                   Transform::scale({1, 0.5 + rng.next_double(), 1}));
    const std::vector<Vec3> v = gear(6 + i % 20, 0, 0, 0, 0.5, 0.5 + rng.next_double());
    add_polygon(scene, build(v), 0,
                xf ? std::optional<Transform>(compose(Transform::translate({cx, cy, z}), *xf))
                   : std::optional<Transform>(Transform::translate({cx, cy, z})));
  }
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  std::unique_ptr<Accelerator> embree;
  if (embree_available()) embree = build_accelerator(scene, AcceleratorOptions{1, AccelBackend::embree});
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const Ray ray{{rng.next_double() * 30 - 15, rng.next_double() * 30 - 15, rng.next_double() * 30 - 15},
                  {rng.next_double() - 0.5, rng.next_double() - 0.5, rng.next_double() - 0.5}};
    const auto a = bvh->intersect(ray), b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) continue;
    ++hits;
    EXPECT_EQ(a->object, b->object);
    EXPECT_EQ(a->t, b->t);
    EXPECT_EQ(a->primitive, b->primitive);
    if (embree) {
      const auto c = embree->intersect(ray);
      ASSERT_TRUE(c);
      EXPECT_EQ(c->object, b->object);
      EXPECT_NEAR(c->t, b->t, 1e-9);
    }
  }
  EXPECT_GT(hits, 200);
}

// Animated cylinders and polygons move with their keys (the per-frame rebuild
// keeps them in object space with the frame's transform).
TEST(NewObjectsAnimation, FramesMoveTheShapes) {
  const Scene base = parse_scene(R"({"camera": {"position": [0, 0, 10], "look_at": [0, 0, 0]}, "objects": [
    {"name": "rod", "type": "cylinder", "base": [0, -1, 0], "apex": [0, 1, 0], "radius": 0.5},
    {"name": "sheet", "type": "polygon", "vertices": [[-1, -1, -2], [1, -1, -2], [1, 1, -2], [-1, 1, -2]],
     "normals": [[0, 0, 1], [0, 0, 1], [0, 0, 1], [0, 0, 1]]}],
    "animation": {"frames": 3, "fps": 1, "keys": [
      {"time": 0, "objects": {"rod": {"translate": [0, 0, 0]}, "sheet": {"translate": [0, 0, 0]}}},
      {"time": 2, "objects": {"rod": {"translate": [4, 0, 0]}, "sheet": {"translate": [0, 0, -2]}}}]}})",
                                 kFileName);
  for (int frame = 0; frame < 3; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const Scene scene = scene_at_frame(base, frame);
    const auto accel = build_accelerator(scene);
    // The rod's axis is at x = 2 frame: its front at z = 0.5.
    const auto rod = accel->intersect({{2.0 * frame, 0, 10}, {0, 0, -1}});
    ASSERT_TRUE(rod);
    EXPECT_EQ(rod->object, 0u);
    EXPECT_NEAR(rod->t, 9.5, 1e-12);
    // The sheet is at z = -2 - frame.
    const auto sheet = accel->intersect({{-0.9, 0.9, 10}, {0, 0, -1}});
    ASSERT_TRUE(sheet);
    EXPECT_EQ(sheet->object, 1u);
    EXPECT_NEAR(sheet->t, 12.0 + frame, 1e-12);
    const SurfacePoint sp = evaluate_hit(scene, {{-0.9, 0.9, 10}, {0, 0, -1}}, *sheet);
    EXPECT_NEAR(sp.shading_normal.z, 1.0, 1e-15);
  }
}

// --- the loader ---------------------------------------------------------------

// `object` with one '@' where the error must point: the message must contain
// `message_part` and the error sit at that line and column.
void expect_object_error(std::string_view object, std::string_view message_part) {
  SCOPED_TRACE(std::string(message_part));
  const std::string marked = std::string(
                                 "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},\n"
                                 "\"objects\": [\n") +
                             std::string(object) + "]}";
  const size_t at = marked.find('@');
  ASSERT_NE(at, std::string::npos);
  const std::string text = marked.substr(0, at) + marked.substr(at + 1);
  int line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < at; ++i)
    if (marked[i] == '\n') ++line, line_start = i + 1;
  const int column = static_cast<int>(at - line_start) + 1;
  try {
    parse_scene(text, kFileName);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const Error& e) {
    EXPECT_NE(e.message().find(message_part), std::string::npos) << e.what();
    EXPECT_EQ(e.location().line, line) << e.what();
    EXPECT_EQ(e.location().column, column) << e.what();
  }
}

TEST(NewObjectsLoader, ValuesAndDefaults) {
  const Scene s = parse_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": [
    {"type": "cylinder", "base": [0, 0, 0], "apex": [0, 3, 0], "radius": 0.5},
    {"type": "cone", "base": [1, 0, 0], "apex": [1, 0, 4], "base_radius": 1, "apex_radius": 0, "caps": false},
    {"type": "disk", "center": [0, 1, 0], "normal": [0, 2, 0], "radius": 2},
    {"type": "disk", "center": [0, 1, 0], "normal": [1, 0, 0], "radius": 2, "inner_radius": 1.5},
    {"type": "polygon", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
     "normals": [[0, 0, 2], [0, 0, 1], [0, 1, 1], [0, 0, 1]],
     "transform": {"translate": [0, 0, 1]}}]})",
                              kFileName);
  ASSERT_EQ(s.objects.size(), 5u);
  EXPECT_EQ(s.objects[0].type, ShapeType::cylinder);
  EXPECT_EQ(s.objects[1].type, ShapeType::cone);
  EXPECT_EQ(s.objects[2].type, ShapeType::disk);
  EXPECT_EQ(s.objects[4].type, ShapeType::polygon);
  EXPECT_TRUE(s.cones[0].caps);
  EXPECT_EQ(s.cones[0].base_radius, 0.5);
  EXPECT_EQ(s.cones[0].apex_radius, 0.5);
  EXPECT_EQ(s.cones[0].length, 3.0);
  EXPECT_FALSE(s.cones[1].caps);
  expect_vec(s.cones[1].axis, {0, 0, 1}, 0);
  EXPECT_EQ(s.disks[0].inner_radius, 0.0);
  expect_vec(s.disks[0].normal, {0, 1, 0}, 0);  // normalized
  EXPECT_EQ(s.disks[1].inner_radius, 1.5);
  ASSERT_EQ(s.polygons.size(), 1u);
  expect_vec(s.polygons[0].normals[0], {0, 0, 1}, 0);  // normalized
  expect_vec(s.polygons[0].normals[2], normalize({0, 1, 1}), 1e-16);
  EXPECT_NE(s.objects[4].transform, kNoTransform);
}

TEST(NewObjectsLoader, EveryErrorNamesItsValue) {
  // Cylinders and cones.
  expect_object_error(R"({"type": "cylinder", "base": [0, 0, 0], "apex": @[0, 0, 0], "radius": 1})",
                      "objects[0].apex: must differ from \"base\"");
  expect_object_error(R"({"type": "cylinder", "base": [0, 0, 0], "apex": [0, 1, 0], "radius": @0})",
                      "objects[0].radius: must be > 0 (got 0)");
  expect_object_error(R"({"type": "cylinder", "base": [0, 0, 0], "apex": [0, 1, 0], "radius": 1, "caps": @1})",
                      "objects[0].caps: expected true or false");
  expect_object_error(R"({"type": "cylinder", "base": [0, 0, 0], "apex": [0, 1, 0], @"radis": 1})",
                      "objects[0]: unknown key \"radis\" (did you mean \"radius\"?)");
  expect_object_error(R"(@{"type": "cylinder", "base": [0, 0, 0], "apex": [0, 1, 0]})",
                      "objects[0]: missing required key \"radius\"");
  expect_object_error(R"({"type": "cylinder", "base": [0, 0, 0], "apex": [0, 1, 0], "radius": 1, @"base_radius": 1})",
                      "objects[0]: unknown key \"base_radius\"");
  expect_object_error(R"({"type": "cone", "base": [0, 0, 0], "apex": [0, 1, 0], "base_radius": 0, "apex_radius": @0})",
                      "objects[0].apex_radius: \"base_radius\" and \"apex_radius\" cannot both be 0");
  expect_object_error(R"({"type": "cone", "base": [0, 0, 0], "apex": [0, 1, 0], "base_radius": @-1, "apex_radius": 1})",
                      "objects[0].base_radius: must be >= 0 (got -1)");
  expect_object_error(R"({"type": "cone", "base": [0, 0, 0], "apex": [0, 1, 0], "base_radius": 1, @"apex_raduis": 1})",
                      "did you mean \"apex_radius\"?");
  expect_object_error(
      R"({"type": "cone", "base": [0, 0, 0], "apex": [0, 1, @1e999], "base_radius": 1, "apex_radius": 1})",
      "number out of range: 1e999");
  expect_object_error(R"({"type": @"cylindre"})", "unknown object type \"cylindre\" (did you mean \"cylinder\"?)");
  // Disks.
  expect_object_error(R"({"type": "disk", "center": [0, 0, 0], "normal": @[0, 0, 0], "radius": 1})",
                      "objects[0].normal: must be a non-zero vector");
  expect_object_error(R"({"type": "disk", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1, "inner_radius": @1})",
                      "objects[0].inner_radius: must be less than \"radius\"");
  expect_object_error(
      R"({"type": "disk", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1, "inner_radius": @-0.5})",
      "objects[0].inner_radius: must be >= 0");
  // Polygons.
  expect_object_error(R"({"type": "polygon", "vertices": @[[0, 0, 0], [1, 0, 0]]})",
                      "objects[0].vertices: a polygon needs at least three vertices (got 2)");
  expect_object_error(R"({"type": "polygon", "vertices": @{"x": 1}})", "objects[0].vertices: expected an array");
  expect_object_error(R"({"type": "polygon", "vertices": [[0, 0, 0], @[1, 0], [1, 1, 0]]})",
                      "objects[0].vertices[1]: expected [x, y, z]");
  expect_object_error(R"({"type": "polygon", "vertices": @[[0, 0, 0], [1, 1, 1], [2, 2, 2], [0, 1, 0]]})",
                      "objects[0].vertices: the first three vertices are collinear");
  expect_object_error(R"({"type": "polygon", "vertices": @[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.1]]})",
                      "objects[0].vertices: not planar: vertex 3 is 0.1 from the plane of the first three vertices");
  expect_object_error(
      R"({"type": "polygon", "vertices": @[[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]]})",
      "objects[0].vertices: self-intersecting: the edge from vertex 0 to 1 meets the edge from vertex 2 to 3");
  expect_object_error(R"({"type": "polygon", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]], "normals": @[[0, 0, 1]]})",
                      "objects[0].normals: expected one normal per vertex (3), got 1");
  expect_object_error(R"({"type": "polygon", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]],
                          "normals": [[0, 0, 1], @[0, 0, 0], [0, 0, 1]]})",
                      "objects[0].normals[1]: must be a non-zero vector");
  expect_object_error(R"({"type": "polygon", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]],
                          "normals": [[0, 0, 1], [0, 0, 1], [0, @-1e999, 1]]})",
                      "number out of range: -1e999");
  expect_object_error(R"({"type": "polygon", "vertices": [[0, 0, 0], [2, 0, 0], [2, 2, 0], [1, 1, 0], [0, 2, 0]],
                          "normals": @[[0, 0, 1], [0, 0, 1], [0, 0, 1], [0, 0, 1], [0, 0, 1]]})",
                      "objects[0].normals: a polygon with normals must be convex");
  expect_object_error(R"({"type": "polygon", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0]], @"normal": []})",
                      "unknown key \"normal\" (did you mean \"normals\"?)");
}

}  // namespace
}  // namespace glint
