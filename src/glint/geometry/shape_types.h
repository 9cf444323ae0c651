// The shapes as plain data, in the space the scene file gives them (world
// space for planes and triangles, object space for the rest): what the scene
// stores (scene/scene.h) and what the intersection tests take
// (geometry/shapes.h), so geometry/ needs nothing of scene/.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "glint/math/bounds.h"
#include "glint/math/transform.h"
#include "glint/math/vec3.h"

namespace glint {

struct Sphere {
  Vec3 center;
  double radius = 1.0;
};
struct Plane {
  Vec3 point;
  Vec3 normal{0, 1, 0};
};  // world space, unit normal
struct Triangle {
  Vec3 v0, v1, v2;
};  // world space
struct Box {
  Vec3 lo, hi;
};  // object space

// A cone frustum between two disks on its axis, in object space: `base` with
// base_radius and `apex` with apex_radius (one of them may be 0: a pointed
// cone). A cylinder is the same shape with equal radii, so both object types
// use this struct and Scene::cones. The axis frame is derived once by
// make_cone, for the intersection test and (u, v).
struct Cone {
  Vec3 base, apex;
  double base_radius = 1, apex_radius = 1;
  bool caps = true;  // closed by a disk at each end whose radius is > 0
  // Derived (make_cone): unit axis from base to apex, its length, and a
  // unit reference direction across the axis where u = 0 (docs: "Surface coordinates").
  Vec3 axis{0, 1, 0};
  double length = 1;
  Vec3 ref_u{1, 0, 0};
};
Cone make_cone(const Vec3& base, const Vec3& apex, double base_radius, double apex_radius, bool caps);

// A flat ring in object space: the points of the plane through `center`
// with unit `normal` whose distance from the center is in [inner_radius, radius].
struct Disk {
  Vec3 center;
  Vec3 normal{0, 1, 0};
  double radius = 1, inner_radius = 0;
};

// A torus in object space: the circle of radius major_radius about `center`
// in the plane whose unit normal is `axis`, swept by a disk of minor_radius
// (0 < minor_radius < major_radius).
struct Torus {
  Vec3 center;
  Vec3 axis{0, 1, 0};
  double major_radius = 1, minor_radius = 0.25;
};

// Constructive solid geometry: a tree whose leaves are closed solids
// (sphere, box, closed cylinder or cone, torus) and whose inner nodes
// combine their children's insides (geometry/csg.h). Leaves carry their own
// material and their transform into the CSG object's space (every level of
// nested transforms composed).
enum class CsgOp : uint8_t { union_of, intersection, difference };  // difference: the first child minus the rest
enum class CsgLeafType : uint8_t { sphere, box, cone, torus };
struct CsgLeaf {
  CsgLeafType type = CsgLeafType::sphere;
  uint32_t material = 0;
  bool cylinder = false;           // a cone leaf that the file called a cylinder
  std::optional<Transform> transform;  // leaf space -> the CSG object's space; nullopt: the identity
  Sphere sphere;
  Box box;
  Cone cone;
  Torus torus;
  std::string name;  // the file's, or empty
};
struct CsgNode {
  bool leaf = false;
  CsgOp op = CsgOp::union_of;
  uint32_t index = 0;              // a leaf: into Csg::leaves
  uint32_t first = 0, count = 0;   // an operation: its children are child_nodes[first, first + count)
};
struct Csg {
  std::vector<CsgNode> nodes;  // nodes[0]: the root operation
  std::vector<uint32_t> child_nodes;
  std::vector<CsgLeaf> leaves;
  Bounds3 bounds;  // in the CSG object's space
};

// A simple planar polygon in object space, triangulated once (a fan when
// convex, ear clipping otherwise) so that rays meet it through the watertight
// triangle test. `normal` is the right-hand-rule normal of the first three
// vertices (unit); `normals`, when given, are unit vertex normals for smooth
// shading (the polygon is then convex and `triangles` is the fan (0, i, i+1)).
struct PolygonGrid;
struct Polygon {
  std::vector<Vec3> vertices;
  std::vector<Vec3> normals;
  std::vector<std::array<uint32_t, 3>> triangles;
  Vec3 normal{0, 0, 1};
  Bounds3 bounds;
  // For polygons of many triangles (make_polygon builds it): which triangles
  // lie near a point of the plane, so a ray tests a few, not all of them.
  std::shared_ptr<const PolygonGrid> grid;
};

// Triangle k of a polygon's triangulation, in the polygon's own space.
inline Triangle polygon_triangle(const Polygon& p, uint32_t k) {
  const std::array<uint32_t, 3>& t = p.triangles[k];
  return {p.vertices[t[0]], p.vertices[t[1]], p.vertices[t[2]]};
}

// A uniform grid over a polygon's bounding box in the two coordinates other
// than its normal's largest one; each cell lists, in ascending order, the
// triangles whose (projected) boxes overlap it.
struct PolygonGrid {
  int u = 0, v = 1;                          // the coordinates (0: x, 1: y, 2: z)
  double lo[2] = {0, 0};                     // the grid's corner
  double cell[2] = {1, 1};                   // a cell's size
  int cells[2] = {1, 1};                     // cells along u and v
  std::vector<uint32_t> first;               // cell c = cu + cells[0] * cv lists items[first[c], first[c + 1])
  std::vector<uint32_t> items;               // triangle indices
  std::vector<std::array<double, 4>> boxes;  // per triangle: lo u, lo v, hi u, hi v
  double deviation = 0;                      // the farthest any vertex is from the plane (normal through vertices[0])
  double diagonal = 0;                       // of the vertices' bounding box
};

}  // namespace glint
