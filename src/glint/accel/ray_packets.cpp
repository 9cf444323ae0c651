#include "glint/accel/ray_packets.h"

#include <algorithm>
#include <cmath>

namespace glint {

RayPacket make_ray_packet(const Ray* rays, int count) {
  RayPacket p;
  p.count = count;
  for (int i = 0; i < kPacketSize; ++i) {
    const Ray& r = rays[i < count ? i : 0];  // unused lanes repeat ray 0
    p.origin[0][i] = static_cast<float>(r.origin.x);
    p.origin[1][i] = static_cast<float>(r.origin.y);
    p.origin[2][i] = static_cast<float>(r.origin.z);
    p.direction[0][i] = static_cast<float>(r.direction.x);
    p.direction[1][i] = static_cast<float>(r.direction.y);
    p.direction[2][i] = static_cast<float>(r.direction.z);
    p.t_min[i] = static_cast<float>(r.t_min);
    // Inclusive, as intersect_mesh_bvh. Unused lanes look nowhere, so the
    // packet's farthest distance (which culls nodes) is that of its rays.
    p.t_max[i] = i < count ? float_toward_zero(clamp_to_float(r.t_max)) : -INFINITY;
    p.triangle[i] = kNoTriangle;
  }
  // In float, a row at a time (vectorized): the box tests only need the
  // inverse within an ulp or two (the boxes' padding covers it). Clamped as
  // slab_inverse does.
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < kPacketSize; ++i)
      p.inv_direction[a][i] = std::clamp(1.0f / p.direction[a][i], -kSlabInverseLimit, kSlabInverseLimit);
  return p;
}

#if defined(__AVX2__)

namespace {

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
#endif
static_assert(kPacketSize == 16, "the packet kernel's lanes are 16 rays");

// A leaf reached by this many rays of a packet is tested triangle by
// triangle against all of them at once; by fewer, ray by ray (four triangles
// at once). The threshold hardly matters (4 to 8 measure alike); testing
// every leaf ray by ray is slower.
constexpr int kLeafRaysForSimd = 4;

int dominant_axis(float x, float y, float z) {
  const float ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
  return ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
}

}  // namespace

