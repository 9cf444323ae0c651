#include "glint/accel/ray_packets.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "glint/accel/packet_traversal.h"

namespace glint {

RayPacket make_ray_packet_reference(const Ray* rays, int count, PacketTMax t_max_mode) {
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
    const float t_max = clamp_to_float(r.t_max);
    p.t_max[i] = i >= count ? -INFINITY : (t_max_mode == PacketTMax::inclusive ? float_toward_zero(t_max) : t_max);
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

static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Ray) == 8 * sizeof(double) &&
                  offsetof(Ray, direction) == 3 * sizeof(double) && offsetof(Ray, t_max) == 7 * sizeof(double),
              "a Ray is eight doubles: origin, direction, t_min, t_max");

// Four rays' eight doubles (origin, direction, t_min, t_max) in float,
// transposed: fields[f] holds field f of the four rays. A t_max >= 3e38
// becomes infinity first, as clamp_to_float makes it.
void four_rays_in_float(const Ray* const (&rays)[4], __m128 (&fields)[8]) {
  const __m256d t_max_lane = _mm256_castsi256_pd(_mm256_setr_epi64x(0, 0, 0, -1));
  __m128 head[4], tail[4];
  for (int k = 0; k < 4; ++k) {
    const double* d = reinterpret_cast<const double*>(rays[k]);
    head[k] = _mm256_cvtpd_ps(_mm256_loadu_pd(d));
    const __m256d rest = _mm256_loadu_pd(d + 4);
    const __m256d huge = _mm256_and_pd(_mm256_cmp_pd(rest, _mm256_set1_pd(3.0e38), _CMP_GE_OQ), t_max_lane);
    tail[k] = _mm256_cvtpd_ps(_mm256_blendv_pd(rest, _mm256_set1_pd(INFINITY), huge));
  }
  _MM_TRANSPOSE4_PS(head[0], head[1], head[2], head[3]);
  _MM_TRANSPOSE4_PS(tail[0], tail[1], tail[2], tail[3]);
  for (int k = 0; k < 4; ++k) {
    fields[k] = head[k];
    fields[4 + k] = tail[k];
  }
}

}  // namespace

// make_ray_packet_reference in registers: its lanes are stored one float at
// a time and then read back 64 bytes at once (by the inverse and the
// kernel), a load that has to wait for all sixteen stores to retire.
RayPacket make_ray_packet(const Ray* rays, int count, PacketTMax t_max_mode) {
  using namespace simd16;
  RayPacket p;
  p.count = count;
  __m128 fields[4][8];  // [four rays][field]
  for (int g = 0; g < 4; ++g) {
    const Ray* four[4];
    for (int k = 0; k < 4; ++k) four[k] = &rays[4 * g + k < count ? 4 * g + k : 0];  // unused lanes repeat ray 0
    four_rays_in_float(four, fields[g]);
  }
  const auto field = [&fields](int f) { return from_quads(fields[0][f], fields[1][f], fields[2][f], fields[3][f]); };
  const F16 limit = splat16(kSlabInverseLimit), minus_limit = splat16(-kSlabInverseLimit);
  for (int a = 0; a < 3; ++a) {
    store16(p.origin[a], field(a));
    const F16 direction = field(3 + a);
    store16(p.direction[a], direction);
    // std::clamp(1.0f / direction, -limit, limit), lane by lane.
    const F16 inv = splat16(1.0f) / direction;
    F16 clamped = select16(compare16<_CMP_LT_OQ>(inv, minus_limit), minus_limit, inv);
    clamped = select16(compare16<_CMP_LT_OQ>(limit, inv), limit, clamped);
    store16(p.inv_direction[a], clamped);
  }
  store16(p.t_min, field(6));
  // float_toward_zero: every lane but zeros and NaNs one step toward zero;
  // unused lanes look nowhere.
  F16 t_max = field(7);
  if (t_max_mode == PacketTMax::inclusive)
    t_max = step_toward_zero16(compare16<_CMP_NEQ_OQ>(t_max, splat16(0.0f)), t_max);
  const int used = count >= kPacketSize ? (1 << kPacketSize) - 1 : (1 << count) - 1;
  store16(p.t_max, select16(mask16(used), t_max, splat16(-INFINITY)));
  store16(p.triangle, splat16i(kNoTriangle));
  return p;
}

