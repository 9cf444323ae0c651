// Ray/torus intersection. Along a line the torus's quartic ((|q|^2 + R^2 -
// r^2)^2 = 4 R^2 |q across the axis|^2, q the offset from the center) has
// the roots of g = (distance to the center circle)^2 - r^2 = A - 2 R rho:
// A is a quadratic and rho, the distance from the axis, a hyperbola. So g is
// convex but for one stretch about the line's point nearest the axis, found
// in closed form, and on each stretch Newton's method from the right end
// climbs to the first root without passing it; rho's chord gives a closer
// start, or proves a stretch empty. Roots come out within a few ulps of the
// torus's size (of the origin's distance, for a ray from far away).
#pragma once

#include <optional>

#include "glint/geometry/shape_types.h"
#include "glint/math/bounds.h"
#include "glint/math/ray.h"

namespace glint {

// Every crossing of the ray's whole line with the surface (any t, ignoring
// ray.t_min and t_max), ascending, at most 4; returns how many. They come in
// entry/exit pairs (the torus is a closed solid), so the count is 0, 2 or 4:
// a ray that only touches the surface may give 0 or a pair of (nearly) equal
// crossings, never an odd count. t is in the ray's own units (its direction
// need not be unit length).
int torus_crossings(const Torus& torus, const Ray& ray, double t[4]);

namespace detail {
// intersect_torus for a line that passes through the bounding sphere.
std::optional<double> intersect_torus_near(const Torus& torus, const Ray& ray);
}  // namespace detail

// The nearest crossing in the open interval (ray.t_min, ray.t_max), or
// nothing. Inline up to the bounding sphere (radius R + r) test, which is
// intersect_sphere's: a ray that misses it costs what a sphere miss does.
inline std::optional<double> intersect_torus(const Torus& torus, const Ray& ray) {
  // The line's point nearest the center, f, without cancellation for far rays.
  const Vec3 oc = ray.origin - torus.center;
  const double inv_a = 1.0 / dot(ray.direction, ray.direction);
  const double t_foot = -dot(oc, ray.direction) * inv_a;
  const Vec3 f = oc + t_foot * ray.direction;
  const double bound = torus.major_radius + torus.minor_radius;
  if (!(dot(f, f) < bound * bound)) return std::nullopt;  // also a zero or non-finite direction
  return detail::intersect_torus_near(torus, ray);
}

// Unit outward normal at a point on (or near) the surface: from the nearest
// point of the center circle toward p.
Vec3 torus_normal(const Torus& torus, const Vec3& p);

// The tight object-space box: the center circle's extent along each
// coordinate plus the tube's radius.
Bounds3 torus_bounds(const Torus& torus);

}  // namespace glint
