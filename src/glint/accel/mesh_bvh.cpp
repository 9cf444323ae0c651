#include "glint/accel/mesh_bvh.h"

#include <cmath>
#include <limits>

namespace glint {

MeshBvh build_mesh_bvh(const Mesh& mesh, const BvhBuildOptions& options) {
  const size_t n = mesh.triangle_count();
  std::vector<Bounds3> bounds(n);
  for (size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) bounds[t].extend(to_vec3(mesh.positions[mesh.indices[3 * t + k]]));
  BvhBuildOptions block_options = options;
  block_options.max_leaf_size = 4;
  block_options.block_size = 4;
  MeshBvh out;
  out.bvh = build_bvh(bounds, block_options, mesh.bounds.center());
  bounds = {};
  // Leaves hold ranges of bvh.primitives: turn each into blocks of four.
  for (BvhNode& node : out.bvh.nodes) {
    for (int slot = 0; slot < kBvhWidth; ++slot) {
      if (node.count[slot] == 0) continue;
      const uint32_t first = node.child[slot], count = node.count[slot];
      const uint32_t first_block = static_cast<uint32_t>(out.blocks.size());
      for (uint32_t i = 0; i < count; i += 4) {
        Triangle4 block;
        for (int lane = 0; lane < 4; ++lane) {
          const bool used = i + lane < count;
          const uint32_t tri = used ? out.bvh.primitives[first + i + lane] : 0;
          block.id[lane] = tri;
          for (int v = 0; v < 3; ++v) {
            const Vec3f& p = mesh.positions[mesh.indices[3 * static_cast<size_t>(tri) + v]];
            const float nan = std::numeric_limits<float>::quiet_NaN();
            block.v[v][0][lane] = used ? p.x : nan;
            block.v[v][1][lane] = used ? p.y : nan;
            block.v[v][2][lane] = used ? p.z : nan;
          }
        }
        out.blocks.push_back(block);
      }
      node.child[slot] = first_block;
      node.count[slot] = static_cast<uint32_t>(out.blocks.size()) - first_block;
    }
  }
  out.bvh.primitives = {};  // the blocks carry the triangle indices
  out.blocks.shrink_to_fit();
  return out;
}

namespace {

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

float float_t_min(const Ray& ray) { return static_cast<float>(ray.t_min); }

// The largest float below the ray's t_max: "t <= this" is "t < t_max" in float.
float float_t_max_inclusive(const Ray& ray) { return float_toward_zero(clamp_to_float(ray.t_max)); }

// Among hits at the same float distance (a ray through a shared edge), the
// lower triangle index wins, so the answer does not depend on the order the
// traversal met them in (single rays and packets agree).
constexpr uint32_t kNoHitId = 0x7fffffff;

}  // namespace

Triangle block_triangle(const Triangle4& b, int lane) {
  return {Vec3(b.v[0][0][lane], b.v[0][1][lane], b.v[0][2][lane]),
          Vec3(b.v[1][0][lane], b.v[1][1][lane], b.v[1][2][lane]),
          Vec3(b.v[2][0][lane], b.v[2][1][lane], b.v[2][2][lane])};
}

bool intersect_mesh_bvh(const MeshBvh& m, const Ray& ray, uint32_t& triangle, float& t_hit, Triangle& vertices) {
  const WatertightRay4 wray(ray);
  const __m128 t_min = _mm_set1_ps(float_t_min(ray));
  Ray traversal = ray;
  float best = float_t_max_inclusive(ray);
  uint32_t best_block = 0, best_id = kNoHitId;
  int best_lane = 0;
  const bool found = traverse_closest_leaves(m.bvh, traversal, [&](uint32_t first, uint32_t count, Ray& r) {
    bool found = false;
    for (uint32_t b = first; b < first + count; ++b) {
      __m128 t;
      int mask = intersect_block(m.blocks[b], wray, t_min, _mm_set1_ps(best), t);
      if (!mask) continue;
      alignas(16) float ts[4];
      _mm_store_ps(ts, t);
      while (mask) {
        const int lane = __builtin_ctz(mask);
        mask &= mask - 1;
        const uint32_t id = m.blocks[b].id[lane];
        if (ts[lane] < best || (ts[lane] == best && id < best_id)) {
          best = ts[lane];
          best_id = id;
          best_block = b;
          best_lane = lane;
          found = true;
        }
      }
    }
    if (found) r.t_max = best;
    return found;
  }, [&](uint32_t first, uint32_t count) {
    // Leaf blocks come from anywhere in memory; nodes hit near the root stay cached.
    const char* p = reinterpret_cast<const char*>(&m.blocks[first]);
    const char* end = reinterpret_cast<const char*>(&m.blocks[first + count]);
    for (; p < end; p += 64) _mm_prefetch(p, _MM_HINT_T0);
  });
  if (!found) return false;
  t_hit = best;
  triangle = m.blocks[best_block].id[best_lane];
  vertices = block_triangle(m.blocks[best_block], best_lane);
  return true;
}

bool occluded_mesh_bvh(const MeshBvh& m, const Ray& ray) {
  const WatertightRay4 wray(ray);
  const __m128 t_min = _mm_set1_ps(float_t_min(ray)), t_max = _mm_set1_ps(float_t_max_inclusive(ray));
  return traverse_any_leaves(m.bvh, ray, [&](uint32_t first, uint32_t count, const Ray&) {
    for (uint32_t b = first; b < first + count; ++b) {
      __m128 t;
      if (intersect_block(m.blocks[b], wray, t_min, t_max, t)) return true;
    }
    return false;
  });
}

RayPacket make_ray_packet(const Ray* rays, int count) {
  RayPacket p;
  p.count = count;
  for (int i = 0; i < kPacketSize; ++i) {
    const Ray& r = rays[i < count ? i : 0];  // unused lanes repeat ray 0
    for (int a = 0; a < 3; ++a) {
      p.origin[a][i] = static_cast<float>(r.origin[a]);
      p.direction[a][i] = static_cast<float>(r.direction[a]);
      p.inv_direction[a][i] = static_cast<float>(1.0 / r.direction[a]);
    }
    p.t_min[i] = static_cast<float>(r.t_min);
    p.t_max[i] = float_toward_zero(clamp_to_float(r.t_max));  // inclusive, as intersect_mesh_bvh
    p.triangle[i] = kNoTriangle;
  }
  return p;
}

#if defined(__AVX2__)

namespace {

int dominant_axis(float x, float y, float z) {
  const float ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
  return ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
}

}  // namespace

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
  alignas(32) float sx[kPacketSize], sy[kPacketSize], sz[kPacketSize];
  for (int i = 0; i < kPacketSize; ++i) {
    sz[i] = 1.0f / p.direction[kz][i];
    sx[i] = -p.direction[kx][i] * sz[i];
    sy[i] = -p.direction[ky][i] * sz[i];
  }
  __m256 origin[3], inv_dir[3];
  for (int a = 0; a < 3; ++a) {
    origin[a] = _mm256_load_ps(p.origin[a]);
    inv_dir[a] = _mm256_load_ps(p.inv_direction[a]);
  }
  const __m256 shear_x = _mm256_load_ps(sx), shear_y = _mm256_load_ps(sy), shear_z = _mm256_load_ps(sz);
  // Boxes are entered from t_min scaled down a little (bvh.h), triangles from t_min.
  const __m256 t_min = _mm256_load_ps(p.t_min);
  const __m256 box_t_min =
      _mm256_sub_ps(_mm256_mul_ps(t_min, _mm256_set1_ps(1.0f - 0x1p-20f)), _mm256_set1_ps(1e-30f));
  __m256 t_max = _mm256_load_ps(p.t_max);
  __m256i hit_triangle = _mm256_set1_epi32(static_cast<int>(kNoHitId));
  const int all = (1 << p.count) - 1;

