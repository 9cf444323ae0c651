// Building a Polygon from the scene file's vertices (and optional vertex
// normals): the checks the format asks for (docs/scene-format.md: at least
// three vertices, the first three not collinear, coplanar within 1e-5 of the
// bounding-box diagonal, no edge crossing another, `normals` only on convex
// polygons) and the triangulation the intersection test walks: a fan
// (0, i, i+1) for a convex polygon, ear clipping for a non-convex one.
#pragma once

#include <string>
#include <vector>

#include "glint/geometry/shape_types.h"

namespace glint {

// Relative distance from the plane of the first three vertices (as a
// fraction of the bounding-box diagonal) below which a vertex counts as on it.
inline constexpr double kPolygonPlanarity = 1e-5;
// Non-convex polygons are checked for crossing edges pair by pair and ear
// clipped, both quadratic in the vertex count: more vertices than this are refused.
inline constexpr size_t kMaxNonConvexPolygonVertices = 10000;

// Polygons of at least this many triangles get a PolygonGrid (geometry/shape_types.h): a
// ray then tests the triangles near where it meets the plane, in the same
// order, so it finds the same hit as testing all of them.
inline constexpr size_t kPolygonGridMinTriangles = 8;

struct PolygonBuild {
  Polygon polygon;                // valid when `error` is empty
  std::string error;              // what is wrong, for a message
  bool error_at_normals = false;  // the problem is the `normals` key, not `vertices`
};

// `normals` empty, or one unit vector per vertex.
PolygonBuild make_polygon(std::vector<Vec3> vertices, std::vector<Vec3> normals);

// Whether the polygon (given by its vertices, in order) turns the same way
// at every vertex and winds once around: then the fan triangulates it.
bool polygon_is_convex(const std::vector<Vec3>& vertices, const Vec3& normal);

}  // namespace glint
