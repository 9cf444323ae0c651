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

std::optional<TriangleHit> intersect_triangle(const Triangle& tri, const Ray& ray) {
  const watertight::ShearedTriangle s = watertight::shear_triangle(tri, ray);
  // Inside when all three edge functions share a sign (zero counts as both).
  if ((s.e0 < 0 || s.e1 < 0 || s.e2 < 0) && (s.e0 > 0 || s.e1 > 0 || s.e2 > 0)) return std::nullopt;
  if (s.det == 0.0 || !std::isfinite(s.det)) return std::nullopt;  // edge-on, or degenerate
  const double inv_det = 1.0 / s.det;
  const double t = s.t_scaled * inv_det;
  if (!(t > ray.t_min && t < ray.t_max)) return std::nullopt;
  return TriangleHit{t, s.e1 * inv_det, s.e2 * inv_det};
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
