// Ray/shape intersection for the analytic shapes: each returns the nearest
// distance t in the ray's open interval (t_min, t_max), or nothing. Rays are
// in the shape's own space; directions need not be unit length.
#pragma once

#include <cmath>
#include <optional>
#include <utility>

#include "glint/geometry/shape_types.h"
#include "glint/geometry/triangle_shear.h"
#include "glint/math/ray.h"

namespace glint {

// Inline: the accelerator's leaves call it for every sphere they hold, and a
// call for these few operations was a sixth of a sphereflake's render.
inline std::optional<double> intersect_sphere(const Sphere& s, const Ray& ray) {
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
std::optional<double> intersect_plane(const Plane& p, const Ray& ray);

// Watertight (Woop et al. 2013): a ray through an edge or vertex shared by
// triangles hits at least one of them.
std::optional<TriangleHit> intersect_triangle(const Triangle& tri, const Ray& ray);
// triangle_plane_hit (the plane crossing, for refining float hits) is in
// triangle_shear.h.

struct BoxHit {
  double t;
  int face;
};  // face = 2*axis + (1 if the max side)
std::optional<BoxHit> intersect_box(const Box& box, const Ray& ray);

// Outward unit normal of a box face.
inline Vec3 box_face_normal(int face) {
  Vec3 n(0.0);
  n[face / 2] = (face & 1) ? 1.0 : -1.0;
  return n;
}

// Cylinders and cones (Cone): which part was hit, as Hit::face.
enum ConePart : int { kConeSide = 0, kConeBaseCap = 1, kConeApexCap = 2 };
struct ConeHit {
  double t;
  int part;
};
// Exact in double: the lateral quadric and the slab between the end planes
// are each an interval along the ray, and a closed shape is their
// intersection, whose ends are its entry and exit. A ray through the rim
// where side and cap meet therefore always finds one of them (no crack);
// an open shape keeps only the quadric's ends that lie in the slab.
std::optional<ConeHit> intersect_cone(const Cone& cone, const Ray& ray);
// The unit outward normal at p (cone space) of the part hit: a cap's axis
// direction away from the solid, or the side's gradient (across the axis,
// tilted by the slope).
Vec3 cone_normal(const Cone& cone, int part, const Vec3& p);
// Cone-space bounds: the two end disks' boxes.
Bounds3 cone_bounds(const Cone& cone);

std::optional<double> intersect_disk(const Disk& disk, const Ray& ray);
Bounds3 disk_bounds(const Disk& disk);

// A polygon through its triangles (watertight triangle test, so the
// triangulation's shared edges let no ray through).
struct PolygonHit {
  double t, b1, b2;
  uint32_t triangle;
};
std::optional<PolygonHit> intersect_polygon(const Polygon& polygon, const Ray& ray);

}  // namespace glint
