#include "glint/geometry/shapes.h"

#include <cmath>

namespace glint {

std::optional<double> intersect_sphere(const Sphere& s, const Ray& ray) {
  // a t^2 + 2 b t + c = 0 with the discriminant written as a (r^2 - |f|^2),
  // f the center's offset from the ray line: no cancellation for far rays.
  const Vec3 oc = ray.origin - s.center;
  const double a = dot(ray.direction, ray.direction);
  const double b = dot(oc, ray.direction);
  const Vec3 f = oc - (b / a) * ray.direction;
  const double r2 = s.radius * s.radius;
  const double disc = a * (r2 - dot(f, f));
  if (disc < 0.0) return std::nullopt;
  const double c = dot(oc, oc) - r2;
  // Stable roots: q never suffers from b and sqrt(disc) cancelling.
  const double q = -(b + std::copysign(std::sqrt(disc), b));
  double t0 = q / a;
  double t1 = q != 0.0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > ray.t_min && t0 < ray.t_max) return t0;
  if (t1 > ray.t_min && t1 < ray.t_max) return t1;
  return std::nullopt;
}

std::optional<double> intersect_plane(const Plane& p, const Ray& ray) {
  const double denom = dot(p.normal, ray.direction);
  if (denom == 0.0) return std::nullopt;
  const double t = dot(p.normal, p.point - ray.origin) / denom;
  if (t > ray.t_min && t < ray.t_max) return t;
  return std::nullopt;
}

namespace {

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

template <int kz>
ShearedTriangle shear_triangle_in(const Triangle& tri, const Ray& ray) {
  using A = ShearAxes<kz>;
  const Vec3& d = ray.direction;
  // One division: the shear must be the same for every triangle a ray
  // meets (that is what closes the cracks), not correctly rounded.
  const double sz = 1.0 / A::z(d), sx = -A::x(d) * sz, sy = -A::y(d) * sz;
  const Vec3 a = tri.v0 - ray.origin, b = tri.v1 - ray.origin, c = tri.v2 - ray.origin;
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

ShearedTriangle shear_triangle(const Triangle& tri, const Ray& ray) {
  const Vec3& d = ray.direction;
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  if (ax > ay) return ax > az ? shear_triangle_in<0>(tri, ray) : shear_triangle_in<2>(tri, ray);
  return ay > az ? shear_triangle_in<1>(tri, ray) : shear_triangle_in<2>(tri, ray);
}

}  // namespace

std::optional<TriangleHit> intersect_triangle(const Triangle& tri, const Ray& ray) {
  const ShearedTriangle s = shear_triangle(tri, ray);
  // Inside when all three edge functions share a sign (zero counts as both).
  if ((s.e0 < 0 || s.e1 < 0 || s.e2 < 0) && (s.e0 > 0 || s.e1 > 0 || s.e2 > 0)) return std::nullopt;
  if (s.det == 0.0 || !std::isfinite(s.det)) return std::nullopt;  // edge-on, or degenerate
  const double inv_det = 1.0 / s.det;
  const double t = s.t_scaled * inv_det;
  if (!(t > ray.t_min && t < ray.t_max)) return std::nullopt;
  return TriangleHit{t, s.e1 * inv_det, s.e2 * inv_det};
}

TriangleHit triangle_plane_hit(const Triangle& tri, const Ray& ray) {
  const ShearedTriangle s = shear_triangle(tri, ray);
  if (s.det == 0.0 || !std::isfinite(s.det)) return TriangleHit{kInfinity, 0, 0};
  const double inv_det = 1.0 / s.det;
  return TriangleHit{s.t_scaled * inv_det, s.e1 * inv_det, s.e2 * inv_det};
}

std::optional<BoxHit> intersect_box(const Box& box, const Ray& ray) {
  double t_near = -kInfinity, t_far = kInfinity;
  int near_face = -1, far_face = -1;
  for (int axis = 0; axis < 3; ++axis) {
    const double o = ray.origin[axis], d = ray.direction[axis];
    if (d == 0.0) {
      if (o < box.lo[axis] || o > box.hi[axis]) return std::nullopt;
      continue;
    }
    double t0 = (box.lo[axis] - o) / d, t1 = (box.hi[axis] - o) / d;
    int f0 = 2 * axis, f1 = 2 * axis + 1;
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(f0, f1);
    }
    if (t0 > t_near) { t_near = t0; near_face = f0; }
    if (t1 < t_far) { t_far = t1; far_face = f1; }
    if (t_near > t_far) return std::nullopt;
  }
  if (t_near > ray.t_min && t_near < ray.t_max && near_face >= 0) return BoxHit{t_near, near_face};
  if (t_far > ray.t_min && t_far < ray.t_max && far_face >= 0) return BoxHit{t_far, far_face};
  return std::nullopt;
}

}  // namespace glint
