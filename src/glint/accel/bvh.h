// Bvh: our bounding volume hierarchy. Built by binned SAH as a binary tree,
// then collapsed into 4-wide nodes whose four child boxes are tested at once
// with SSE. Leaves are ranges of a reordered primitive-index array. It knows
// only boxes: callers pass the per-primitive test, so one traversal serves
// spheres, boxes and triangles alike.
#pragma once

#include <immintrin.h>

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "glint/math/bounds.h"
#include "glint/math/ray.h"

namespace glint {

// Four child boxes in SoA layout (bounds[axis*2 + 0/1][child] = lo/hi).
// child[i] is a node index when count[i] == 0, else the first primitive of
// a leaf of count[i] primitives; unused slots have an empty box.
struct alignas(64) Bvh4Node {
  float bounds[6][4];
  uint32_t child[4];
  uint32_t count[4];
};
static_assert(sizeof(Bvh4Node) == 128);

struct BvhBuildOptions {
  int max_leaf_size = 4;
  int threads = 0;  // 0: all cores
  // Leaves are tested this many primitives at a time (SIMD triangle blocks):
  // the SAH counts a leaf's cost in blocks, so it fills them.
  int block_size = 1;
};

struct Bvh {
  std::vector<Bvh4Node> nodes;       // nodes[0] is the root
  std::vector<uint32_t> primitives;  // leaf ranges index this; values are caller's ids
  bool empty() const { return nodes.empty(); }
};

// Builds over primitive i = 0..bounds.size()-1 with the given world bounds.
// Primitives with empty or non-finite bounds are left out. Node boxes are
// float, rounded outward and padded by ~1e-6 of the scene's extent (origin
// included), so the float slab test never misses what the double tests hit.
Bvh build_bvh(std::span<const Bounds3> bounds, const BvhBuildOptions& options = {},
              const Vec3& origin_hint = Vec3(0.0));

// Per-ray constants for the 4-wide slab test.
struct RaySlabs4 {
  __m128 origin[3], inv_dir[3];
  int near_lo[3];  // row of bounds[] holding the near plane per axis
  explicit RaySlabs4(const Ray& ray) {
    for (int a = 0; a < 3; ++a) {
      const float inv = static_cast<float>(1.0 / ray.direction[a]);
      origin[a] = _mm_set1_ps(static_cast<float>(ray.origin[a]));
      inv_dir[a] = _mm_set1_ps(inv);
      // From the inverse, so a direction of -0.0 (inverse -inf) counts as negative.
      near_lo[a] = std::signbit(inv) ? 1 : 0;
    }
  }
};

// Bit i set when the ray overlaps child i within (t_min, t_max); `t_near`
// gets the entry distances.
inline int hit_children(const Bvh4Node& n, const RaySlabs4& r, float t_min, float t_max, __m128& t_near) {
  __m128 lo_t = _mm_set1_ps(t_min), hi_t = _mm_set1_ps(t_max);
  for (int a = 0; a < 3; ++a) {
    const __m128 near_plane = _mm_load_ps(n.bounds[2 * a + r.near_lo[a]]);
    const __m128 far_plane = _mm_load_ps(n.bounds[2 * a + 1 - r.near_lo[a]]);
    const __m128 t0 = _mm_mul_ps(_mm_sub_ps(near_plane, r.origin[a]), r.inv_dir[a]);
    const __m128 t1 = _mm_mul_ps(_mm_sub_ps(far_plane, r.origin[a]), r.inv_dir[a]);
    // maxps/minps return the second operand when one is NaN (origin on a slab
    // of a parallel ray): the running interval wins, keeping the box.
    lo_t = _mm_max_ps(t0, lo_t);
    hi_t = _mm_min_ps(t1, hi_t);
  }
  // Widen the far end by a few float ulps: the slab arithmetic rounds.
  hi_t = _mm_mul_ps(hi_t, _mm_set1_ps(1.0f + 4.0f * 0x1p-23f));
  t_near = lo_t;
  return _mm_movemask_ps(_mm_cmple_ps(lo_t, hi_t));
}

inline float clamp_to_float(double t) {
  return t >= 3.0e38 ? INFINITY : static_cast<float>(t);
}

// Closest hit over leaves: `leaf(first, count, ray)` tests a leaf's range
// (first/count as stored in the node) and returns true after shrinking
// ray.t_max to a nearer hit. Children are visited near to far.
template <class LeafFn>
bool traverse_closest_leaves(const Bvh& bvh, Ray& ray, LeafFn&& leaf) {
  if (bvh.nodes.empty()) return false;
  const RaySlabs4 slabs(ray);
  struct Entry { uint32_t child, count; float t; };
  Entry stack[256];
  int top = 0;
  bool found = false;
  const float t_min = static_cast<float>(ray.t_min) * (1.0f - 0x1p-20f) - 1e-30f;
  float t_max = clamp_to_float(ray.t_max);
  stack[top++] = {0, 0, -INFINITY};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t > t_max * (1.0f + 0x1p-20f)) continue;  // a nearer hit was found since
    if (e.count > 0) {
      if (leaf(e.child, e.count, ray)) {
        found = true;
        t_max = clamp_to_float(ray.t_max);
      }
      continue;
    }
    const Bvh4Node& n = bvh.nodes[e.child];
    __m128 t_near;
    int mask = hit_children(n, slabs, t_min, t_max, t_near);
    if (!mask) continue;
    alignas(16) float t[4];
    _mm_store_ps(t, t_near);
    // Push far to near so the nearest child is popped first.
    Entry hits[4];
    int k = 0;
    while (mask) {
      const int i = __builtin_ctz(mask);
      mask &= mask - 1;
      Entry h{n.child[i], n.count[i], t[i]};
      int j = k++;
      while (j > 0 && hits[j - 1].t < h.t) {
        hits[j] = hits[j - 1];
        --j;
      }
      hits[j] = h;
    }
    for (int i = 0; i < k; ++i) stack[top++] = hits[i];
  }
  return found;
}

