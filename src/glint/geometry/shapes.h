// Ray/shape intersection for the analytic shapes: each returns the nearest
// distance t in the ray's open interval (t_min, t_max), or nothing. Rays are
// in the shape's own space; directions need not be unit length.
#pragma once

#include <optional>

#include "glint/geometry/triangle_shear.h"
#include "glint/math/ray.h"
#include "glint/scene/scene.h"

namespace glint {

std::optional<double> intersect_sphere(const Sphere& s, const Ray& ray);
std::optional<double> intersect_plane(const Plane& p, const Ray& ray);

// Watertight (Woop et al. 2013): a ray through an edge or vertex shared by
// triangles hits at least one of them.
std::optional<TriangleHit> intersect_triangle(const Triangle& tri, const Ray& ray);
// triangle_plane_hit (the plane crossing, for refining float hits) is in
// triangle_shear.h.

struct BoxHit { double t; int face; };  // face = 2*axis + (1 if the max side)
std::optional<BoxHit> intersect_box(const Box& box, const Ray& ray);

// Outward unit normal of a box face.
inline Vec3 box_face_normal(int face) {
  Vec3 n(0.0);
  n[face / 2] = (face & 1) ? 1.0 : -1.0;
  return n;
}

}  // namespace glint
