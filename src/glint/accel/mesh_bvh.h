// MeshBvh: our BVH over one mesh's triangles. The SAH build fills leaves of
// up to four triangles, and each leaf is stored as one block of four
// triangles in float SoA layout, tested at once with SSE by the watertight
// algorithm of Woop, Benthin and Wald (JCGT 2013). Float is enough to pick
// the triangle (mesh vertices are floats); the caller refines the winner in
// double for shading.
#pragma once

#include <cstdint>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/accel/bvh.h"
#include "glint/scene/scene.h"

namespace glint {

struct alignas(16) Triangle4 {
  float v[3][3][4];  // v[vertex][axis][lane]; unused lanes hold NaN (never hit)
  uint32_t id[4];    // the mesh's triangle index per lane
};
static_assert(sizeof(Triangle4) == 160);

struct MeshBvh {
  Bvh bvh;  // leaves: child = first block, count = number of blocks
  HugePageVector<Triangle4> blocks;
  size_t memory_bytes() const {
    return bvh.nodes.capacity() * sizeof(BvhNode) + bvh.primitives.capacity() * sizeof(uint32_t) +
           blocks.capacity() * sizeof(Triangle4);
  }
};

MeshBvh build_mesh_bvh(const Mesh& mesh, const BvhBuildOptions& options = {});

// The nearest triangle hit in (ray.t_min, ray.t_max), in float: its index,
// distance and where its vertices are (`slot` = block * 4 + lane in
// MeshBvh::blocks, already in cache, so shading need not read the mesh
// again). False when none.
bool intersect_mesh_bvh(const MeshBvh& mesh_bvh, const Ray& ray, uint32_t& triangle, float& t, uint32_t& slot);
// The vertices of lane `lane` of block `block`, as stored and in double.
TriangleVertices block_vertices(const Triangle4& block, int lane);
Triangle block_triangle(const Triangle4& block, int lane);
// Whether any triangle is hit in (ray.t_min, ray.t_max).
bool occluded_mesh_bvh(const MeshBvh& mesh_bvh, const Ray& ray);

// Packets: up to kPacketSize coherent rays (camera rays of neighbouring
// pixels) traced together through the same nodes. Each node is tested once
// for the whole packet (interval arithmetic over the rays), each leaf only
// for the rays whose own box test passes it. The triangle arithmetic per ray
// is that of intersect_mesh_bvh, and ties go to the lower triangle index in
// both, so the hits are exactly the single rays' hits.
struct alignas(64) RayPacket {
  float origin[3][kPacketSize], direction[3][kPacketSize];
  float inv_direction[3][kPacketSize];           // 1 / direction, clamped to +-2^100 as RaySlabs does
  float t_min[kPacketSize], t_max[kPacketSize];  // t_max shrinks to each hit
  uint32_t triangle[kPacketSize];                // out: the hit, or kNoTriangle
  uint32_t slot[kPacketSize];                    // out: where in MeshBvh::blocks (block * 4 + lane)
  int count = 0;                                 // rays in use
};
inline constexpr uint32_t kNoTriangle = ~0u;

RayPacket make_ray_packet(const Ray* rays, int count);
// False (and nothing traced) when the rays are not coherent enough for the
// packet kernel (directions of different signs or dominant axes) or the
// build has no packet kernel (no AVX): trace them one by one then.
bool intersect_mesh_packet(const MeshBvh& mesh_bvh, RayPacket& packet);

}  // namespace glint
