// Bvh: our bounding volume hierarchy. A flat vector of 32-byte nodes built by
// binned SAH, plus the primitive indices reordered so each leaf is a range.
// It knows only boxes; callers pass the per-primitive intersection test, so
// one traversal serves spheres, boxes and triangles alike.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "glint/math/bounds.h"

namespace glint {

struct BvhNode {
  float lo[3];
  uint32_t offset;  // leaf: first index into Bvh::primitives; interior: second child
  float hi[3];
  uint16_t count;   // primitives in a leaf; 0 for an interior node (first child = next node)
  uint16_t axis;    // interior: split axis, for front-to-back order
};
static_assert(sizeof(BvhNode) == 32);

struct BvhBuildOptions {
  int max_leaf_size = 8;
  int threads = 0;  // 0: all cores
};

struct Bvh {
  std::vector<BvhNode> nodes;
  std::vector<uint32_t> primitives;  // leaf ranges index this; values are caller's ids

  bool empty() const { return nodes.empty(); }
};

// Builds over primitive i = 0..bounds.size()-1 with the given world bounds.
// Primitives with empty or non-finite bounds are left out.
Bvh build_bvh(std::span<const Bounds3> bounds, const BvhBuildOptions& options = {});

// Per-ray constants for the slab test.
struct RaySlabs {
  Vec3 origin, inv_dir;
  int dir_negative[3];
  explicit RaySlabs(const Ray& ray) : origin(ray.origin) {
    for (int a = 0; a < 3; ++a) {
      inv_dir[a] = 1.0 / ray.direction[a];
      // From the inverse, so a direction of -0.0 (inverse -inf) counts as negative.
      dir_negative[a] = inv_dir[a] < 0.0;
    }
  }
};

// Entry distance of the ray into the node's box if it overlaps (t_min, t_max).
inline bool hit_node(const BvhNode& n, const RaySlabs& r, double t_min, double t_max) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (static_cast<double>(n.lo[a]) - r.origin[a]) * r.inv_dir[a];
    double t1 = (static_cast<double>(n.hi[a]) - r.origin[a]) * r.inv_dir[a];
    if (r.dir_negative[a]) std::swap(t0, t1);
    // Written so a NaN (origin on a slab of a parallel ray) keeps the box.
    t_min = t0 > t_min ? t0 : t_min;
    t_max = t1 < t_max ? t1 : t_max;
  }
  return t_min <= t_max;
}

// Closest hit: `intersect(prim, ray)` returns true and shrinks ray.t_max when
// the primitive is hit nearer than ray.t_max.
template <class IntersectFn>
bool traverse_closest(const Bvh& bvh, Ray& ray, IntersectFn&& intersect) {
  if (bvh.nodes.empty()) return false;
  const RaySlabs slabs(ray);
  uint32_t stack[64];
  int top = 0;
  uint32_t node = 0;
  bool found = false;
  while (true) {
    const BvhNode& n = bvh.nodes[node];
    if (hit_node(n, slabs, ray.t_min, ray.t_max)) {
      if (n.count > 0) {
        for (uint32_t i = 0; i < n.count; ++i)
          found |= intersect(bvh.primitives[n.offset + i], ray);
      } else {
        // Visit the child on the ray's near side first so t_max shrinks early.
        if (slabs.dir_negative[n.axis]) {
          stack[top++] = node + 1;
          node = n.offset;
        } else {
          stack[top++] = n.offset;
          node = node + 1;
        }
        continue;
      }
    }
    if (top == 0) break;
    node = stack[--top];
  }
  return found;
}

// Any hit: stops at the first primitive for which `hits(prim, ray)` is true.
template <class HitsFn>
bool traverse_any(const Bvh& bvh, const Ray& ray, HitsFn&& hits) {
  if (bvh.nodes.empty()) return false;
  const RaySlabs slabs(ray);
  uint32_t stack[64];
  int top = 0;
  uint32_t node = 0;
  while (true) {
    const BvhNode& n = bvh.nodes[node];
    if (hit_node(n, slabs, ray.t_min, ray.t_max)) {
      if (n.count > 0) {
        for (uint32_t i = 0; i < n.count; ++i)
          if (hits(bvh.primitives[n.offset + i], ray)) return true;
      } else {
        stack[top++] = n.offset;
        node = node + 1;
        continue;
      }
    }
    if (top == 0) break;
    node = stack[--top];
  }
  return false;
}

}  // namespace glint