// glint:long-function: the hot 16-ray packet traversal, kept as one loop on
// purpose: its state (stack, active masks, the lanes' t_max) stays in
// registers across nodes and leaves; not split without a benchmark.
bool intersect_mesh_packet(const MeshBvh& m, RayPacket& p) {
  if (m.bvh.nodes.empty()) return true;
  // One shear frame and one set of direction signs for the whole packet.
  const int kz = dominant_axis(p.direction[0][0], p.direction[1][0], p.direction[2][0]);
  bool negative[3];
  for (int a = 0; a < 3; ++a) negative[a] = std::signbit(p.inv_direction[a][0]);
  for (int i = 1; i < kPacketSize; ++i) {
    if (dominant_axis(p.direction[0][i], p.direction[1][i], p.direction[2][i]) != kz) return false;
    for (int a = 0; a < 3; ++a)
      if (std::signbit(p.inv_direction[a][i]) != negative[a]) return false;
  }
  const int kx = kz == 2 ? 0 : kz + 1;
  const int ky = kx == 2 ? 0 : kx + 1;

  // Per-lane constants, computed as the single-ray kernels compute them.
  alignas(64) float sx[kPacketSize], sy[kPacketSize], sz[kPacketSize];
  for (int i = 0; i < kPacketSize; ++i) {
    sz[i] = 1.0f / p.direction[kz][i];
    sx[i] = -p.direction[kx][i] * sz[i];
    sy[i] = -p.direction[ky][i] * sz[i];
  }
  F16 origin[3];
  for (int a = 0; a < 3; ++a) origin[a] = load16(p.origin[a]);
  const F16 shear_x = load16(sx), shear_y = load16(sy), shear_z = load16(sz);
  // Boxes are entered from t_min scaled down a little (wide_bvh.h), triangles from t_min.
  const F16 t_min = load16(p.t_min);
  const F16 box_t_min = t_min * splat16(1.0f - 0x1p-20f) - splat16(1e-30f);
  F16 t_max = load16(p.t_max);
  I16 hit_triangle = splat16i(kNoHitId);
  I16 hit_slot = splat16i(0);  // block * 4 + lane of the hit

  // Nodes are tested once for the whole packet, like a single ray, with
  // interval arithmetic: per axis, the packet's origins and inverse
  // directions as [lo, hi] ranges give a t range that holds every ray's own
  // slab distances (float rounding is monotonic, so it holds for the rounded
  // values too). A child is entered when any ray may hit it; leaves are then
  // tested against every ray, so a ray's hits are exactly its own.
  float o_lo[3], o_hi[3], inv_lo[3], inv_hi[3];
  for (int a = 0; a < 3; ++a) {
    o_lo[a] = min_lane(origin[a]);
    o_hi[a] = max_lane(origin[a]);
    const F16 inv = load16(p.inv_direction[a]);
    inv_lo[a] = min_lane(inv);
    inv_hi[a] = max_lane(inv);
  }
  // t = (plane - o) * inv. With inv > 0 it falls as o grows: the near bound
  // takes the largest origin, the far bound the smallest; with inv < 0 the
  // other way round. The sign of (plane - o) picks the inverse: both products
  // are taken and the lower (near) or higher (far) kept.
  __m256 near_origin[3], far_origin[3], inv_a[3], inv_b[3], near_row_mask[3];
  for (int a = 0; a < 3; ++a) {
    near_origin[a] = _mm256_set1_ps(negative[a] ? o_lo[a] : o_hi[a]);
    far_origin[a] = _mm256_set1_ps(negative[a] ? o_hi[a] : o_lo[a]);
    inv_a[a] = _mm256_set1_ps(inv_lo[a]);
    inv_b[a] = _mm256_set1_ps(inv_hi[a]);
    near_row_mask[a] = _mm256_castsi256_ps(_mm256_set1_epi32(negative[a] ? -1 : 0));
  }
  const __m256 node_t_min = _mm256_set1_ps(min_lane(box_t_min));
  // The farthest any ray still looks (its hit, or its t_max): boxes behind it are skipped.
  float node_t_max = max_lane(t_max);
  const __m256 widen = _mm256_set1_ps(1.0f + 4.0f * 0x1p-23f);
  const __m256 minus_inf = _mm256_set1_ps(-INFINITY), plus_inf = _mm256_set1_ps(INFINITY);
  const int active = p.count >= kPacketSize ? (1 << kPacketSize) - 1 : (1 << p.count) - 1;

  // Per-ray box test of a leaf child (the packet test only says some ray may
  // hit it): the rays that do, as a bit mask.
  F16 inv_dir[3];
  for (int a = 0; a < 3; ++a) inv_dir[a] = load16(p.inv_direction[a]);
  const F16 widen16 = splat16(1.0f + 4.0f * 0x1p-23f);
  auto rays_hitting = [&](const BvhNode& n, int c) {
    F16 lo_t = box_t_min, hi_t = t_max;
    for (int a = 0; a < 3; ++a) {
      const F16 near_plane = splat16(n.bounds[2 * a + (negative[a] ? 1 : 0)][c]);
      const F16 far_plane = splat16(n.bounds[2 * a + (negative[a] ? 0 : 1)][c]);
      lo_t = max16((near_plane - origin[a]) * inv_dir[a], lo_t);
      hi_t = min16((far_plane - origin[a]) * inv_dir[a], hi_t);
    }
    hi_t = hi_t * widen16;  // as hit_children does
    return bits16(compare16<_CMP_LE_OQ>(lo_t, hi_t)) & active;
  };

  // A block against the rays in `mask`, each triangle against all of them at
  // once (worth it when many rays reach the block).
  const F16 zero = splat16(0.0f);
  auto block_all_rays = [&](uint32_t b, int mask) {
    const Triangle4& block = m.blocks[b];
    const M16 in_mask = mask16(mask);
    bool hit = false;
    for (int lane = 0; lane < 4; ++lane) {
      F16 x[3], y[3], z[3];
      for (int v = 0; v < 3; ++v) {
        z[v] = splat16(block.v[v][kz][lane]) - origin[kz];
        x[v] = (splat16(block.v[v][kx][lane]) - origin[kx]) + shear_x * z[v];
        y[v] = (splat16(block.v[v][ky][lane]) - origin[ky]) + shear_y * z[v];
      }
      const F16 e0 = x[1] * y[2] - y[1] * x[2];
      const F16 e1 = x[2] * y[0] - y[2] * x[0];
      const F16 e2 = x[0] * y[1] - y[0] * x[1];
      const M16 any_neg =
          or16(or16(compare16<_CMP_LT_OQ>(e0, zero), compare16<_CMP_LT_OQ>(e1, zero)), compare16<_CMP_LT_OQ>(e2, zero));
      const M16 any_pos =
          or16(or16(compare16<_CMP_GT_OQ>(e0, zero), compare16<_CMP_GT_OQ>(e1, zero)), compare16<_CMP_GT_OQ>(e2, zero));
      const F16 det = (e0 + e1) + e2;
      const F16 t_scaled = ((e0 * z[0] + e1 * z[1]) + e2 * z[2]) * shear_z;
      const F16 t = t_scaled / det;
      M16 valid = andnot16(and16(any_neg, any_pos), compare16<_CMP_NEQ_UQ>(det, zero));
      valid = and16(valid, and16(compare16<_CMP_GT_OQ>(t, t_min), compare16<_CMP_LE_OQ>(t, t_max)));
      // Nearer, or as near with a lower triangle index (as intersect_mesh_bvh).
      const I16 id = splat16i(block.id[lane]);
      valid = and16(valid, or16(compare16<_CMP_LT_OQ>(t, t_max), greater16(hit_triangle, id)));
      valid = and16(valid, in_mask);
      if (bits16(valid)) {
        t_max = select16(valid, t, t_max);
        hit_triangle = select16(valid, id, hit_triangle);
        hit_slot = select16(valid, splat16i(4 * b + static_cast<uint32_t>(lane)), hit_slot);
        hit = true;
      }
    }
    return hit;
  };

  // A block against one ray, its four triangles at once (as intersect_mesh_bvh).
  alignas(64) float ray_t_max[kPacketSize];
  alignas(64) uint32_t ray_triangle[kPacketSize], ray_slot[kPacketSize];
  auto block_one_ray = [&](uint32_t b, int i) {
    const Triangle4& block = m.blocks[b];
    const float origin[3] = {p.origin[0][i], p.origin[1][i], p.origin[2][i]};
    const WatertightRay4 wray(origin, kx, ky, kz, sx[i], sy[i], sz[i]);
    __m128 t;
    int mask = intersect_block(block, wray, _mm_set1_ps(p.t_min[i]), _mm_set1_ps(ray_t_max[i]), t);
    if (!mask) return false;
    alignas(16) float ts[4];
    _mm_store_ps(ts, t);
    bool hit = false;
    for (; mask; mask &= mask - 1) {
      const int lane = __builtin_ctz(mask);
      const uint32_t id = block.id[lane];
      if (ts[lane] < ray_t_max[i] || (ts[lane] == ray_t_max[i] && id < ray_triangle[i])) {
        ray_t_max[i] = ts[lane];
        ray_triangle[i] = id;
        ray_slot[i] = 4 * b + static_cast<uint32_t>(lane);
        hit = true;
      }
    }
    return hit;
  };

  // `mask`: for a leaf, the rays whose own box test passed.
  struct Entry {
    uint32_t child, count;
    float t;
    int mask;
  };
  Entry stack[kTraversalStack];
  int top = 0;
  // As in traverse_closest_leaves: the nearest child is visited next without
  // a trip through the stack.
  Entry e{0, 0, -INFINITY, 0};
  for (;;) {
    if (e.count > 0) {
      bool hit = false;
      if (__builtin_popcount(e.mask) >= kLeafRaysForSimd) {
        for (uint32_t b = e.child; b < e.child + e.count; ++b) hit |= block_all_rays(b, e.mask);
      } else {
        store16(ray_t_max, t_max);
        store16(ray_triangle, hit_triangle);
        store16(ray_slot, hit_slot);
        for (int rays = e.mask; rays; rays &= rays - 1)
          for (uint32_t b = e.child; b < e.child + e.count; ++b) hit |= block_one_ray(b, __builtin_ctz(rays));
        if (hit) {
          t_max = load16(ray_t_max);
          hit_triangle = load16(ray_triangle);
          hit_slot = load16(ray_slot);
        }
      }
      if (hit) node_t_max = max_lane(t_max);
    } else {
      const BvhNode& n = m.bvh.nodes[e.child];
      __m256 lo_t = node_t_min, hi_t = _mm256_set1_ps(node_t_max);
      for (int a = 0; a < 3; ++a) {
        const __m256 lo = _mm256_load_ps(n.bounds[2 * a]), hi = _mm256_load_ps(n.bounds[2 * a + 1]);
        const __m256 near_plane = _mm256_blendv_ps(lo, hi, near_row_mask[a]);
        const __m256 far_plane = _mm256_blendv_ps(hi, lo, near_row_mask[a]);
        const __m256 dn = _mm256_sub_ps(near_plane, near_origin[a]), df = _mm256_sub_ps(far_plane, far_origin[a]);
        const __m256 na = _mm256_mul_ps(dn, inv_a[a]), nb = _mm256_mul_ps(dn, inv_b[a]);
        const __m256 fa = _mm256_mul_ps(df, inv_a[a]), fb = _mm256_mul_ps(df, inv_b[a]);
        // 0 * inf (a ray parallel to the slab, starting on it) bounds nothing.
        const __m256 t0 = _mm256_blendv_ps(_mm256_min_ps(na, nb), minus_inf, _mm256_cmp_ps(na, nb, _CMP_UNORD_Q));
        const __m256 t1 = _mm256_blendv_ps(_mm256_max_ps(fa, fb), plus_inf, _mm256_cmp_ps(fa, fb, _CMP_UNORD_Q));
        lo_t = _mm256_max_ps(t0, lo_t);
        hi_t = _mm256_min_ps(t1, hi_t);
      }
      hi_t = _mm256_mul_ps(hi_t, widen);  // as hit_children does
      int mask = _mm256_movemask_ps(_mm256_cmp_ps(lo_t, hi_t, _CMP_LE_OQ));
      if (mask) {
        alignas(32) float t[kBvhWidth];
        _mm256_store_ps(t, lo_t);
        const int first = top;
        while (mask) {
          const int i = __builtin_ctz(mask);
          mask &= mask - 1;
          const Entry h{n.child[i], n.count[i], t[i], n.count[i] ? rays_hitting(n, i) : 0};
          if (h.count && !h.mask) continue;
          if (h.count) {  // leaf blocks: on their way while the others are ordered
            const char* block = reinterpret_cast<const char*>(&m.blocks[h.child]);
            for (uint32_t line = 0; line < h.count * sizeof(Triangle4); line += 64)
              _mm_prefetch(block + line, _MM_HINT_T0);
          }
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
    }
    // Next: the nearest pushed entry still in front of some ray's hit.
    bool more = false;
    while (top > 0 && !more) {
      e = stack[--top];
      more = e.t <= node_t_max * (1.0f + 0x1p-20f);
    }
    if (!more) break;
  }
  store16(p.t_max, t_max);
  store16(p.triangle, hit_triangle);
  store16(p.slot, hit_slot);
  for (int i = 0; i < kPacketSize; ++i)
    if (p.triangle[i] == kNoHitId) p.triangle[i] = kNoTriangle;
  return true;
}

#else

bool intersect_mesh_packet(const MeshBvh&, RayPacket&) { return false; }

#endif

}  // namespace glint
