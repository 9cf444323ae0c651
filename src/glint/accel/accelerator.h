// Accelerator: the two queries the integrator asks of the scene's geometry,
// intersect (closest hit) and occluded (any hit, for shadow rays). Our BVH
// answers them; other backends (Embree) plug in behind the same interface.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "glint/geometry/hit.h"
#include "glint/math/ray.h"
#include "glint/scene/scene.h"

namespace glint {

struct MeshBvh;

// Rays per packet (Accelerator::intersect_packet).
inline constexpr int kPacketSize = 16;

// A mesh triangle in the mesh's own space, as doubles.
Triangle mesh_triangle(const Mesh& mesh, uint32_t triangle);

// One object against a world-space ray (object-space for transformed shapes
// is handled inside). Fills `hit` and returns true when nearer than ray.t_max.
// `mesh_bvhs` (one per Scene::meshes entry) speeds up mesh objects; without
// it every triangle is tested.
bool intersect_object(const Scene& scene, uint32_t object, const Ray& ray, Hit& hit,
                      const std::vector<MeshBvh>* mesh_bvhs = nullptr);
bool occludes_object(const Scene& scene, uint32_t object, const Ray& ray,
                     const std::vector<MeshBvh>* mesh_bvhs = nullptr);

// No object: an empty slot of the shadow cache (occluded_cached).
inline constexpr uint32_t kNoShadowBlocker = ~0u;

class Accelerator {
 public:
  virtual ~Accelerator() = default;
  virtual std::optional<Hit> intersect(const Ray& ray) const = 0;
  virtual bool occluded(const Ray& ray) const = 0;
  // Closest hits of up to kPacketSize rays at once (camera rays of
  // neighbouring pixels): the same answers as intersect() ray by ray, which
  // is what the default does. Our BVH traces a packet together (the rays'
  // direction signs alike; else ray by ray).
  virtual void intersect_packet(const Ray* rays, int count, std::optional<Hit>* hits) const {
    for (int i = 0; i < count; ++i) hits[i] = intersect(rays[i]);
  }
  // The object hit first by an any-hit query, for tools that name a blocker.
  virtual std::optional<uint32_t> first_blocker(const Ray& ray) const = 0;
  // occluded(ray), asking object `cache` first when it is not
  // kNoShadowBlocker, and setting `cache` to the blocker found otherwise:
  // the same answer, sooner when rays in a row are blocked by one object.
  virtual bool occluded_cached(const Ray& ray, uint32_t& /*cache*/) const { return occluded(ray); }
  // occluded_cached for up to kPacketSize shadow rays at once (from the
  // points of neighbouring pixels toward one light): blocked[i] is
  // occluded(rays[i]), which is what the default asks ray by ray. Our BVH
  // traces a packet together (the rays' direction signs alike).
  virtual void occluded_packet(const Ray* rays, int count, bool* blocked, uint32_t& cache) const {
    for (int i = 0; i < count; ++i) blocked[i] = occluded_cached(rays[i], cache);
  }
  // Bytes held by the acceleration structure itself (not the scene).
  virtual size_t memory_bytes() const = 0;
};

// Which traversal kernel answers the queries: our BVH, or Intel Embree (when
// glint was built with it). Both give the same hits up to float ties: Embree's
// float hits on mesh triangles are refined in double by our triangle test.
// Ours is the default: it measured faster end to end (docs/performance.md).
enum class AccelBackend { bvh, embree };

struct AcceleratorOptions {
  int threads = 0;  // build threads; 0: all cores
  AccelBackend backend = AccelBackend::bvh;
};

// Our SAH BVH over every finite object (or Embree's, per options.backend);
// infinite planes are tested apart.
std::unique_ptr<Accelerator> build_accelerator(const Scene& scene, const AcceleratorOptions& options = {});

// True when this build of glint has the Embree backend.
bool embree_available();
// Throws glint::Error when Embree is not available.
std::unique_ptr<Accelerator> build_embree_accelerator(const Scene& scene, const AcceleratorOptions& options);

// A mesh object's triangle against a world-space ray, in double, without
// range or edge rejection: how the Embree backend turns its float hit into
// the same t and barycentrics our own test gives.
Hit refine_mesh_hit(const Scene& scene, uint32_t object, uint32_t triangle, const Ray& world_ray);
// Tests every object for every ray: the reference the BVH is checked against.
std::unique_ptr<Accelerator> build_brute_force(const Scene& scene);

}  // namespace glint
