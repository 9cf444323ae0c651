// Packet traversal: up to kPacketSize (16) coherent rays through one wide
// BVH together. Here: the 16-lane SIMD helpers; the packet's node test, one
// test of a node's children for all its rays by interval arithmetic over
// their origins and inverse directions (it holds every ray's own slab
// distances: float rounding is monotonic); and each ray's own box test of a
// leaf child. The mesh packet kernel (ray_packets.cpp) and the object BVH's
// packets (object_bvh.cpp, through the traversals below, whose leaves the
// caller tests ray by ray) share them. AVX2 only: without it the traversals
// answer "not traced" and callers go ray by ray. Internal.
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "glint/accel/ray_packets.h"
#include "glint/accel/wide_bvh.h"

namespace glint {

#if defined(__AVX2__)

namespace simd16 {


// The packet's 16 rays as SIMD lanes: one AVX-512 register where the CPU
// has them, else two AVX halves. Masks are AVX-512 mask registers or AVX
// vectors of all-ones lanes; `bits` gives them as an integer, bit i for ray i.
#if defined(__AVX512F__)
struct F16 {
  __m512 v;
};
struct I16 {
  __m512i v;
};
using M16 = __mmask16;
inline F16 load16(const float* p) { return {_mm512_load_ps(p)}; }
inline void store16(float* p, F16 a) { _mm512_store_ps(p, a.v); }
inline F16 splat16(float x) { return {_mm512_set1_ps(x)}; }
inline F16 operator+(F16 a, F16 b) { return {_mm512_add_ps(a.v, b.v)}; }
inline F16 operator-(F16 a, F16 b) { return {_mm512_sub_ps(a.v, b.v)}; }
inline F16 operator*(F16 a, F16 b) { return {_mm512_mul_ps(a.v, b.v)}; }
inline F16 operator/(F16 a, F16 b) { return {_mm512_div_ps(a.v, b.v)}; }
inline F16 min16(F16 a, F16 b) { return {_mm512_min_ps(a.v, b.v)}; }
inline F16 max16(F16 a, F16 b) { return {_mm512_max_ps(a.v, b.v)}; }
template <int kCmp>
inline M16 compare16(F16 a, F16 b) {
  return _mm512_cmp_ps_mask(a.v, b.v, kCmp);
}
inline M16 and16(M16 a, M16 b) { return a & b; }
inline M16 or16(M16 a, M16 b) { return a | b; }
inline M16 andnot16(M16 a, M16 b) { return static_cast<M16>(~a & b); }  // b and not a
inline int bits16(M16 m) { return m; }
inline M16 mask16(int bits) { return static_cast<M16>(bits); }
inline F16 select16(M16 m, F16 yes, F16 no) { return {_mm512_mask_blend_ps(m, no.v, yes.v)}; }
inline I16 splat16i(uint32_t x) { return {_mm512_set1_epi32(static_cast<int>(x))}; }
inline I16 select16(M16 m, I16 yes, I16 no) { return {_mm512_mask_blend_epi32(m, no.v, yes.v)}; }
inline M16 greater16(I16 a, I16 b) { return _mm512_cmpgt_epi32_mask(a.v, b.v); }
inline I16 load16(const uint32_t* p) { return {_mm512_load_si512(p)}; }
inline void store16(uint32_t* p, I16 a) { _mm512_store_si512(p, a.v); }
inline float max_lane(F16 a) { return _mm512_reduce_max_ps(a.v); }
inline float min_lane(F16 a) { return _mm512_reduce_min_ps(a.v); }
// Lanes 0-3 from q0, 4-7 from q1, and so on.
inline F16 from_quads(__m128 q0, __m128 q1, __m128 q2, __m128 q3) {
  const __m512 low = _mm512_insertf32x4(_mm512_castps128_ps512(q0), q1, 1);
  return {_mm512_insertf32x4(_mm512_insertf32x4(low, q2, 2), q3, 3)};
}
// The float one step nearer zero than `a` in each lane of `m` (its bits
// less one: the caller leaves zeros and NaNs out of `m`, which that would
// turn into NaNs and infinities). `m` as compare16 gives it (in AVX lanes,
// all ones or all zeros).
inline F16 step_toward_zero16(M16 m, F16 a) {
  return {_mm512_castsi512_ps(
      _mm512_mask_sub_epi32(_mm512_castps_si512(a.v), m, _mm512_castps_si512(a.v), _mm512_set1_epi32(1)))};
}
#else
struct F16 {
  __m256 lo, hi;
};
struct I16 {
  __m256i lo, hi;
};
using M16 = F16;
inline F16 load16(const float* p) { return {_mm256_load_ps(p), _mm256_load_ps(p + 8)}; }
inline void store16(float* p, F16 a) {
  _mm256_store_ps(p, a.lo);
  _mm256_store_ps(p + 8, a.hi);
}
inline F16 splat16(float x) { return {_mm256_set1_ps(x), _mm256_set1_ps(x)}; }
inline F16 operator+(F16 a, F16 b) { return {_mm256_add_ps(a.lo, b.lo), _mm256_add_ps(a.hi, b.hi)}; }
inline F16 operator-(F16 a, F16 b) { return {_mm256_sub_ps(a.lo, b.lo), _mm256_sub_ps(a.hi, b.hi)}; }
inline F16 operator*(F16 a, F16 b) { return {_mm256_mul_ps(a.lo, b.lo), _mm256_mul_ps(a.hi, b.hi)}; }
inline F16 operator/(F16 a, F16 b) { return {_mm256_div_ps(a.lo, b.lo), _mm256_div_ps(a.hi, b.hi)}; }
inline F16 min16(F16 a, F16 b) { return {_mm256_min_ps(a.lo, b.lo), _mm256_min_ps(a.hi, b.hi)}; }
inline F16 max16(F16 a, F16 b) { return {_mm256_max_ps(a.lo, b.lo), _mm256_max_ps(a.hi, b.hi)}; }
template <int kCmp>
inline M16 compare16(F16 a, F16 b) {
  return {_mm256_cmp_ps(a.lo, b.lo, kCmp), _mm256_cmp_ps(a.hi, b.hi, kCmp)};
}
inline M16 and16(M16 a, M16 b) { return {_mm256_and_ps(a.lo, b.lo), _mm256_and_ps(a.hi, b.hi)}; }
inline M16 or16(M16 a, M16 b) { return {_mm256_or_ps(a.lo, b.lo), _mm256_or_ps(a.hi, b.hi)}; }
inline M16 andnot16(M16 a, M16 b) { return {_mm256_andnot_ps(a.lo, b.lo), _mm256_andnot_ps(a.hi, b.hi)}; }
inline int bits16(M16 m) { return _mm256_movemask_ps(m.lo) | _mm256_movemask_ps(m.hi) << 8; }
inline M16 mask16(int bits) {
  const __m256i lane_bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  auto half = [&](int b) {
    const __m256i set = _mm256_and_si256(_mm256_set1_epi32(b), lane_bit);
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lane_bit));
  };
  return {half(bits & 0xff), half(bits >> 8 & 0xff)};
}
inline F16 select16(M16 m, F16 yes, F16 no) {
  return {_mm256_blendv_ps(no.lo, yes.lo, m.lo), _mm256_blendv_ps(no.hi, yes.hi, m.hi)};
}
inline I16 splat16i(uint32_t x) {
  return {_mm256_set1_epi32(static_cast<int>(x)), _mm256_set1_epi32(static_cast<int>(x))};
}
inline I16 select16(M16 m, I16 yes, I16 no) {
  auto half = [](__m256 mask, __m256i y, __m256i n) {
    return _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(n), _mm256_castsi256_ps(y), mask));
  };
  return {half(m.lo, yes.lo, no.lo), half(m.hi, yes.hi, no.hi)};
}
inline M16 greater16(I16 a, I16 b) {
  return {_mm256_castsi256_ps(_mm256_cmpgt_epi32(a.lo, b.lo)), _mm256_castsi256_ps(_mm256_cmpgt_epi32(a.hi, b.hi))};
}
inline I16 load16(const uint32_t* p) {
  return {_mm256_load_si256(reinterpret_cast<const __m256i*>(p)),
          _mm256_load_si256(reinterpret_cast<const __m256i*>(p + 8))};
}
inline void store16(uint32_t* p, I16 a) {
  _mm256_store_si256(reinterpret_cast<__m256i*>(p), a.lo);
  _mm256_store_si256(reinterpret_cast<__m256i*>(p + 8), a.hi);
}
inline float max_lane(F16 a) {
  alignas(32) float v[8];
  _mm256_store_ps(v, _mm256_max_ps(a.lo, a.hi));
  return *std::max_element(v, v + 8);
}
inline float min_lane(F16 a) {
  alignas(32) float v[8];
  _mm256_store_ps(v, _mm256_min_ps(a.lo, a.hi));
  return *std::min_element(v, v + 8);
}
inline F16 from_quads(__m128 q0, __m128 q1, __m128 q2, __m128 q3) {
  return {_mm256_set_m128(q1, q0), _mm256_set_m128(q3, q2)};
}
inline F16 step_toward_zero16(M16 m, F16 a) {
  // All-ones lanes are -1 as integers: adding the mask subtracts one there.
  auto half = [](__m256 mask, __m256 x) {
    return _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(x), _mm256_castps_si256(mask)));
  };
  return {half(m.lo, a.lo), half(m.hi, a.hi)};
}
#endif

}  // namespace simd16

