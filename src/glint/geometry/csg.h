// Ray and CSG solid (Csg in shape_types.h): each leaf's spans along the
// ray's whole line (where the ray is inside it), combined up the tree by
// the operations, then the first span end in the ray's interval. A camera
// inside the solid therefore sees its exit; coincident faces are decided
// by the operation at that point, not by rounding order.
#pragma once

#include <optional>

#include "glint/geometry/shape_types.h"
#include "glint/math/ray.h"

namespace glint {

struct CsgHit {
  double t;
  uint32_t leaf;  // into Csg::leaves
  int part;       // the leaf's box face or cone part (0 for spheres and tori)
  bool flip;      // the leaf's normal points into the result (a subtracted solid): turn it
};
// `ray` is in the CSG object's space.
std::optional<CsgHit> intersect_csg(const Csg& csg, const Ray& ray);

// The leaf's outward unit normal at p, in the leaf's own space.
Vec3 csg_leaf_normal(const CsgLeaf& leaf, int part, const Vec3& p_leaf);

// The leaf's bounds in the CSG object's space, and the tree's (a union's is
// its children's union, an intersection's their overlap, a difference's its
// first child's).
Bounds3 csg_leaf_bounds(const CsgLeaf& leaf);
Bounds3 csg_bounds(const Csg& csg);

}  // namespace glint
