// Ray/torus intersection: random tori and rays (grazing, tangent, from far
// away, from the surface) against a brute-force march of the distance
// function in long double; known crossings (a ray along the plane through
// the center, rays through the hole); t_min/t_max; non-unit directions;
// normals and bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "glint/geometry/torus.h"
#include "glint/math/rng.h"

namespace glint {
namespace {

using LD = long double;

Ray make_ray(const Vec3& origin, const Vec3& direction) {
  Ray r;
  r.origin = origin;
  r.direction = direction;
  return r;
}

// --- the reference: the signed distance to the surface along the ray, in long double

struct LVec {
  LD x, y, z;
};
LVec lvec(const Vec3& v) { return {v.x, v.y, v.z}; }
LD ldot(const LVec& a, const LVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

struct Reference {
  LVec o, d, c, n;
  LD R, r;
  Reference(const Torus& torus, const Ray& ray)
      : o(lvec(ray.origin)),
        d(lvec(ray.direction)),
        c(lvec(torus.center)),
        n(lvec(torus.axis)),
        R(torus.major_radius),
        r(torus.minor_radius) {}
  LVec q(LD t) const { return {o.x + t * d.x - c.x, o.y + t * d.y - c.y, o.z + t * d.z - c.z}; }
  // The signed distance to the surface (the distance to the center circle
  // less r: exact for a torus), negative inside.
  LD distance(LD t) const {
    const LVec p = q(t);
    const LD z = ldot(p, n);
    const LVec across{p.x - z * n.x, p.y - z * n.y, p.z - z * n.z};
    const LD e = std::sqrt(ldot(across, across)) - R;
    return std::sqrt(e * e + z * z) - r;
  }
  // |cos| of the angle between the ray and the surface normal at t.
  LD cosine(LD t) const {
    const LVec p = q(t);
    const LD z = ldot(p, n);
    LVec across{p.x - z * n.x, p.y - z * n.y, p.z - z * n.z};
    const LD l = std::sqrt(ldot(across, across));
    const LVec m{p.x - R * across.x / l, p.y - R * across.y / l, p.z - R * across.z / l};
    return std::abs(ldot(m, d)) / std::sqrt(ldot(m, m) * ldot(d, d));
  }
  // Where the line is inside the bounding sphere, a little widened.
  bool chord(LD& t0, LD& t1) const {
    const LVec oc{o.x - c.x, o.y - c.y, o.z - c.z};
    const LD a = ldot(d, d), b = ldot(oc, d);
    const LD tf = -b / a;
    const LVec f{oc.x + tf * d.x, oc.y + tf * d.y, oc.z + tf * d.z};
    const LD big = (R + r) * 1.001L;
    const LD disc = big * big - ldot(f, f);
    if (disc <= 0) return false;
    const LD h = std::sqrt(disc / a);
    t0 = tf - h;
    t1 = tf + h;
    return true;
  }
  // Sign changes of the distance along the bounding sphere's chord, refined
  // by bisection. The distance changes no faster than the point moves, so
  // steps of 0.9 of it (in length) cannot pass a crossing; steps of at least
  // 1e-7 of the size (one a far-from-tangent ray passes) keep it finite.
  std::vector<LD> march() const {
    std::vector<LD> roots;
    LD t0, t1;
    if (!chord(t0, t1)) return roots;
    const LD len = std::sqrt(ldot(d, d)), min_step = 1e-7L * (R + r) / len;
    LD t = t0, dt = distance(t0);
    while (t < t1) {
      const LD next = std::min(t1, t + std::max(0.9L * std::abs(dt) / len, min_step));
      const LD dn = distance(next);
      if ((dn < 0) != (dt < 0)) {
        LD a = t, b = next;
        for (int k = 0; k < 200; ++k) {
          const LD m = 0.5L * (a + b);
          if (m == a || m == b) break;
          ((distance(m) < 0) == (dt < 0) ? a : b) = m;
        }
        roots.push_back(0.5L * (a + b));
      }
      t = next;
      dt = dn;
    }
    return roots;
  }
};

// --- random tori and rays ---------------------------------------------------

double uniform(Rng& rng, double lo, double hi) { return lo + (hi - lo) * rng.next_double(); }

Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const double l2 = dot(v, v);
    if (l2 > 1e-4 && l2 <= 1) return v / std::sqrt(l2);
  }
}

// A unit vector across the axis.
Vec3 across_axis(const Vec3& axis, const Vec3& hint) { return normalize(hint - dot(hint, axis) * axis); }

Torus random_torus(Rng& rng) {
  Torus t;
  const double size = std::pow(10.0, uniform(rng, -3, 3));
  t.major_radius = size * uniform(rng, 0.5, 2);
  t.minor_radius = t.major_radius * std::pow(10.0, uniform(rng, -2, std::log10(0.95)));
  const double far = rng.next_double() < 0.2 ? 1000.0 : 5.0;
  t.center = size * far * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  t.axis = random_unit(rng);
  return t;
}

// The surface point at angles (theta about the axis, phi about the tube),
// and its normal.
struct SurfacePoint {
  Vec3 p, n;
};
SurfacePoint surface_point(const Torus& t, double theta, double phi) {
  const Vec3 e1 = across_axis(t.axis, std::abs(t.axis.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0));
  const Vec3 e2 = cross(t.axis, e1);
  const Vec3 radial = std::cos(theta) * e1 + std::sin(theta) * e2;
  const Vec3 n = std::cos(phi) * radial + std::sin(phi) * t.axis;
  return {t.center + t.major_radius * radial + t.minor_radius * n, n};
}

SurfacePoint random_surface_point(Rng& rng, const Torus& t) {
  return surface_point(t, uniform(rng, 0, 2 * std::numbers::pi), uniform(rng, 0, 2 * std::numbers::pi));
}

double bound_radius(const Torus& t) { return t.major_radius + t.minor_radius; }

// A direction of random length (t then scales with it).
Vec3 random_length(Rng& rng, const Vec3& unit) { return unit * std::pow(10.0, uniform(rng, -2, 2)); }

Ray random_ray(Rng& rng, const Torus& t, int kind) {
  const double size = bound_radius(t);
  switch (kind) {
    case 0: {  // anywhere near, any direction
      const Vec3 o = t.center + size * 3.0 * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      return make_ray(o, random_length(rng, random_unit(rng)));
    }
    case 1: {  // aimed at a point near the surface
      const SurfacePoint s = random_surface_point(rng, t);
      const Vec3 target = s.p + size * 0.05 * uniform(rng, -1, 1) * s.n;
      const Vec3 dir = random_unit(rng);
      return make_ray(target - size * uniform(rng, 0, 3) * dir, random_length(rng, dir));
    }
    case 2: {  // from 1e4 times the torus's size, aimed inside its bounding sphere
      const Vec3 target = t.center + size * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      const Vec3 dir = random_unit(rng);
      return make_ray(target - size * 1e4 * dir, random_length(rng, dir));
    }
    case 3: {  // (nearly) tangent: a tangent line moved off the surface by up to 1e-3 of the size
      const SurfacePoint s = random_surface_point(rng, t);
      const Vec3 tangent = across_axis(s.n, random_unit(rng));
      const double offset = size * std::pow(10.0, uniform(rng, -12, -3)) * (rng.next_double() < 0.5 ? -1 : 1);
      return make_ray(s.p + offset * s.n - size * uniform(rng, 0, 3) * tangent, random_length(rng, tangent));
    }
    default: {  // from a point of the surface
      const SurfacePoint s = random_surface_point(rng, t);
      return make_ray(s.p, random_length(rng, random_unit(rng)));
    }
  }
}

// The checks of one ray, and what they saw.
struct Stats {
  int rays = 0, hits = 0, clear = 0;
  double worst = 0;  // the largest error of a clear crossing, in units of R + r
};

void check_ray(const Torus& torus, const Ray& ray, Stats& stats, const char* what) {
  double t[4];
  const int n = torus_crossings(torus, ray, t);
  const Reference ref(torus, ray);
  const double size = bound_radius(torus);
  const double len = length(ray.direction);
  const double tol = 1e-9 * size / len;  // in t units
  ++stats.rays;
  if (n > 0) ++stats.hits;
  ASSERT_TRUE(n == 0 || n == 2 || n == 4) << what << ": " << n << " crossings";
  for (int k = 0; k + 1 < n; ++k) ASSERT_LE(t[k], t[k + 1]) << what;
  // Every crossing is one: the distance changes sign across it, outside to
  // inside at the even ones, or (a touch) stays within rounding of 0. (Random
  // rays have no two crossings within 2 tol.)
  bool all_clear = true;  // and far enough apart for the march to see each
  for (int k = 0; k < n; ++k) {
    const LD before = ref.distance(LD(t[k]) - tol), after = ref.distance(LD(t[k]) + tol);
    const bool touch = std::max(std::abs(before), std::abs(after)) <= 1e-12L * size;
    EXPECT_TRUE(touch || (k % 2 == 0 ? before >= 0 && after <= 0 : before <= 0 && after >= 0))
        << what << ": crossing " << k << " of " << n << " at t = " << t[k] << " is not one (distance "
        << double(before) << " before, " << double(after) << " after)";
    all_clear = all_clear && ref.cosine(t[k]) >= 0.02 && (k == 0 || (t[k] - t[k - 1]) * len > 1e-6 * size);
  }
  // Every crossing the march sees at a clear angle is among them; where all
  // are clear, so are the counts the same.
  const std::vector<LD> marched = ref.march();
  for (const LD root : marched) {
    if (ref.cosine(root) < 0.02) {
      all_clear = false;
      continue;
    }
    ++stats.clear;
    double best = kInfinity;
    for (int k = 0; k < n; ++k) best = std::min(best, double(std::abs(LD(t[k]) - root)));
    EXPECT_LE(best, tol) << what << ": the march's crossing at " << double(root) << " is missing (" << n
                         << " found)";
    stats.worst = std::max(stats.worst, best * len / size);
  }
  if (all_clear) {
    EXPECT_EQ(n, static_cast<int>(marched.size())) << what;
  }
  // The nearest hit is the first crossing past t_min; one within rounding
  // of t_min (a ray from the surface) may count or not.
  const auto hit = intersect_torus(torus, ray);
  int first = 0;
  while (first < n && !(t[first] > ray.t_min + tol)) ++first;
  if (hit) {
    EXPECT_GT(*hit, ray.t_min) << what;
    const bool at_start = *hit <= ray.t_min + 2 * tol && first > 0 && t[first - 1] >= ray.t_min - tol;
    if (!at_start) {
      ASSERT_LT(first, n) << what << ": a hit at " << *hit << " where the line has no crossing";
      EXPECT_NEAR(*hit, t[first], tol) << what;
    }
  } else {
    EXPECT_EQ(first, n) << what << ": no hit, but a crossing at " << t[first];
  }
}

TEST(TorusIntersection, RandomRaysAgreeWithABruteForceMarch) {
  Rng rng(12345);
  const char* kinds[] = {"near", "aimed", "far", "grazing", "from the surface"};
  for (int kind = 0; kind < 5; ++kind) {
    Stats stats;
    for (int i = 0; i < 3000; ++i) {
      const Torus torus = random_torus(rng);
      const Ray ray = random_ray(rng, torus, kind);
      check_ray(torus, ray, stats, kinds[kind]);
      if (HasFailure()) return;
    }
    // Near double precision: a few ulps of the size, or from 1e4 sizes away
    // a few of the distance (what rounding the origin's offset leaves).
    EXPECT_LT(stats.worst, kind == 2 ? 1e-10 : 1e-13) << kinds[kind];
    EXPECT_GT(stats.hits, kind == 0 ? 40 : 600) << kinds[kind];
  }
}

// Tangent lines on the outer half (where the surface is convex) moved
// inward by delta cross twice near the tangent point, at about +-sqrt(2
// delta / k), k the surface's curvature along the line; moved outward they
// miss there.
TEST(TorusIntersection, GrazingRaysFindBothCrossingsAndNoneWhenJustMissing) {
  Rng rng(777);
  for (int i = 0; i < 3000; ++i) {
    const Torus torus = random_torus(rng);
    const double size = bound_radius(torus);
    const SurfacePoint s = surface_point(torus, uniform(rng, 0, 2 * std::numbers::pi),
                                         uniform(rng, -0.45, 0.45) * std::numbers::pi);  // outer half
    const Vec3 tangent = across_axis(s.n, random_unit(rng));
    const double delta = size * std::pow(10.0, uniform(rng, -11, -4));
    const double back = size * uniform(rng, 0.5, 1e4);
    const double len = std::pow(10.0, uniform(rng, -2, 2));
    // The normal curvature along the tangent (Euler: k1 cos^2 + k2 sin^2).
    const Vec3 radial = across_axis(torus.axis, s.n);
    const Vec3 around = normalize(cross(torus.axis, radial));
    const double c = dot(tangent, around);
    const double cos_phi = dot(s.n, radial);
    const double k_tube = 1.0 / torus.minor_radius;
    const double k_ring = cos_phi / (torus.major_radius + torus.minor_radius * cos_phi);
    const double curvature = k_ring * c * c + k_tube * (1 - c * c);
    const double half = std::sqrt(2 * delta / curvature);  // distance, not t

    const Ray in = make_ray(s.p - delta * s.n - back * tangent, tangent * len);
    double t[4];
    const int n = torus_crossings(torus, in, t);
    ASSERT_TRUE(n == 2 || n == 4) << i << ": " << n;
    // The pair about the tangent point.
    const double center = back / len;
    int k = 0;
    while (k < n && t[k] < center - 2 * half / len) ++k;
    ASSERT_LT(k + 1, n) << i;
    EXPECT_NEAR(t[k] * len, back - half, 0.1 * half + 1e-9 * size) << i;
    EXPECT_NEAR(t[k + 1] * len, back + half, 0.1 * half + 1e-9 * size) << i;
    // Each is a crossing to within 1e-9 of the size, or, from far away, to
    // within what rounding the origin's coordinates (~eps |o|) moves a root
    // whose angle's cosine is k half.
    const Reference ref(torus, in);
    const double tol = (1e-9 * size + 4e-16 * back / (curvature * half)) / len;
    EXPECT_GE(ref.distance(LD(t[k]) - tol), 0) << i;
    EXPECT_LE(ref.distance(LD(t[k]) + tol), 0) << i;
    EXPECT_LE(ref.distance(LD(t[k + 1]) - tol), 0) << i;
    EXPECT_GE(ref.distance(LD(t[k + 1]) + tol), 0) << i;

    const Ray out = make_ray(s.p + delta * s.n - back * tangent, tangent * len);
    const int m = torus_crossings(torus, out, t);
    ASSERT_TRUE(m == 0 || m == 2 || m == 4) << i << ": " << m;
    for (int j = 0; j < m; ++j) EXPECT_GT(std::abs(t[j] * len - back), 0.5 * half) << i << ": a crossing at a miss";
    if (HasFailure()) return;
  }
}

TEST(TorusIntersection, ExactTangentRaysGiveAnEvenCount) {
  Rng rng(4242);
  for (int i = 0; i < 5000; ++i) {
    const Torus torus = random_torus(rng);
    const SurfacePoint s = random_surface_point(rng, torus);
    const Vec3 tangent = across_axis(s.n, random_unit(rng));
    const Ray ray = make_ray(s.p - bound_radius(torus) * uniform(rng, 0, 3) * tangent, tangent);
    double t[4];
    const int n = torus_crossings(torus, ray, t);
    ASSERT_TRUE(n == 0 || n == 2 || n == 4) << i << ": " << n;
  }
  // Tangent to the bounding sphere at the outer equator, and to the top and
  // bottom circles along the slab's planes.
  const Torus torus{{1, 2, 3}, normalize(Vec3(1, 2, 2)), 2.0, 0.5};
  const Vec3 e1 = across_axis(torus.axis, Vec3(1, 0, 0));
  const Vec3 e2 = cross(torus.axis, e1);
  double t[4];
  const int outer = torus_crossings(torus, make_ray(torus.center + 2.5 * e1 - 5 * e2, e2), t);
  EXPECT_TRUE(outer == 0 || outer == 2) << outer;
  const int top = torus_crossings(torus, make_ray(torus.center + 0.5 * torus.axis - 5 * e2, e2), t);
  EXPECT_TRUE(top == 0 || top == 2 || top == 4) << top;
}

TEST(TorusIntersection, RayAlongThePlaneThroughTheCenterHitsFourTimes) {
  const Torus torus{{1.5, -2, 0.25}, normalize(Vec3(0.3, 1, -0.2)), 3.0, 0.75};
  const Vec3 u = across_axis(torus.axis, Vec3(1, 0.5, 0));
  const double D = 10;
  for (const double scale : {1.0, 0.01, 37.0}) {
    const Ray ray = make_ray(torus.center - D * u, u * scale);
    double t[4];
    ASSERT_EQ(torus_crossings(torus, ray, t), 4);
    const double R = torus.major_radius, r = torus.minor_radius;
    const double expected[4] = {D - (R + r), D - (R - r), D + (R - r), D + (R + r)};
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(t[k] * scale, expected[k], 1e-13 * D) << k;
    const auto hit = intersect_torus(torus, ray);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(*hit * scale, expected[0], 1e-13 * D);
  }
}

TEST(TorusIntersection, NonUnitDirectionsScaleT) {
  Rng rng(99);
  for (int i = 0; i < 2000; ++i) {
    const Torus torus = random_torus(rng);
    const Ray unit = random_ray(rng, torus, 1);
    const Vec3 dir = normalize(unit.direction);
    const double scale = std::pow(10.0, uniform(rng, -3, 3));
    double a[4], b[4];
    const int n = torus_crossings(torus, make_ray(unit.origin, dir), a);
    const int m = torus_crossings(torus, make_ray(unit.origin, dir * scale), b);
    ASSERT_EQ(n, m) << i;
    for (int k = 0; k < n; ++k) EXPECT_NEAR(b[k] * scale, a[k], 1e-9 * bound_radius(torus)) << i;
  }
}

TEST(TorusIntersection, RaysThroughTheHoleAlongTheAxisMiss) {
  Rng rng(5);
  for (int i = 0; i < 2000; ++i) {
    const Torus torus = random_torus(rng);
    const double R = torus.major_radius, r = torus.minor_radius;
    const Vec3 side = across_axis(torus.axis, random_unit(rng));
    const double off = (R - r) * uniform(rng, 0, 0.9);
    const Vec3 o = torus.center + off * side + 10 * (R + r) * torus.axis;
    // Straight down the axis, or tilted as far as the hole allows.
    Vec3 d = -torus.axis;
    if (i % 2) {
      const double room = (R - r) * 0.9 - off;
      d = normalize(-torus.axis + (room / (10 * (R + r) + r)) * across_axis(torus.axis, random_unit(rng)));
    }
    const Ray ray = make_ray(o, d * std::pow(10.0, uniform(rng, -2, 2)));
    double t[4];
    EXPECT_EQ(torus_crossings(torus, ray, t), 0) << i;
    EXPECT_FALSE(intersect_torus(torus, ray)) << i;
  }
  // Exactly along the axis through the center.
  const Torus torus{{0, 0, 0}, {0, 0, 1}, 1.0, 0.25};
  double t[4];
  EXPECT_EQ(torus_crossings(torus, make_ray({0, 0, 5}, {0, 0, -1}), t), 0);
}

TEST(TorusIntersection, RespectsTMinAndTMax) {
  const Torus torus{{0, 0, 0}, {0, 1, 0}, 2.0, 0.5};
  Ray ray = make_ray({-10, 0, 0}, {1, 0, 0});  // crossings at 7.5, 8.5, 11.5, 12.5
  auto hit = intersect_torus(torus, ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(*hit, 7.5, 1e-13);
  ray.t_min = 7.5;  // open interval: the crossing at t_min itself does not count
  hit = intersect_torus(torus, ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(*hit, 8.5, 1e-13);
  ray.t_min = 9;
  hit = intersect_torus(torus, ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(*hit, 11.5, 1e-13);
  ray.t_max = 11.4;
  EXPECT_FALSE(intersect_torus(torus, ray));
  ray.t_min = 0;
  ray.t_max = 7.4;
  EXPECT_FALSE(intersect_torus(torus, ray));
  ray.t_min = 12.6;
  ray.t_max = kInfinity;
  EXPECT_FALSE(intersect_torus(torus, ray));
  // Crossings behind the origin are in the line's list but not hits.
  ray = make_ray({0, 0, 0}, {1, 0, 0});  // from the hole's center: crossings at -2.5, -1.5, 1.5, 2.5
  double t[4];
  ASSERT_EQ(torus_crossings(torus, ray, t), 4);
  EXPECT_NEAR(t[0], -2.5, 1e-13);
  EXPECT_NEAR(t[1], -1.5, 1e-13);
  hit = intersect_torus(torus, ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(*hit, 1.5, 1e-13);
  // From inside the tube: the exit.
  ray = make_ray({2, 0.1, 0}, {1, 0, 0});
  hit = intersect_torus(torus, ray);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(*hit, std::sqrt(0.25 - 0.01), 1e-13);
  // Random t intervals: the first crossing inside.
  Rng rng(31);
  for (int i = 0; i < 3000; ++i) {
    const Torus tor = random_torus(rng);
    Ray r = random_ray(rng, tor, 1);
    const int n = torus_crossings(tor, r, t);
    if (n == 0) continue;
    r.t_min = uniform(rng, t[0] - 1, t[n - 1] + 0.1) ;
    r.t_max = r.t_min + uniform(rng, 0, t[n - 1] - t[0] + 1);
    const auto h = intersect_torus(tor, r);
    const double* first = std::find_if(t, t + n, [&](double x) { return x > r.t_min && x < r.t_max; });
    if (first == t + n) {
      EXPECT_FALSE(h) << i;
    } else {
      ASSERT_TRUE(h) << i;
      EXPECT_NEAR(*h, *first, 1e-9 * bound_radius(tor) / length(r.direction)) << i;
      EXPECT_TRUE(*h > r.t_min && *h < r.t_max) << i;
    }
  }
}

TEST(TorusIntersection, RaysLeavingTheSurfaceDoNotHitItAgainThere) {
  // A ray from a hit point (moved off by the renderer's epsilon along the
  // normal, or not at all with t_min a little above 0) finds the surface
  // only where the line truly meets it again.
  Rng rng(2024);
  for (int i = 0; i < 3000; ++i) {
    const Torus torus = random_torus(rng);
    const double size = bound_radius(torus);
    const SurfacePoint s = random_surface_point(rng, torus);
    Vec3 dir = random_unit(rng);
    if (dot(dir, s.n) < 0) dir = -dir;
    Ray ray = make_ray(s.p + 1e-7 * size * s.n, dir);
    if (const auto h = intersect_torus(torus, ray)) {
      EXPECT_GT(*h, 1e-4 * size) << i;
    }
    ray = make_ray(s.p, dir);
    ray.t_min = 1e-9 * size;
    if (const auto h = intersect_torus(torus, ray)) {
      EXPECT_GT(*h, 1e-4 * size) << i;
    }
    // Into the surface: the exit, beyond the origin.
    ray = make_ray(s.p, -dir);
    ray.t_min = 1e-9 * size;
    const auto h = intersect_torus(torus, ray);
    ASSERT_TRUE(h) << i;
    EXPECT_GT(*h, 1e-9 * size) << i;
  }
}

TEST(TorusIntersection, NormalsAreUnitAndMatchTheParametricOnes) {
  const Torus torus{{1, -1, 2}, normalize(Vec3(1, 1, 1)), 2.0, 0.5};
  const Vec3 u = across_axis(torus.axis, Vec3(0, 0, 1));
  const auto near = [](const Vec3& a, const Vec3& b) { return length(a - b) < 1e-12; };
  EXPECT_TRUE(near(torus_normal(torus, torus.center + 2.5 * u), u));
  EXPECT_TRUE(near(torus_normal(torus, torus.center + 1.5 * u), -u));
  EXPECT_TRUE(near(torus_normal(torus, torus.center + 2.0 * u + 0.5 * torus.axis), torus.axis));
  EXPECT_TRUE(near(torus_normal(torus, torus.center + 2.0 * u - 0.5 * torus.axis), -torus.axis));
  Rng rng(8);
  for (int i = 0; i < 2000; ++i) {
    const Torus t = random_torus(rng);
    const SurfacePoint s = random_surface_point(rng, t);
    const Vec3 n = torus_normal(t, s.p);
    EXPECT_NEAR(length(n), 1.0, 1e-14) << i;
    // The point's rounding (relative to the center's size) moves the normal by that over r.
    const double slack = 1e-13 * (1 + max_abs_component(t.center) / t.minor_radius);
    EXPECT_LT(length(n - s.n), slack) << i;
    // At a hit, the normal faces against a ray from outside.
    const Ray ray = random_ray(rng, t, 1);
    if (const auto h = intersect_torus(t, ray)) {
      double all[4];
      const int count = torus_crossings(t, ray, all);
      int k = 0;
      while (k < count && !(all[k] > 0)) ++k;
      if (k < count && k % 2 == 0 && Reference(t, ray).cosine(*h) > 0.01) {
        EXPECT_LT(dot(torus_normal(t, ray.at(*h)), ray.direction), 0) << i;
      }
    }
  }
}

TEST(TorusIntersection, BoundsAreTightAndHoldTheSurface) {
  Rng rng(17);
  for (int i = 0; i < 500; ++i) {
    const Torus t = random_torus(rng);
    const Bounds3 b = torus_bounds(t);
    Vec3 lo(kInfinity), hi(-kInfinity);
    for (int k = 0; k < 4000; ++k) {
      const Vec3 p = random_surface_point(rng, t).p;
      lo = min(lo, p);
      hi = max(hi, p);
    }
    const double size = bound_radius(t);
    for (int a = 0; a < 3; ++a) {
      EXPECT_LE(b.lo[a], lo[a]) << i;
      EXPECT_GE(b.hi[a], hi[a]) << i;
      EXPECT_LT(lo[a] - b.lo[a], 0.02 * size) << i;  // 4000 samples come close to the extremes
      EXPECT_LT(b.hi[a] - hi[a], 0.02 * size) << i;
    }
  }
  // Axis along y: the box is (R + r, r, R + r) about the center.
  const Bounds3 b = torus_bounds(Torus{{1, 2, 3}, {0, 1, 0}, 2.0, 0.5});
  EXPECT_NEAR(b.lo.x, -1.5, 1e-11);
  EXPECT_NEAR(b.hi.y, 2.5, 1e-11);
  EXPECT_NEAR(b.lo.y, 1.5, 1e-11);
  EXPECT_NEAR(b.hi.z, 5.5, 1e-11);
}

}  // namespace
}  // namespace glint
