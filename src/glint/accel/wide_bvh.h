// Bvh: our bounding volume hierarchy. Built by binned SAH as a binary tree,
// then collapsed into wide nodes whose child boxes are tested at once: 8-wide
// with AVX where the compiler may use it, else 4-wide with SSE. Leaves are ranges of a reordered primitive-index array.
// It knows only boxes: callers pass the per-primitive test, so one traversal serves spheres, boxes and triangles alike.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "glint/accel/huge_pages.h"
#include "glint/accel/simd_lanes.h"
#include "glint/math/bounds.h"
#include "glint/math/ray.h"

namespace glint {

// The float inverse of a direction component for the slab test. A zero (or
// tiny) component gives +-2^100 rather than infinity: infinity times the
// origin would make inf - inf = NaN in the fused form. 2^100 is a power of
// two, so plane * inverse stays exact, and the slab distances of a parallel
// ray still cull as infinity did (they are +-2^100 times the offset).
inline constexpr float kSlabInverseLimit = 0x1p100f;
inline float slab_inverse(double direction) {
  const float inv = static_cast<float>(1.0 / direction);
  return std::abs(inv) <= kSlabInverseLimit ? inv : std::copysign(kSlabInverseLimit, inv);
}

// kBvhWidth child boxes in SoA layout (bounds[axis*2 + 0/1][child] = lo/hi).
// child[i] is a node index when count[i] == 0, else the first primitive of
// a leaf of count[i] primitives; unused slots have an empty box.
struct alignas(64) BvhNode {
  float bounds[6][kBvhWidth];
  uint32_t child[kBvhWidth];
  uint32_t count[kBvhWidth];
};
static_assert(sizeof(BvhNode) == 32 * kBvhWidth);

struct BvhBuildOptions {
  int max_leaf_size = 4;
  int threads = 0;  // 0: all cores
  // Leaves are tested this many primitives at a time (SIMD triangle blocks):
  // the SAH counts a leaf's cost in blocks, so it fills them.
  int block_size = 1;
};

struct Bvh {
  HugePageVector<BvhNode> nodes;     // nodes[0] is the root
  std::vector<uint32_t> primitives;  // leaf ranges index this; values are caller's ids
  bool empty() const { return nodes.empty(); }
};

// Builds over primitive i = 0..bounds.size()-1 with the given world bounds.
// Primitives with empty or non-finite bounds are left out. Node boxes are
// float, rounded outward and padded by ~1e-6 of the scene's extent (origin
// included), so the float slab test never misses what the double tests hit.
Bvh build_bvh(std::span<const Bounds3> bounds, const BvhBuildOptions& options = {},
              const Vec3& origin_hint = Vec3(0.0));

// A primitive's box in float: exact for float geometry (mesh triangles), so
// the build needs no double boxes (48 bytes a primitive) beside its own.
struct FloatBox {
  float lo[3], hi[3];
};
// As build_bvh, over `count` primitives whose boxes `boxes_of(begin, end,
// out)` writes, those of primitives begin .. end - 1 to out[0 .. end -
// begin): ranges of up to kFloatBoxRange primitives (one call a range, not
// one a primitive: the call was half the time of filling the build's
// boxes). Called from the build's threads at once; must not throw.
inline constexpr size_t kFloatBoxRange = 256;
Bvh build_bvh_over_float_boxes(size_t count, const std::function<void(size_t, size_t, FloatBox*)>& boxes_of,
                               const BvhBuildOptions& options = {}, const Vec3& origin_hint = Vec3(0.0));

// Per-ray constants for the wide slab test.
struct RaySlabs {
  FloatLanes origin[3], inv_dir[3];
  // origin * inv_dir, so a slab distance (plane - origin) * inv_dir is one
  // fused multiply-subtract, plane * inv_dir - origin * inv_dir: three
  // cycles less on the chain from a node's load to its children's.
  FloatLanes origin_scaled[3];
  // False when origin * inv_dir overflows on some axis (a huge origin with a
  // zero or tiny direction component): every fused distance would then be
  // an infinity of one sign and cull every box, so such a ray takes the
  // subtract-then-multiply form.
  bool fused = true;
  // All bits set where the direction is negative on that axis (the near
  // plane is then the box's hi side): a blend picks the planes, which keeps
  // the general-purpose registers free for the traversal.
  FloatLanes negative[3];
  explicit RaySlabs(const Ray& ray) {
    for (int a = 0; a < 3; ++a) {
      const float inv = slab_inverse(ray.direction[a]);
      origin[a] = lanes_set1(static_cast<float>(ray.origin[a]));
      inv_dir[a] = lanes_set1(inv);
      const float scaled = static_cast<float>(ray.origin[a]) * inv;
      origin_scaled[a] = lanes_set1(scaled);
      fused = fused && std::isfinite(scaled);
      // From the inverse, so a direction of -0.0 counts as negative.
      negative[a] = lanes_set1(std::bit_cast<float>(std::signbit(inv) ? ~0u : 0u));
    }
  }
};

#if defined(__FMA__)
inline constexpr bool kHaveFusedSlabs = true;
#else
inline constexpr bool kHaveFusedSlabs = false;
#endif

// The slab distance of `plane`: (plane - origin) * inv_dir. Fused
// (`kFused`, when the ray's RaySlabs::fused allows it) it is plane * inv_dir
// - origin * inv_dir, whose one rounding of origin * inv_dir moves the plane
// by at most an ulp of the origin, as the subtraction's rounding does: the
// far side's widening in hit_children covers both (a test sees a small mesh
// from 10^5 radii away).
template <bool kFused>
inline FloatLanes slab_distance(FloatLanes plane, const RaySlabs& r, int a) {
#if defined(__FMA__)
  if constexpr (kFused) return lanes_fmsub(plane, r.inv_dir[a], r.origin_scaled[a]);
#endif
  return lanes_mul(lanes_sub(plane, r.origin[a]), r.inv_dir[a]);
}

// Bit i set when the ray overlaps child i within (t_min, t_max); `t_near`
// gets the entry distances.
template <bool kFused>
inline int hit_children(const BvhNode& n, const RaySlabs& r, FloatLanes t_min, float t_max, FloatLanes& t_near) {
  FloatLanes lo_t = t_min, hi_t = lanes_set1(t_max);
  for (int a = 0; a < 3; ++a) {
    const FloatLanes lo = lanes_load(n.bounds[2 * a]), hi = lanes_load(n.bounds[2 * a + 1]);
    const FloatLanes near_plane = lanes_blend(lo, hi, r.negative[a]);
    const FloatLanes far_plane = lanes_blend(hi, lo, r.negative[a]);
    const FloatLanes t0 = slab_distance<kFused>(near_plane, r, a);
    const FloatLanes t1 = slab_distance<kFused>(far_plane, r, a);
    // max/min return the second operand when one is NaN (0 * inf, inf -
    // inf): the running interval wins, keeping the box.
    lo_t = lanes_max(t0, lo_t);
    hi_t = lanes_min(t1, hi_t);
  }
  // Widen the far end by a few float ulps: the slab arithmetic rounds.
  hi_t = lanes_mul(hi_t, lanes_set1(1.0f + 4.0f * 0x1p-23f));
  t_near = lo_t;
  return lanes_le_mask(lo_t, hi_t);
}

// Each node visited pushes at most kBvhWidth - 1 more entries than it pops,
// and the build bounds the depth to 60 binary levels (wide_bvh_build.cpp), so the
// wide tree is at most 60 deep too.
inline constexpr int kTraversalStack = (kBvhWidth - 1) * 64;

inline float clamp_to_float(double t) { return t >= 3.0e38 ? INFINITY : static_cast<float>(t); }

// std::nextafter(x, 0.0f) without the library call: one step toward zero
// (+inf gives the largest float; zero and NaN stay).
inline float float_toward_zero(float x) {
  if (x == 0.0f || x != x) return x;
  return std::bit_cast<float>(std::bit_cast<uint32_t>(x) - 1u);
}

// Closest hit over leaves: `leaf(first, count, ray)` tests a leaf's range
// (first/count as stored in the node) and returns true after shrinking
// ray.t_max to a nearer hit. Children are visited near to far.
// `prefetch(first, count)` is told of every leaf found hit, before the
// children are ordered: its data is then on its way when the leaf's turn comes.
struct NoPrefetch {
  void operator()(uint32_t, uint32_t) const {}
};

// traverse_closest_leaves for one form of the slab distances (RaySlabs::fused).
template <bool kFused, class LeafFn, class PrefetchFn>
bool traverse_closest_with(const Bvh& bvh, const RaySlabs& slabs, Ray& ray, LeafFn& leaf, PrefetchFn& prefetch) {
  struct Entry {
    uint32_t child, count;
    float t;
  };
  Entry stack[kTraversalStack];
  int top = 0;
  bool found = false;
  const FloatLanes t_min = lanes_set1(static_cast<float>(ray.t_min) * (1.0f - 0x1p-20f) - 1e-30f);
  float t_max = clamp_to_float(ray.t_max);
  // The nearest child is visited next without a trip through the stack; the
  // order of visits is the same as pushing every child far to near.
  Entry e{0, 0, -INFINITY};
  for (;;) {
    if (e.count > 0) {
      if (leaf(e.child, e.count, ray)) {
        found = true;
        t_max = clamp_to_float(ray.t_max);
      }
    } else {
      const BvhNode& n = bvh.nodes[e.child];
      FloatLanes t_near;
      int mask = hit_children<kFused>(n, slabs, t_min, t_max, t_near);
      if (mask) {
        alignas(32) float t[kBvhWidth];
        lanes_store(t, t_near);
        // One or two children hit are the common cases: no sort.
        const int i0 = __builtin_ctz(mask);
        mask &= mask - 1;
        const Entry c0{n.child[i0], n.count[i0], t[i0]};
        if (c0.count) prefetch(c0.child, c0.count);
        if (!mask) {
          e = c0;
          continue;
        }
        const int i1 = __builtin_ctz(mask);
        mask &= mask - 1;
        const Entry c1{n.child[i1], n.count[i1], t[i1]};
        if (c1.count) prefetch(c1.child, c1.count);
        if (!mask) {
          // Ties go to the later child, as the general case below orders them.
          if (c0.t < c1.t) {
            stack[top++] = c1;
            e = c0;
          } else {
            stack[top++] = c0;
            e = c1;
          }
          continue;
        }
        // Three or more: onto the stack, sorted far to near in place.
        const int base = top;
        auto insert = [&](const Entry& h) {
          int j = top++;
          while (j > base && stack[j - 1].t < h.t) {
            stack[j] = stack[j - 1];
            --j;
          }
          stack[j] = h;
        };
        insert(c0);
        insert(c1);
        while (mask) {
          const int i = __builtin_ctz(mask);
          mask &= mask - 1;
          const Entry h{n.child[i], n.count[i], t[i]};
          if (h.count) prefetch(h.child, h.count);
          insert(h);
        }
        e = stack[--top];
        continue;
      }
    }
    // Next: the nearest pushed entry still in front of the nearest hit.
    do {
      if (top == 0) return found;
      e = stack[--top];
    } while (e.t > t_max * (1.0f + 0x1p-20f));
  }
}

template <class LeafFn, class PrefetchFn = NoPrefetch>
bool traverse_closest_leaves(const Bvh& bvh, Ray& ray, LeafFn&& leaf, PrefetchFn&& prefetch = {}) {
  if (bvh.nodes.empty()) return false;
  const RaySlabs slabs(ray);
  if (kHaveFusedSlabs && slabs.fused) return traverse_closest_with<true>(bvh, slabs, ray, leaf, prefetch);
  return traverse_closest_with<false>(bvh, slabs, ray, leaf, prefetch);
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
// traverse_any_leaves for one form of the slab distances (RaySlabs::fused).
template <bool kFused, class LeafFn, class PrefetchFn>
bool traverse_any_with(const Bvh& bvh, const RaySlabs& slabs, const Ray& ray, LeafFn& leaf, PrefetchFn& prefetch) {
  struct Entry {
    uint32_t child, count;
  };
  Entry stack[kTraversalStack];
  int top = 0;
  const FloatLanes t_min = lanes_set1(static_cast<float>(ray.t_min) * (1.0f - 0x1p-20f) - 1e-30f);
  const float t_max = clamp_to_float(ray.t_max);
  // The last child hit is visited next without a trip through the stack (the
  // order of visits is the same as pushing them all).
  Entry e{0, 0};
  for (;;) {
    if (e.count > 0) {
      if (leaf(e.child, e.count, ray)) return true;
    } else {
      const BvhNode& n = bvh.nodes[e.child];
      FloatLanes t_near;
      int mask = hit_children<kFused>(n, slabs, t_min, t_max, t_near);
      if (mask) {
        int last = 0;
        while (mask) {
          last = __builtin_ctz(mask);
          mask &= mask - 1;
          if (n.count[last]) prefetch(n.child[last], n.count[last]);
          if (mask) stack[top++] = {n.child[last], n.count[last]};
        }
        e = {n.child[last], n.count[last]};
        continue;
      }
    }
    if (top == 0) return false;
    e = stack[--top];
  }
}

template <class LeafFn, class PrefetchFn = NoPrefetch>
bool traverse_any_leaves(const Bvh& bvh, const Ray& ray, LeafFn&& leaf, PrefetchFn&& prefetch = {}) {
  if (bvh.nodes.empty()) return false;
  const RaySlabs slabs(ray);
  if (kHaveFusedSlabs && slabs.fused) return traverse_any_with<true>(bvh, slabs, ray, leaf, prefetch);
  return traverse_any_with<false>(bvh, slabs, ray, leaf, prefetch);
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
