// The watertight ray/triangle arithmetic of Woop, Benthin and Wald (JCGT
// 2013), inline: the mesh kernels refine every float hit with it in double,
// and inlined into them its results stay in registers (returned through
// memory they were reloaded wider than they were stored, which stalls).
#pragma once

#include <cmath>

#include "glint/geometry/shape_types.h"
#include "glint/math/ray.h"

namespace glint {

struct TriangleHit {
  double t, b1, b2;
};  // barycentrics of v1 and v2

inline const Vec3& corner(const Triangle& tri, int i) { return i == 0 ? tri.v0 : (i == 1 ? tri.v1 : tri.v2); }

namespace watertight {

// The watertight ray/triangle test of Woop, Benthin and Wald (JCGT 2013):
// vertices are moved into a frame where the ray runs along +z from the
// origin, and the 2D edge functions decide the hit. An edge shared by two
// triangles gets the same function with the opposite sign in both, computed
// from the same numbers, so a ray through the edge hits at least one of them:
// no cracks. Each function is a difference of two products; when rounding
// makes one exactly zero, it is recomputed in long double.
struct ShearedTriangle {
  double e0, e1, e2;  // edge functions: weights of v0, v1, v2 (unnormalized)
  double det;         // e0 + e1 + e2
  double t_scaled;    // t * det
};

// Components in the shear frame's order (kx, ky, kz), with kz the axis
// where the direction is largest: the frame is a template argument, so the
// body is straight-line code (indexing a Vec3 by a run-time axis branched on
// every component, a fifth of a refined hit).
template <int kz>
struct ShearAxes {
  static constexpr int kx = kz == 2 ? 0 : kz + 1;
  static constexpr int ky = kx == 2 ? 0 : kx + 1;
  static double x(const Vec3& v) { return component(v, kx); }
  static double y(const Vec3& v) { return component(v, ky); }
  static double z(const Vec3& v) { return component(v, kz); }
  static constexpr double component(const Vec3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }
};

// `Corners` is a Triangle or anything else with a `corner(tri, i)` (found by
// argument-dependent lookup) giving vertex i as a Vec3: the mesh kernels
// read a float hit's vertices in place from their leaf block, since a
// Triangle built from them on the stack and read back wider than it was
// written stalls the load (a failed store-to-load forwarding).
template <int kz, class Corners>
[[gnu::always_inline]] inline ShearedTriangle shear_triangle_in(const Corners& tri, const Ray& ray) {
  using A = ShearAxes<kz>;
  const Vec3& d = ray.direction;
  // One division: the shear must be the same for every triangle a ray
  // meets (that is what closes the cracks), not correctly rounded.
  const double sz = 1.0 / A::z(d), sx = -A::x(d) * sz, sy = -A::y(d) * sz;
  const Vec3 a = corner(tri, 0) - ray.origin, b = corner(tri, 1) - ray.origin, c = corner(tri, 2) - ray.origin;
  const double ax2 = A::x(a) + sx * A::z(a), ay2 = A::y(a) + sy * A::z(a);
  const double bx2 = A::x(b) + sx * A::z(b), by2 = A::y(b) + sy * A::z(b);
  const double cx2 = A::x(c) + sx * A::z(c), cy2 = A::y(c) + sy * A::z(c);
  ShearedTriangle s;
  s.e0 = bx2 * cy2 - by2 * cx2;
  s.e1 = cx2 * ay2 - cy2 * ax2;
  s.e2 = ax2 * by2 - ay2 * bx2;
  if (s.e0 == 0.0 || s.e1 == 0.0 || s.e2 == 0.0) [[unlikely]] {
    using L = long double;
    s.e0 = static_cast<double>(L(bx2) * L(cy2) - L(by2) * L(cx2));
    s.e1 = static_cast<double>(L(cx2) * L(ay2) - L(cy2) * L(ax2));
    s.e2 = static_cast<double>(L(ax2) * L(by2) - L(ay2) * L(bx2));
  }
  s.det = s.e0 + s.e1 + s.e2;
  s.t_scaled = (s.e0 * A::z(a) + s.e1 * A::z(b) + s.e2 * A::z(c)) * sz;
  return s;
}

template <class Corners>
[[gnu::always_inline]] inline ShearedTriangle shear_triangle(const Corners& tri, const Ray& ray) {
  const Vec3& d = ray.direction;
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  if (ax > ay) return ax > az ? shear_triangle_in<0>(tri, ray) : shear_triangle_in<2>(tri, ray);
  return ay > az ? shear_triangle_in<1>(tri, ray) : shear_triangle_in<2>(tri, ray);
}

}  // namespace watertight

// The ray's crossing of the triangle's plane with its barycentrics, inside
// the triangle or not (t = infinity when the ray runs in the plane).
template <class Corners>
[[gnu::always_inline]] inline TriangleHit triangle_plane_hit(const Corners& tri, const Ray& ray) {
  const watertight::ShearedTriangle s = watertight::shear_triangle(tri, ray);
  if (s.det == 0.0 || !std::isfinite(s.det)) return TriangleHit{kInfinity, 0, 0};
  const double inv_det = 1.0 / s.det;
  return TriangleHit{s.t_scaled * inv_det, s.e1 * inv_det, s.e2 * inv_det};
}

}  // namespace glint
