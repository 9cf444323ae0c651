#include "glint/accel/mesh_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace glint {

MeshBvh build_mesh_bvh(const Mesh& mesh, const BvhBuildOptions& options) {
  BvhBuildOptions block_options = options;
  block_options.max_leaf_size = 4;
  block_options.block_size = 4;
  MeshBvh out;
  // Float boxes straight from the float vertices (min and max in the order
  // Bounds3::extend takes them, so -0 and +0 land as they did in double).
  const auto triangle_boxes = [&mesh](size_t begin, size_t end, FloatBox* boxes) {
    for (size_t t = begin; t < end; ++t) {
      const uint32_t* i = &mesh.indices[3 * t];
      FloatBox& b = boxes[t - begin];
      const Vec3f& p0 = mesh.positions[i[0]];
      b.lo[0] = b.hi[0] = p0.x;
      b.lo[1] = b.hi[1] = p0.y;
      b.lo[2] = b.hi[2] = p0.z;
      for (int k = 1; k < 3; ++k) {
        const Vec3f& p = mesh.positions[i[k]];
        const float v[3] = {p.x, p.y, p.z};
        for (int a = 0; a < 3; ++a) {
          b.lo[a] = std::min(b.lo[a], v[a]);
          b.hi[a] = std::max(b.hi[a], v[a]);
        }
      }
    }
  };
  out.bvh = build_bvh_over_float_boxes(mesh.triangle_count(), triangle_boxes, block_options, mesh.bounds.center());
  // Leaves hold ranges of bvh.primitives: turn each into blocks of four.
  // First where each leaf's blocks go (so the buffer is allocated once, at
  // its size), then the blocks themselves, nodes split over the threads.
  std::vector<uint32_t> first_block(out.bvh.nodes.size() * kBvhWidth);
  uint32_t blocks = 0;
  for (size_t node = 0; node < out.bvh.nodes.size(); ++node)
    for (int slot = 0; slot < kBvhWidth; ++slot) {
      first_block[node * kBvhWidth + slot] = blocks;
      blocks += (out.bvh.nodes[node].count[slot] + 3) / 4;
    }
  out.blocks.resize(blocks);
  auto fill = [&](size_t node_begin, size_t node_end) {
    for (size_t node = node_begin; node < node_end; ++node) {
      BvhNode& n = out.bvh.nodes[node];
      for (int slot = 0; slot < kBvhWidth; ++slot) {
        if (n.count[slot] == 0) continue;
        const uint32_t first = n.child[slot], count = n.count[slot];
        uint32_t b = first_block[node * kBvhWidth + slot];
        n.child[slot] = b;
        n.count[slot] = (count + 3) / 4;
        for (uint32_t i = 0; i < count; i += 4, ++b) {
          Triangle4& block = out.blocks[b];
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
        }
      }
    }
  };
  const size_t nodes = out.bvh.nodes.size();
  const int threads =
      std::clamp(options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency()), 1,
                 static_cast<int>(std::max<size_t>(1, nodes / 1024)));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(fill, nodes * t / threads, nodes * (t + 1) / threads);
  fill(0, nodes / threads);
  for (std::thread& t : pool) t.join();
  // The blocks carry the triangle indices. (A fresh vector frees the memory;
  // `= {}` would keep the capacity.)
  out.bvh.primitives = std::vector<uint32_t>();
  return out;
}

uint64_t mesh_bvh_digest(const Mesh& mesh, const BvhBuildOptions& options) {
  const MeshBvh bvh = build_mesh_bvh(mesh, options);
  uint64_t hash = 0xcbf29ce484222325ull;
  auto add = [&hash](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 0x100000001b3ull;
  };
  add(bvh.bvh.nodes.data(), bvh.bvh.nodes.size() * sizeof(BvhNode));
  add(bvh.blocks.data(), bvh.blocks.size() * sizeof(Triangle4));
  return hash;
}

BvhShape mesh_bvh_shape(const Mesh& mesh, const BvhBuildOptions& options) {
  const MeshBvh bvh = build_mesh_bvh(mesh, options);
  BvhShape shape;
  shape.nodes = bvh.bvh.nodes.size();
  shape.width = kBvhWidth;
  for (const BvhNode& n : bvh.bvh.nodes)
    for (int i = 0; i < kBvhWidth; ++i) shape.leaves += n.count[i] > 0;
  return shape;
}

namespace {

float float_t_min(const Ray& ray) { return static_cast<float>(ray.t_min); }

// Leaf blocks come from anywhere in memory (nodes near the root stay cached):
// asked for as soon as a leaf is found hit, they are on their way while the
// traversal decides what to visit first.
void prefetch_blocks(const MeshBvh& m, uint32_t first, uint32_t count) {
  const char* p = reinterpret_cast<const char*>(&m.blocks[first]);
  const char* end = reinterpret_cast<const char*>(&m.blocks[first + count]);
  for (; p < end; p += 64) _mm_prefetch(p, _MM_HINT_T0);
}

// The largest float below the ray's t_max: "t <= this" is "t < t_max" in float.
float float_t_max_inclusive(const Ray& ray) { return float_toward_zero(clamp_to_float(ray.t_max)); }

}  // namespace

bool intersect_mesh_bvh(const MeshBvh& m, const Ray& ray, uint32_t& triangle, float& t_hit, uint32_t& slot) {
  const WatertightRay4 wray(ray);
  const __m128 t_min = _mm_set1_ps(float_t_min(ray));
  Ray traversal = ray;
  float best = float_t_max_inclusive(ray);
  uint32_t best_block = 0, best_id = kNoHitId;
  int best_lane = 0;
  const bool found = traverse_closest_leaves(
      m.bvh, traversal,
      [&](uint32_t first, uint32_t count, Ray& r) {
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
      },
      [&](uint32_t first, uint32_t count) { prefetch_blocks(m, first, count); });
  if (!found) return false;
  t_hit = best;
  triangle = m.blocks[best_block].id[best_lane];
  slot = 4 * best_block + static_cast<uint32_t>(best_lane);
  return true;
}

bool occluded_mesh_bvh(const MeshBvh& m, const Ray& ray) {
  const WatertightRay4 wray(ray);
  const __m128 t_min = _mm_set1_ps(float_t_min(ray)), t_max = _mm_set1_ps(float_t_max_inclusive(ray));
  return traverse_any_leaves(
      m.bvh, ray,
      [&](uint32_t first, uint32_t count, const Ray&) {
        for (uint32_t b = first; b < first + count; ++b) {
          __m128 t;
          if (intersect_block(m.blocks[b], wray, t_min, t_max, t)) return true;
        }
        return false;
      },
      [&](uint32_t first, uint32_t count) { prefetch_blocks(m, first, count); });
}

}  // namespace glint