// The packet's constants for box tests.
struct PacketBoxes {
  bool negative[3];               // the rays' direction signs (all alike)
  simd16::F16 origin[3], inv_dir[3];
  simd16::F16 box_t_min;          // boxes are entered from t_min scaled down a little (wide_bvh.h)
  // Per axis, the origin and inverse direction bounds of the node test.
  __m256 near_origin[3], far_origin[3], inv_a[3], inv_b[3], near_row_mask[3];
  __m256 node_t_min;
  int active;  // bit i for each ray in use
};

// False when the packet's rays differ in the sign of a direction component:
// the node test needs one near and one far side per axis.
inline bool packet_direction_signs(const RayPacket& p, bool (&negative)[3]) {
  for (int a = 0; a < 3; ++a) negative[a] = std::signbit(p.inv_direction[a][0]);
  for (int i = 1; i < kPacketSize; ++i)
    for (int a = 0; a < 3; ++a)
      if (std::signbit(p.inv_direction[a][i]) != negative[a]) return false;
  return true;
}

inline PacketBoxes make_packet_boxes(const RayPacket& p, const bool (&negative)[3]) {
  using namespace simd16;
  PacketBoxes b;
  for (int a = 0; a < 3; ++a) {
    b.negative[a] = negative[a];
    b.origin[a] = load16(p.origin[a]);
    b.inv_dir[a] = load16(p.inv_direction[a]);
  }
  b.box_t_min = load16(p.t_min) * splat16(1.0f - 0x1p-20f) - splat16(1e-30f);
  // t = (plane - o) * inv. With inv > 0 it falls as o grows: the near bound
  // takes the largest origin, the far bound the smallest; with inv < 0 the
  // other way round. The sign of (plane - o) picks the inverse: both products
  // are taken and the lower (near) or higher (far) kept.
  for (int a = 0; a < 3; ++a) {
    const float o_lo = min_lane(b.origin[a]), o_hi = max_lane(b.origin[a]);
    b.near_origin[a] = _mm256_set1_ps(negative[a] ? o_lo : o_hi);
    b.far_origin[a] = _mm256_set1_ps(negative[a] ? o_hi : o_lo);
    b.inv_a[a] = _mm256_set1_ps(min_lane(b.inv_dir[a]));
    b.inv_b[a] = _mm256_set1_ps(max_lane(b.inv_dir[a]));
    b.near_row_mask[a] = _mm256_castsi256_ps(_mm256_set1_epi32(negative[a] ? -1 : 0));
  }
  b.node_t_min = _mm256_set1_ps(min_lane(b.box_t_min));
  b.active = p.count >= kPacketSize ? (1 << kPacketSize) - 1 : (1 << p.count) - 1;
  return b;
}

