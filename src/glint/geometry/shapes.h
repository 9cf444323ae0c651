// Ray/shape intersection for the analytic shapes: each returns the nearest
// distance t in the ray's open interval (t_min, t_max), or nothing. Rays are
// in the shape's own space; directions need not be unit length.
#pragma once

#include <optional>

#include "glint/geometry/triangle_shear.h"
#include "glint/math/ray.h"
#include "glint/geometry/shape_types.h"

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

// Cylinders and cones (Cone): which part was hit, as Hit::face.
enum ConePart : int { kConeSide = 0, kConeBaseCap = 1, kConeApexCap = 2 };
struct ConeHit { double t; int part; };
// Exact in double: the lateral quadric and the slab between the end planes
// are each an interval along the ray, and a closed shape is their
// intersection, whose ends are its entry and exit. A ray through the rim
// where side and cap meet therefore always finds one of them (no crack);
// an open shape keeps only the quadric's ends that lie in the slab.
std::optional<ConeHit> intersect_cone(const Cone& cone, const Ray& ray);

std::optional<double> intersect_disk(const Disk& disk, const Ray& ray);

// A polygon through its triangles (watertight triangle test, so the
// triangulation's shared edges let no ray through).
struct PolygonHit { double t, b1, b2; uint32_t triangle; };
std::optional<PolygonHit> intersect_polygon(const Polygon& polygon, const Ray& ray);

}  // namespace glint
