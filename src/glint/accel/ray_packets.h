// Ray packets: up to kPacketSize coherent rays traced together through a
// mesh's BVH (the packet kernel; AVX2, with AVX-512 where the CPU has it).
// Internal.
#pragma once

#include <cstdint>

#include "glint/accel/mesh_bvh.h"

namespace glint {

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

// How a ray's double t_max becomes the lane's float t_max (clamp_to_float
// either way; unused lanes get -inf): `inclusive`, one float step nearer
// zero, so "t <= t_max" in float is "t < t_max" (the mesh kernels, as
// intersect_mesh_bvh); `as_is` for the object BVH's leaves, which test in
// double against the ray itself (as traverse_closest_leaves).
enum class PacketTMax { inclusive, as_is };
RayPacket make_ray_packet(const Ray* rays, int count, PacketTMax t_max = PacketTMax::inclusive);
// The same packet made lane by lane in plain C++ (what make_ray_packet does
// where there is no AVX2): the tests compare the two byte for byte.
RayPacket make_ray_packet_reference(const Ray* rays, int count, PacketTMax t_max = PacketTMax::inclusive);
// False (and nothing traced) when the rays are not coherent enough for the
// packet kernel (directions of different signs or dominant axes) or the
// build has no packet kernel (no AVX): trace them one by one then.
bool intersect_mesh_packet(const MeshBvh& mesh_bvh, RayPacket& packet);

}  // namespace glint