// The children of `n` that some ray may hit before `node_t_max` (the
// farthest any ray still looks), as a bit mask; `t` gets their entry
// distances (the packet's nearest).
inline int packet_children(const PacketBoxes& b, const BvhNode& n, float node_t_max, float* t) {
  static_assert(kBvhWidth == 8, "the packet's node test is 8 children wide");
  const __m256 minus_inf = _mm256_set1_ps(-INFINITY), plus_inf = _mm256_set1_ps(INFINITY);
  __m256 lo_t = b.node_t_min, hi_t = _mm256_set1_ps(node_t_max);
  for (int a = 0; a < 3; ++a) {
    const __m256 lo = _mm256_load_ps(n.bounds[2 * a]), hi = _mm256_load_ps(n.bounds[2 * a + 1]);
    const __m256 near_plane = _mm256_blendv_ps(lo, hi, b.near_row_mask[a]);
    const __m256 far_plane = _mm256_blendv_ps(hi, lo, b.near_row_mask[a]);
    const __m256 dn = _mm256_sub_ps(near_plane, b.near_origin[a]), df = _mm256_sub_ps(far_plane, b.far_origin[a]);
    const __m256 na = _mm256_mul_ps(dn, b.inv_a[a]), nb = _mm256_mul_ps(dn, b.inv_b[a]);
    const __m256 fa = _mm256_mul_ps(df, b.inv_a[a]), fb = _mm256_mul_ps(df, b.inv_b[a]);
    // 0 * inf (a ray parallel to the slab, starting on it) bounds nothing.
    const __m256 t0 = _mm256_blendv_ps(_mm256_min_ps(na, nb), minus_inf, _mm256_cmp_ps(na, nb, _CMP_UNORD_Q));
    const __m256 t1 = _mm256_blendv_ps(_mm256_max_ps(fa, fb), plus_inf, _mm256_cmp_ps(fa, fb, _CMP_UNORD_Q));
    lo_t = _mm256_max_ps(t0, lo_t);
    hi_t = _mm256_min_ps(t1, hi_t);
  }
  hi_t = _mm256_mul_ps(hi_t, _mm256_set1_ps(1.0f + 4.0f * 0x1p-23f));  // as hit_children does
  _mm256_store_ps(t, lo_t);
  return _mm256_movemask_ps(_mm256_cmp_ps(lo_t, hi_t, _CMP_LE_OQ));
}

