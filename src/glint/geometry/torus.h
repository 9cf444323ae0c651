// Ray/torus intersection. The torus (shape_types.h) is the quartic
// ((|q|^2 + R^2 - r^2)^2 = 4 R^2 |q_plane|^2, q the offset from the center);
// its roots along a ray are found as the roots of the distance to the center
// circle squared minus r^2, whose convex and concave stretches along the ray
// are known in closed form, so that Newton's method started from the right
// end of each stretch can neither miss a crossing nor leave its bracket.
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

// The nearest crossing in the open interval (ray.t_min, ray.t_max), or nothing.
std::optional<double> intersect_torus(const Torus& torus, const Ray& ray);

// Unit outward normal at a point on (or near) the surface: from the nearest
// point of the center circle toward p.
Vec3 torus_normal(const Torus& torus, const Vec3& p);

// The tight object-space box: the center circle's extent along each
// coordinate plus the tube's radius.
Bounds3 torus_bounds(const Torus& torus);

}  // namespace glint
