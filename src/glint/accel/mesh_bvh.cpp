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
    sx = _mm_set1_ps(-d[kx] / d[kz]);
    sy = _mm_set1_ps(-d[ky] / d[kz]);
    sz = _mm_set1_ps(1.0f / d[kz]);
    origin[0] = _mm_set1_ps(static_cast<float>(ray.origin.x));
    origin[1] = _mm_set1_ps(static_cast<float>(ray.origin.y));
    origin[2] = _mm_set1_ps(static_cast<float>(ray.origin.z));
  }
};

// Bit i set when lane i is hit with t in (t_min, t_max); `t` gets the distances.
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
  valid = _mm_and_ps(valid, _mm_and_ps(_mm_cmpgt_ps(t, t_min), _mm_cmplt_ps(t, t_max)));
  return _mm_movemask_ps(valid);
}

float float_t_min(const Ray& ray) { return static_cast<float>(ray.t_min); }

}  // namespace

bool intersect_mesh_bvh(const MeshBvh& m, const Ray& ray, uint32_t& triangle, float& t_hit) {
  const WatertightRay4 wray(ray);
  const __m128 t_min = _mm_set1_ps(float_t_min(ray));
  Ray traversal = ray;
  float best = clamp_to_float(ray.t_max);
  return traverse_closest_leaves(m.bvh, traversal, [&](uint32_t first, uint32_t count, Ray& r) {
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
        if (ts[lane] < best) {
          best = ts[lane];
          triangle = m.blocks[b].id[lane];
          found = true;
        }
      }
    }
    if (found) {
      r.t_max = best;
      t_hit = best;
    }
    return found;
  });
}

bool occluded_mesh_bvh(const MeshBvh& m, const Ray& ray) {
  const WatertightRay4 wray(ray);
  const __m128 t_min = _mm_set1_ps(float_t_min(ray)), t_max = _mm_set1_ps(clamp_to_float(ray.t_max));
  return traverse_any_leaves(m.bvh, ray, [&](uint32_t first, uint32_t count, const Ray&) {
    for (uint32_t b = first; b < first + count; ++b) {
      __m128 t;
      if (intersect_block(m.blocks[b], wray, t_min, t_max, t)) return true;
    }
    return false;
  });
}

}  // namespace glint