// Each ray's own box test of child `c` of `n` (the node test only says some
// ray may hit it), up to the rays' `t_max`: the rays that pass, as a bit mask.
inline int packet_rays_hitting(const PacketBoxes& b, const BvhNode& n, int c, simd16::F16 t_max) {
  using namespace simd16;
  F16 lo_t = b.box_t_min, hi_t = t_max;
  for (int a = 0; a < 3; ++a) {
    const F16 near_plane = splat16(n.bounds[2 * a + (b.negative[a] ? 1 : 0)][c]);
    const F16 far_plane = splat16(n.bounds[2 * a + (b.negative[a] ? 0 : 1)][c]);
    lo_t = max16((near_plane - b.origin[a]) * b.inv_dir[a], lo_t);
    hi_t = min16((far_plane - b.origin[a]) * b.inv_dir[a], hi_t);
  }
  hi_t = hi_t * splat16(1.0f + 4.0f * 0x1p-23f);  // as hit_children does
  return bits16(compare16<_CMP_LE_OQ>(lo_t, hi_t)) & b.active;
}

// Closest hits of a packet through `bvh`, whose leaves the caller tests ray
// by ray: `leaf(first, count, rays)` tests the leaf (first/count as stored in
// the node) against each ray i of the bit mask `rays` (those whose own box
// test reaches it), lowers p.t_max[i] (rounded as clamp_to_float rounds) to
// a nearer hit, and returns the rays it lowered. Children are visited near
// to far for the packet. p.t_max of unused rays is -inf (make_ray_packet).
// `prefetch(first, count)` is told of each leaf as it is pushed.
// False (nothing traced) when the rays' direction signs differ.
template <class LeafFn, class PrefetchFn = NoPrefetch>
bool traverse_packet_closest(const Bvh& bvh, RayPacket& p, LeafFn&& leaf, PrefetchFn&& prefetch = {}) {
  using namespace simd16;
  bool negative[3];
  if (!packet_direction_signs(p, negative)) return false;
  if (bvh.nodes.empty()) return true;
  const PacketBoxes boxes = make_packet_boxes(p, negative);
  F16 t_max = load16(p.t_max);
  float node_t_max = max_lane(t_max);
  struct Entry {
    uint32_t child, count;
    float t;
    int rays;  // for a leaf: the rays whose own box test passed
  };
  Entry stack[kTraversalStack];
  int top = 0;
  Entry e{0, 0, -INFINITY, 0};
  for (;;) {
    if (e.count > 0) {
      if (leaf(e.child, e.count, e.rays)) {
        t_max = load16(p.t_max);
        node_t_max = max_lane(t_max);
      }
    } else {
      const BvhNode& n = bvh.nodes[e.child];
      alignas(32) float t[kBvhWidth];
      int mask = packet_children(boxes, n, node_t_max, t);
      const int first = top;
      while (mask) {
        const int i = __builtin_ctz(mask);
        mask &= mask - 1;
        const Entry h{n.child[i], n.count[i], t[i], n.count[i] ? packet_rays_hitting(boxes, n, i, t_max) : 0};
        if (h.count && !h.rays) continue;
        if (h.count) prefetch(h.child, h.count);  // on its way while the others are ordered
        int j = top++;  // sorted far to near
        while (j > first && stack[j - 1].t < h.t) {
          stack[j] = stack[j - 1];
          --j;
        }
        stack[j] = h;
      }
      if (top > first) {
        e = stack[--top];
        continue;
      }
    }
    // Next: the nearest pushed entry still in front of some ray's hit.
    bool more = false;
    while (top > 0 && !more) {
      e = stack[--top];
      more = e.t <= node_t_max * (1.0f + 0x1p-20f);
    }
    if (!more) return true;
  }
}