  struct Entry { uint32_t child, count; int mask; };
  Entry stack[kTraversalStack];
  int top = 0;
  const __m256 widen = _mm256_set1_ps(1.0f + 4.0f * 0x1p-23f);
  const __m256 zero = _mm256_setzero_ps();
  // As in traverse_closest_leaves: the nearest child is visited next without
  // a trip through the stack.
  Entry e{0, 0, all};
  for (;;) {
    if (e.count > 0) {
      for (uint32_t b = e.child; b < e.child + e.count; ++b) {
        const Triangle4& block = m.blocks[b];
        for (int lane = 0; lane < 4; ++lane) {
          // One triangle against every ray of the packet.
          __m256 x[3], y[3], z[3];
          for (int v = 0; v < 3; ++v) {
            z[v] = _mm256_sub_ps(_mm256_set1_ps(block.v[v][kz][lane]), origin[kz]);
            x[v] = _mm256_add_ps(_mm256_sub_ps(_mm256_set1_ps(block.v[v][kx][lane]), origin[kx]),
                                 _mm256_mul_ps(shear_x, z[v]));
            y[v] = _mm256_add_ps(_mm256_sub_ps(_mm256_set1_ps(block.v[v][ky][lane]), origin[ky]),
                                 _mm256_mul_ps(shear_y, z[v]));
          }
          const __m256 e0 = _mm256_sub_ps(_mm256_mul_ps(x[1], y[2]), _mm256_mul_ps(y[1], x[2]));
          const __m256 e1 = _mm256_sub_ps(_mm256_mul_ps(x[2], y[0]), _mm256_mul_ps(y[2], x[0]));
          const __m256 e2 = _mm256_sub_ps(_mm256_mul_ps(x[0], y[1]), _mm256_mul_ps(y[0], x[1]));
          const __m256 any_neg = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_LT_OQ),
                                                           _mm256_cmp_ps(e1, zero, _CMP_LT_OQ)),
                                              _mm256_cmp_ps(e2, zero, _CMP_LT_OQ));
          const __m256 any_pos = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(e0, zero, _CMP_GT_OQ),
                                                           _mm256_cmp_ps(e1, zero, _CMP_GT_OQ)),
                                              _mm256_cmp_ps(e2, zero, _CMP_GT_OQ));
          const __m256 det = _mm256_add_ps(_mm256_add_ps(e0, e1), e2);
          const __m256 t_scaled = _mm256_mul_ps(
              _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(e0, z[0]), _mm256_mul_ps(e1, z[1])), _mm256_mul_ps(e2, z[2])),
              shear_z);
          const __m256 t = _mm256_div_ps(t_scaled, det);
          __m256 valid = _mm256_andnot_ps(_mm256_and_ps(any_neg, any_pos), _mm256_cmp_ps(det, zero, _CMP_NEQ_UQ));
          valid = _mm256_and_ps(valid, _mm256_and_ps(_mm256_cmp_ps(t, t_min, _CMP_GT_OQ),
                                                     _mm256_cmp_ps(t, t_max, _CMP_LE_OQ)));
          // Nearer, or as near with a lower triangle index (as intersect_mesh_bvh).
          const __m256i id = _mm256_set1_epi32(static_cast<int>(block.id[lane]));
          valid = _mm256_and_ps(valid, _mm256_or_ps(_mm256_cmp_ps(t, t_max, _CMP_LT_OQ),
                                                    _mm256_castsi256_ps(_mm256_cmpgt_epi32(hit_triangle, id))));
          if (_mm256_movemask_ps(valid) & e.mask) {
            valid = _mm256_and_ps(valid, _mm256_castsi256_ps(_mm256_set_epi32(
                                             e.mask & 128 ? -1 : 0, e.mask & 64 ? -1 : 0, e.mask & 32 ? -1 : 0,
                                             e.mask & 16 ? -1 : 0, e.mask & 8 ? -1 : 0, e.mask & 4 ? -1 : 0,
                                             e.mask & 2 ? -1 : 0, e.mask & 1 ? -1 : 0)));
            t_max = _mm256_blendv_ps(t_max, t, valid);
            hit_triangle = _mm256_castps_si256(
                _mm256_blendv_ps(_mm256_castsi256_ps(hit_triangle), _mm256_castsi256_ps(id), valid));
          }
        }
      }
      if (top == 0) break;
      e = stack[--top];
      continue;
    }
    const BvhNode& n = m.bvh.nodes[e.child];
    // Each child box against every ray; children are pushed far to near by
    // the entry distance of the packet's first ray that hits them.
    Entry hits[kBvhWidth];
    float near[kBvhWidth];
    int k = 0;
    for (int c = 0; c < kBvhWidth; ++c) {
      if (n.count[c] == 0 && n.child[c] == 0 && n.bounds[0][c] > n.bounds[1][c]) continue;  // empty slot
      __m256 lo_t = box_t_min, hi_t = t_max;
      for (int a = 0; a < 3; ++a) {
        const __m256 near_plane = _mm256_set1_ps(n.bounds[2 * a + (negative[a] ? 1 : 0)][c]);
        const __m256 far_plane = _mm256_set1_ps(n.bounds[2 * a + (negative[a] ? 0 : 1)][c]);
        lo_t = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(near_plane, origin[a]), inv_dir[a]), lo_t);
        hi_t = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(far_plane, origin[a]), inv_dir[a]), hi_t);
      }
      hi_t = _mm256_mul_ps(hi_t, widen);  // as hit_children does
      const int mask = _mm256_movemask_ps(_mm256_cmp_ps(lo_t, hi_t, _CMP_LE_OQ)) & e.mask;
      if (!mask) continue;
      alignas(32) float lo[kPacketSize];
      _mm256_store_ps(lo, lo_t);
      const float d = lo[__builtin_ctz(mask)];
      int j = k++;
      while (j > 0 && near[j - 1] < d) {
        hits[j] = hits[j - 1];
        near[j] = near[j - 1];
        --j;
      }
      hits[j] = {n.child[c], n.count[c], mask};
      near[j] = d;
    }
    if (k > 0) {
      for (int i = 0; i + 1 < k; ++i) stack[top++] = hits[i];
      e = hits[k - 1];
      continue;
    }
    if (top == 0) break;
    e = stack[--top];
  }
  _mm256_store_ps(p.t_max, t_max);
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(p.triangle), hit_triangle);
  for (int i = 0; i < kPacketSize; ++i)
    if (p.triangle[i] == kNoHitId) p.triangle[i] = kNoTriangle;
  return true;
}

#else

bool intersect_mesh_packet(const MeshBvh&, RayPacket&) { return false; }

#endif

}  // namespace glint