#else

RayPacket make_ray_packet(const Ray* rays, int count, PacketTMax t_max_mode) {
  return make_ray_packet_reference(rays, count, t_max_mode);
}

#endif

#if defined(__AVX2__)

namespace {

using namespace simd16;

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

// glint:long-function: the hot 16-ray packet kernel, kept as one function on
// purpose: its leaf tests' state (the lanes' t_max and hits) stays in
// registers across leaves; not split without a benchmark.
bool intersect_mesh_packet(const MeshBvh& m, RayPacket& p) {
  if (m.bvh.nodes.empty()) return true;
  // One shear frame and one set of direction signs for the whole packet.
  const int kz = dominant_axis(p.direction[0][0], p.direction[1][0], p.direction[2][0]);
  for (int i = 1; i < kPacketSize; ++i)
    if (dominant_axis(p.direction[0][i], p.direction[1][i], p.direction[2][i]) != kz) return false;
  const int kx = kz == 2 ? 0 : kz + 1;
  const int ky = kx == 2 ? 0 : kx + 1;

  // Per-lane constants, computed as the single-ray kernels compute them.
  alignas(64) float sx[kPacketSize], sy[kPacketSize], sz[kPacketSize];
  for (int i = 0; i < kPacketSize; ++i) {
    sz[i] = 1.0f / p.direction[kz][i];
    sx[i] = -p.direction[kx][i] * sz[i];
    sy[i] = -p.direction[ky][i] * sz[i];
  }
  // Nodes are tested once for the whole packet (traverse_packet_closest); a
  // child is entered when any ray may hit it; leaves are then tested against
  // every ray whose own box test passes, so a ray's hits are exactly its own.
  F16 origin[3];
  for (int a = 0; a < 3; ++a) origin[a] = load16(p.origin[a]);
  const F16 shear_x = load16(sx), shear_y = load16(sy), shear_z = load16(sz);
  const F16 t_min = load16(p.t_min);  // triangles are tested from t_min itself
  F16 t_max = load16(p.t_max);
  I16 hit_triangle = splat16i(kNoHitId);
  I16 hit_slot = splat16i(0);  // block * 4 + lane of the hit

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

  // The shared packet traversal (packet_traversal.h) visits the nodes; a
  // leaf's blocks are tested here against the rays that reach it, the
  // packet's hits kept in registers and its t_max handed back on a hit.
  const bool traced = traverse_packet_closest(
      m.bvh, p,
      [&](uint32_t first, uint32_t count, int rays) {
        bool hit = false;
        if (__builtin_popcount(rays) >= kLeafRaysForSimd) {
          for (uint32_t b = first; b < first + count; ++b) hit |= block_all_rays(b, rays);
        } else {
          store16(ray_t_max, t_max);
          store16(ray_triangle, hit_triangle);
          store16(ray_slot, hit_slot);
          for (int r = rays; r; r &= r - 1)
            for (uint32_t b = first; b < first + count; ++b) hit |= block_one_ray(b, __builtin_ctz(r));
          if (hit) {
            t_max = load16(ray_t_max);
            hit_triangle = load16(ray_triangle);
            hit_slot = load16(ray_slot);
          }
        }
        if (hit) store16(p.t_max, t_max);
        return hit ? rays : 0;
      },
      [&](uint32_t first, uint32_t count) {  // leaf blocks: on their way while the others are ordered
        const char* block = reinterpret_cast<const char*>(&m.blocks[first]);
        for (uint32_t line = 0; line < count * sizeof(Triangle4); line += 64) _mm_prefetch(block + line, _MM_HINT_T0);
      });
  if (!traced) return false;  // direction signs differ
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