// Any hits of a packet through `bvh`: `leaf(first, count, rays)` tests the
// leaf against each ray of the bit mask `rays` (still open, and reaching it
// by their own box test) and returns those it found blocked, which go no
// further. The blocked rays as a bit mask, or -1 (nothing traced) when the
// rays' direction signs differ.
template <class LeafFn>
int traverse_packet_any(const Bvh& bvh, const RayPacket& p, LeafFn&& leaf) {
  using namespace simd16;
  bool negative[3];
  if (!packet_direction_signs(p, negative)) return -1;
  if (bvh.nodes.empty()) return 0;
  const PacketBoxes boxes = make_packet_boxes(p, negative);
  const F16 t_max = load16(p.t_max);
  const float node_t_max = max_lane(t_max);
  int open = boxes.active;
  struct Entry {
    uint32_t child, count;
    int rays;
  };
  Entry stack[kTraversalStack];
  int top = 0;
  Entry e{0, 0, 0};
  for (;;) {
    if (e.count > 0) {
      if (const int rays = e.rays & open) {
        open &= ~leaf(e.child, e.count, rays);
        if (!open) break;
      }
    } else {
      const BvhNode& n = bvh.nodes[e.child];
      alignas(32) float t[kBvhWidth];
      int mask = packet_children(boxes, n, node_t_max, t);
      while (mask) {
        const int i = __builtin_ctz(mask);
        mask &= mask - 1;
        const Entry h{n.child[i], n.count[i], n.count[i] ? packet_rays_hitting(boxes, n, i, t_max) & open : open};
        if (h.rays) stack[top++] = h;
      }
    }
    if (top == 0) break;
    e = stack[--top];
  }
  return boxes.active & ~open;
}

#else

template <class LeafFn, class PrefetchFn = NoPrefetch>
bool traverse_packet_closest(const Bvh&, RayPacket&, LeafFn&&, PrefetchFn&& = {}) {
  return false;
}
template <class LeafFn>
int traverse_packet_any(const Bvh&, const RayPacket&, LeafFn&&) {
  return -1;
}

#endif

}  // namespace glint
