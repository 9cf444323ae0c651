// Triangle blocks: the leaves of a mesh's BVH store four triangles at a time
// in float SoA layout (Triangle4), tested at once with SSE by the watertight
// algorithm of Woop, Benthin and Wald (JCGT 2013). Shared by the single-ray
// kernel (mesh_bvh.cpp) and the packet kernel (ray_packets.cpp). Internal.
#pragma once

#include <immintrin.h>

#include <cmath>
#include <cstdint>

#include "glint/geometry/hit.h"
#include "glint/geometry/shape_types.h"
#include "glint/math/ray.h"

namespace glint {

struct alignas(16) Triangle4 {
  float v[3][3][4];  // v[vertex][axis][lane]; unused lanes hold NaN (never hit)
  uint32_t id[4];    // the mesh's triangle index per lane
};
static_assert(sizeof(Triangle4) == 160);

// The vertices of lane `lane` of block `b`, as stored and in double. Inline:
// every mesh hit reads them (intersect_mesh, packets).
inline TriangleVertices block_vertices(const Triangle4& b, int lane) {
  return {Vec3f{b.v[0][0][lane], b.v[0][1][lane], b.v[0][2][lane]},
          Vec3f{b.v[1][0][lane], b.v[1][1][lane], b.v[1][2][lane]},
          Vec3f{b.v[2][0][lane], b.v[2][1][lane], b.v[2][2][lane]}};
}
// Lane `lane` of a block as the double refinement reads it
// (triangle_plane_hit): each vertex loaded from the block where it is used.
struct BlockTriangle {
  const Triangle4& block;
  int lane;
};
inline Vec3 corner(const BlockTriangle& t, int i) {
  return Vec3(t.block.v[i][0][t.lane], t.block.v[i][1][t.lane], t.block.v[i][2][t.lane]);
}

// The ray in the watertight test's frame: axis kz is where the direction is
// largest, and the shear (sx, sy, sz) maps the direction to (0, 0, 1).
struct WatertightRay4 {
  int kx, ky, kz;
  __m128 origin[3];  // in x, y, z order (not permuted)
  __m128 sx, sy, sz;

  explicit WatertightRay4(const Ray& ray) {
    const float d[3] = {static_cast<float>(ray.direction.x), static_cast<float>(ray.direction.y),
                        static_cast<float>(ray.direction.z)};
    const float ax = std::abs(d[0]), ay = std::abs(d[1]), az = std::abs(d[2]);
    kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    // One division: the shear only has to be the same for every triangle
    // (and for packets, which compute it alike), not correctly rounded.
    const float inv_z = 1.0f / d[kz];
    sx = _mm_set1_ps(-d[kx] * inv_z);
    sy = _mm_set1_ps(-d[ky] * inv_z);
    sz = _mm_set1_ps(inv_z);
    origin[0] = _mm_set1_ps(static_cast<float>(ray.origin.x));
    origin[1] = _mm_set1_ps(static_cast<float>(ray.origin.y));
    origin[2] = _mm_set1_ps(static_cast<float>(ray.origin.z));
  }
  // A ray of a packet (its origin `ray_origin`), whose frame (kx, ky, kz)
  // and shear are computed as above.
  WatertightRay4(const float (&ray_origin)[3], int kx_, int ky_, int kz_, float sx_, float sy_, float sz_)
      : kx(kx_), ky(ky_), kz(kz_), sx(_mm_set1_ps(sx_)), sy(_mm_set1_ps(sy_)), sz(_mm_set1_ps(sz_)) {
    for (int a = 0; a < 3; ++a) origin[a] = _mm_set1_ps(ray_origin[a]);
  }
};

// Bit i set when lane i is hit with t in (t_min, t_max]; `t` gets the distances.
inline int intersect_block(const Triangle4& b, const WatertightRay4& r, __m128 t_min, __m128 t_max, __m128& t) {
  __m128 x[3], y[3], z[3];
  for (int v = 0; v < 3; ++v) {
    z[v] = _mm_sub_ps(_mm_load_ps(b.v[v][r.kz]), r.origin[r.kz]);
    x[v] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(b.v[v][r.kx]), r.origin[r.kx]), _mm_mul_ps(r.sx, z[v]));
    y[v] = _mm_add_ps(_mm_sub_ps(_mm_load_ps(b.v[v][r.ky]), r.origin[r.ky]), _mm_mul_ps(r.sy, z[v]));
  }
  // Edge functions: the same products for a shared edge, with opposite signs.
  const __m128 e0 = _mm_sub_ps(_mm_mul_ps(x[1], y[2]), _mm_mul_ps(y[1], x[2]));
  const __m128 e1 = _mm_sub_ps(_mm_mul_ps(x[2], y[0]), _mm_mul_ps(y[2], x[0]));
  const __m128 e2 = _mm_sub_ps(_mm_mul_ps(x[0], y[1]), _mm_mul_ps(y[0], x[1]));
  const __m128 zero = _mm_setzero_ps();
  const __m128 any_neg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)), _mm_cmplt_ps(e2, zero));
  const __m128 any_pos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)), _mm_cmpgt_ps(e2, zero));
  const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
  const __m128 t_scaled =
      _mm_mul_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, z[0]), _mm_mul_ps(e1, z[1])), _mm_mul_ps(e2, z[2])), r.sz);
  t = _mm_div_ps(t_scaled, det);  // NaN lanes and det == 0 fail the range tests below
  __m128 valid = _mm_andnot_ps(_mm_and_ps(any_neg, any_pos), _mm_cmpneq_ps(det, zero));
  valid = _mm_and_ps(valid, _mm_and_ps(_mm_cmpgt_ps(t, t_min), _mm_cmple_ps(t, t_max)));
  return _mm_movemask_ps(valid);
}

// Among hits at the same float distance (a ray through a shared edge), the
// lower triangle index wins, so the answer does not depend on the order the
// traversal met them in (single rays and packets agree).
inline constexpr uint32_t kNoHitId = 0x7fffffff;

}  // namespace glint
