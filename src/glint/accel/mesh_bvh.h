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
#include "glint/accel/triangle_blocks.h"
#include "glint/accel/wide_bvh.h"
#include "glint/scene/scene.h"

namespace glint {

struct MeshBvh {
  Bvh bvh;  // leaves: child = first block, count = number of blocks
  HugePageVector<Triangle4> blocks;
  size_t memory_bytes() const {
    return bvh.nodes.capacity() * sizeof(BvhNode) + bvh.primitives.capacity() * sizeof(uint32_t) +
           blocks.capacity() * sizeof(Triangle4);
  }
};

MeshBvh build_mesh_bvh(const Mesh& mesh, const BvhBuildOptions& options = {});

// A digest (64-bit FNV-1a) of the bytes of the nodes and blocks that
// build_mesh_bvh(mesh, options) makes: lets the tests, which are not compiled
// for the library's SIMD width and so cannot hold a MeshBvh, compare trees.
uint64_t mesh_bvh_digest(const Mesh& mesh, const BvhBuildOptions& options);

// The shape of the tree build_mesh_bvh(mesh, options) makes, for the tests
// (which cannot hold a MeshBvh): its wide nodes, its leaves and the slots
// a node has.
struct BvhShape {
  size_t nodes = 0, leaves = 0;
  int width = 0;
};
BvhShape mesh_bvh_shape(const Mesh& mesh, const BvhBuildOptions& options);

// The nearest triangle hit in (ray.t_min, ray.t_max), in float: its index,
// distance and where its vertices are (`slot` = block * 4 + lane in
// MeshBvh::blocks, already in cache, so shading need not read the mesh
// again). False when none.
bool intersect_mesh_bvh(const MeshBvh& mesh_bvh, const Ray& ray, uint32_t& triangle, float& t, uint32_t& slot);
// Whether any triangle is hit in (ray.t_min, ray.t_max).
bool occluded_mesh_bvh(const MeshBvh& mesh_bvh, const Ray& ray);

}  // namespace glint