// Closest hit: `intersect(prim, ray)` returns true and shrinks ray.t_max when
// the primitive is hit nearer than ray.t_max.
template <class IntersectFn>
bool traverse_closest(const Bvh& bvh, Ray& ray, IntersectFn&& intersect) {
  return traverse_closest_leaves(bvh, ray, [&](uint32_t first, uint32_t count, Ray& r) {
    bool found = false;
    for (uint32_t i = 0; i < count; ++i) found |= intersect(bvh.primitives[first + i], r);
    return found;
  });
}

// Any hit over leaves: stops at the first leaf for which `leaf(first, count,
// ray)` is true.
template <class LeafFn>
bool traverse_any_leaves(const Bvh& bvh, const Ray& ray, LeafFn&& leaf) {
  if (bvh.nodes.empty()) return false;
  const RaySlabs4 slabs(ray);
  struct Entry { uint32_t child, count; };
  Entry stack[256];
  int top = 0;
  const float t_min = static_cast<float>(ray.t_min) * (1.0f - 0x1p-20f) - 1e-30f;
  const float t_max = clamp_to_float(ray.t_max);
  stack[top++] = {0, 0};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.count > 0) {
      if (leaf(e.child, e.count, ray)) return true;
      continue;
    }
    const Bvh4Node& n = bvh.nodes[e.child];
    __m128 t_near;
    int mask = hit_children(n, slabs, t_min, t_max, t_near);
    while (mask) {
      const int i = __builtin_ctz(mask);
      mask &= mask - 1;
      stack[top++] = {n.child[i], n.count[i]};
    }
  }
  return false;
}

// Any hit: stops at the first primitive for which `hits(prim, ray)` is true.
template <class HitsFn>
bool traverse_any(const Bvh& bvh, const Ray& ray, HitsFn&& hits) {
  return traverse_any_leaves(bvh, ray, [&](uint32_t first, uint32_t count, const Ray& r) {
    for (uint32_t i = 0; i < count; ++i)
      if (hits(bvh.primitives[first + i], r)) return true;
    return false;
  });
}

}  // namespace glint
