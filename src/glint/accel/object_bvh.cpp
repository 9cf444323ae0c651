// The top-level accelerator (BvhAccelerator): one wide BVH over the scene's
// objects, a mesh's own BVH (mesh_bvh.h) below each mesh object, infinite
// planes tested apart; and the hit tests of one object, which live here
// because this traversal is their hot caller.
#include "glint/accel/accelerator.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>

#include "glint/accel/huge_pages.h"
#include "glint/accel/mesh_bvh.h"
#include "glint/accel/packet_slots.h"
#include "glint/accel/packet_traversal.h"
#include "glint/accel/ray_packets.h"
#include "glint/accel/triangle_leaf.h"
#include "glint/accel/wide_bvh.h"
#include "glint/geometry/csg.h"
#include "glint/geometry/shapes.h"
#include "glint/geometry/torus.h"
#include "glint/geometry/triangle_shear.h"

namespace glint {

Triangle mesh_triangle(const Mesh& mesh, uint32_t triangle) {
  const uint32_t* i = &mesh.indices[3 * static_cast<size_t>(triangle)];
  return {to_vec3(mesh.positions[i[0]]), to_vec3(mesh.positions[i[1]]), to_vec3(mesh.positions[i[2]])};
}

namespace {

// Fills `hit` field by field. A Hit built apart and then copied whole made
// the copy's wide loads wait for the narrow stores that had just built it (a
// failed store-to-load forwarding: a third of intersect_mesh's time in perf).
inline void set_hit(Hit& hit, double t, uint32_t object, double b1, double b2, int face, uint32_t primitive) {
  hit.t = t;
  hit.object = object;
  hit.b1 = b1;
  hit.b2 = b2;
  hit.face = face;
  hit.primitive = primitive;
}

// intersect_plane's crossing (the same arithmetic, so the same t), without
// its division when the sign already says the crossing is behind the
// origin: num / denom <= 0 (or NaN) never exceeds a t_min >= 0. Shadow and
// reflected rays leaving a floor are most of a scene's plane tests.
inline bool plane_crossing(const Plane& p, const Ray& ray, double& t) {
  const double denom = dot(p.normal, ray.direction);
  if (denom == 0.0) return false;
  const double num = dot(p.normal, p.point - ray.origin);
  const bool ahead = (num > 0.0 && denom > 0.0) || (num < 0.0 && denom < 0.0);
  if (!ahead && ray.t_min >= 0.0) return false;
  t = num / denom;
  return t > ray.t_min && t < ray.t_max;
}

// std::nextafter(t, +infinity) without the library call (the object BVH's
// leaves ask it for every leaf once a ray has a hit).
inline double double_above(double t) {
  if (t == 0.0) return std::numeric_limits<double>::denorm_min();
  if (!(t < kInfinity)) return t;  // +inf, NaN
  const uint64_t bits = std::bit_cast<uint64_t>(t);
  return std::bit_cast<double>(t > 0.0 ? bits + 1 : bits - 1);
}

// Closest hit among a mesh's triangles (ray in the mesh's space): through its
// BVH when there is one (float blocks, then the winner refined in double),
// else every triangle in double.
bool intersect_mesh(const Mesh& mesh, const MeshBvh* bvh, uint32_t index, const Ray& object_ray, Hit& hit) {
  if (bvh) {
    uint32_t triangle = 0, slot = 0;
    float t = 0;
    if (!intersect_mesh_bvh(*bvh, object_ray, triangle, t, slot)) return false;
    // Both copies of the vertices from the leaf block (in cache, and written
    // long ago: read back from `hit` they would wait on the stores).
    const Triangle4& block = bvh->blocks[slot / 4];
    const TriangleHit h = triangle_plane_hit(BlockTriangle{block, static_cast<int>(slot % 4)}, object_ray);
    hit.vertices = block_vertices(block, static_cast<int>(slot % 4));
    // The double crossing of a float hit can fall just outside the interval
    // (grazing rays, hits at t_min): the float distance stands then.
    set_hit(hit, h.t > object_ray.t_min && h.t < object_ray.t_max ? h.t : static_cast<double>(t), index, h.b1, h.b2, 0,
            triangle);
    return true;
  }
  Ray ray = object_ray;
  bool found = false;
  for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const Triangle vertices = mesh_triangle(mesh, t);
    const auto h = intersect_triangle(vertices, ray);
    if (!h) continue;
    hit = Hit{h->t, index, h->b1, h->b2, 0, t, to_vertices(vertices)};
    ray.t_max = h->t;
    found = true;
  }
  return found;
}

bool occludes_mesh(const Mesh& mesh, const MeshBvh* bvh, const Ray& ray) {
  if (bvh) return occluded_mesh_bvh(*bvh, ray);
  for (uint32_t t = 0; t < mesh.triangle_count(); ++t)
    if (intersect_triangle(mesh_triangle(mesh, t), ray)) return true;
  return false;
}

// `ray` is in the object's own space.
inline bool intersect_shape(const Scene& scene, const Object& object, uint32_t index, const Ray& ray, Hit& hit,
                            const std::vector<MeshBvh>* mesh_bvhs) {
  switch (object.type) {
    case ShapeType::sphere:
      if (auto t = intersect_sphere(scene.spheres[object.shape], ray)) {
        hit = Hit{*t, index, 0, 0, 0, 0, {}};
        return true;
      }
      return false;
    case ShapeType::plane:
      if (auto t = intersect_plane(scene.planes[object.shape], ray)) {
        hit = Hit{*t, index, 0, 0, 0, 0, {}};
        return true;
      }
      return false;
    case ShapeType::triangle:
      if (auto h = intersect_triangle(scene.triangles[object.shape], ray)) {
        hit = Hit{h->t, index, h->b1, h->b2, 0, 0, {}};
        return true;
      }
      return false;
    case ShapeType::box:
      if (auto h = intersect_box(scene.boxes[object.shape], ray)) {
        hit = Hit{h->t, index, 0, 0, h->face, 0, {}};
        return true;
      }
      return false;
    case ShapeType::mesh:
      return intersect_mesh(scene.meshes[object.shape], mesh_bvhs ? &(*mesh_bvhs)[object.shape] : nullptr, index, ray,
                            hit);
    case ShapeType::cylinder:
    case ShapeType::cone:
      if (auto h = intersect_cone(scene.cones[object.shape], ray)) {
        hit = Hit{h->t, index, 0, 0, h->part, 0, {}};
        return true;
      }
      return false;
    case ShapeType::disk:
      if (auto t = intersect_disk(scene.disks[object.shape], ray)) {
        hit = Hit{*t, index, 0, 0, 0, 0, {}};
        return true;
      }
      return false;
    case ShapeType::polygon:
      if (auto h = intersect_polygon(scene.polygons[object.shape], ray)) {
        hit = Hit{h->t, index, h->b1, h->b2, 0, h->triangle, {}};
        return true;
      }
      return false;
    case ShapeType::torus:
      if (auto t = intersect_torus(scene.tori[object.shape], ray)) {
        hit = Hit{*t, index, 0, 0, 0, 0, {}};
        return true;
      }
      return false;
    case ShapeType::csg:  // face: the leaf's part, doubled, plus 1 where its normal turns; primitive: the leaf
      if (auto h = intersect_csg(scene.csgs[object.shape], ray)) {
        hit = Hit{h->t, index, 0, 0, 2 * h->part + (h->flip ? 1 : 0), h->leaf, {}};
        return true;
      }
      return false;
  }
  return false;
}

// The ray in the object's own space (same t: the direction is mapped, not renormalized).
inline Ray to_object_space(const Scene& scene, const Object& object, const Ray& world_ray) {
  if (object.transform == kNoTransform) return world_ray;
  const Transform& xf = scene.transforms[object.transform];
  Ray ray = world_ray;
  ray.origin = xf.inverse_point(world_ray.origin);
  ray.direction = xf.inverse_vector(world_ray.direction);
  return ray;
}

}  // namespace

bool intersect_object(const Scene& scene, uint32_t index, const Ray& world_ray, Hit& hit,
                      const std::vector<MeshBvh>* mesh_bvhs) {
  const Object& object = scene.objects[index];
  if (object.transform == kNoTransform) return intersect_shape(scene, object, index, world_ray, hit, mesh_bvhs);
  return intersect_shape(scene, object, index, to_object_space(scene, object, world_ray), hit, mesh_bvhs);
}

Hit refine_mesh_hit(const Scene& scene, uint32_t object, uint32_t triangle, const Ray& world_ray) {
  const Object& o = scene.objects[object];
  const Ray ray = to_object_space(scene, o, world_ray);
  const Triangle tri = mesh_triangle(scene.meshes[o.shape], triangle);
  const TriangleHit h = triangle_plane_hit(tri, ray);
  return Hit{h.t, object, h.b1, h.b2, 0, triangle, to_vertices(tri)};
}

bool occludes_object(const Scene& scene, uint32_t index, const Ray& world_ray, const std::vector<MeshBvh>* mesh_bvhs) {
  const Object& object = scene.objects[index];
  if (object.type == ShapeType::mesh)
    return occludes_mesh(scene.meshes[object.shape], mesh_bvhs ? &(*mesh_bvhs)[object.shape] : nullptr,
                         to_object_space(scene, object, world_ray));
  Hit scratch;
  return intersect_object(scene, index, world_ray, scratch, mesh_bvhs);
}

namespace {

// What one primitive of the top-level BVH is: an object, or one triangle of
// an untransformed polygon of several (each its own primitive, so the tree
// finds a big polygon's triangles as a mesh's: NFF's 144-vertex gear faces).
inline constexpr uint32_t kWholeObject = ~0u;
struct Part {
  uint32_t object = 0;
  uint32_t triangle = kWholeObject;  // into Polygon::triangles
};

// The untransformed triangle of a part (a triangle object, a polygon of one
// triangle, one triangle of a polygon) as its hit test takes it, or nothing.
std::optional<Triangle> plain_triangle(const Scene& scene, const Part& part) {
  const Object& o = scene.objects[part.object];
  if (o.transform != kNoTransform) return std::nullopt;
  if (o.type == ShapeType::triangle) return scene.triangles[o.shape];
  if (o.type == ShapeType::polygon) {
    const Polygon& p = scene.polygons[o.shape];
    if (part.triangle == kWholeObject && p.triangles.size() != 1) return std::nullopt;
    return polygon_triangle(p, part.triangle == kWholeObject ? 0 : part.triangle);
  }
  return std::nullopt;
}

// The scene's finite objects as the tree's primitives, with their bounds.
void make_parts(const Scene& scene, std::vector<Part>& parts, std::vector<Bounds3>& bounds) {
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (o.type == ShapeType::plane) continue;
    if (o.type == ShapeType::polygon && o.transform == kNoTransform) {
      const Polygon& p = scene.polygons[o.shape];
      if (p.triangles.size() > 1) {
        for (uint32_t k = 0; k < p.triangles.size(); ++k) {
          Bounds3 b;
          for (const uint32_t v : p.triangles[k]) b.extend(p.vertices[v]);
          parts.push_back({i, k});
          bounds.push_back(b);
        }
        continue;
      }
    }
    parts.push_back({i, kWholeObject});
    bounds.push_back(object_bounds(scene, i));
  }
}

// Two levels: one BVH per mesh (built once, shared by its instances) and one
// over all finite objects; infinite planes are tested apart.
class BvhAccelerator final : public Accelerator {
 public:
  BvhAccelerator(const Scene& scene, const AcceleratorOptions& options) : scene_(scene) {
    BvhBuildOptions build_options;
    build_options.threads = options.threads;
    mesh_bvhs_.reserve(scene.meshes.size());
    for (const Mesh& mesh : scene.meshes) mesh_bvhs_.push_back(build_mesh_bvh(mesh, build_options));
    for (uint32_t i = 0; i < scene.objects.size(); ++i)
      if (scene.objects[i].type == ShapeType::plane)
        planes_.push_back({scene.planes[scene.objects[i].shape], i, scene.objects[i].transform != kNoTransform});
    std::vector<Part> parts;
    std::vector<Bounds3> bounds;
    make_parts(scene, parts, bounds);
    bvh_ = build_bvh(bounds, build_options, scene.camera.position);
    slots_.reserve(bvh_.primitives.size());
    for (const uint32_t primitive : bvh_.primitives) {
      const Part& part = parts[primitive];
      const Object& o = scene.objects[part.object];
      Slot slot;
      slot.object = part.object;
      slot.triangle = part.triangle;
      slot.is_sphere = o.type == ShapeType::sphere && o.transform == kNoTransform;
      if (slot.is_sphere) slot.sphere = scene.spheres[o.shape];
      slots_.push_back(slot);
    }
    // Leaves of plain triangles alone, for TriangleLeaf::maybe_hit.
    leaf_.assign(bvh_.primitives.size(), kNone);
    for (const BvhNode& node : bvh_.nodes)
      for (int c = 0; c < kBvhWidth; ++c) {
        const uint32_t first = node.child[c], count = node.count[c];
        if (count == 0 || count > 4) continue;
        bool triangles = true;
        Triangle tri[4];
        for (uint32_t i = 0; i < count; ++i) {
          const Slot& slot = slots_[first + i];
          const std::optional<Triangle> t =
              triangles ? plain_triangle(scene, {slot.object, slot.triangle}) : std::nullopt;
          triangles = t.has_value();
          if (t) tri[i] = *t;
        }
        if (triangles) {
          TriangleLeaf leaf;
          leaf.count = count;
          for (uint32_t i = 0; i < 4; ++i) {
            const Triangle& t = tri[std::min(i, count - 1)];
            const Vec3* vertex[3] = {&t.v0, &t.v1, &t.v2};
            for (int j = 0; j < 3; ++j)
              for (int a = 0; a < 3; ++a) leaf.v[j][a][i] = (*vertex[j])[a];
          }
          leaf_[first] = static_cast<uint32_t>(triangle_leaves_.size());
          triangle_leaves_.push_back(leaf);
        }
      }
    // Packets take the fast path when the only finite object is one mesh.
    uint32_t finite = 0;
    for (uint32_t i = 0; i < scene.objects.size(); ++i)
      if (scene.objects[i].type != ShapeType::plane) {
        ++finite;
        single_mesh_ = scene.objects[i].type == ShapeType::mesh ? i : kNone;
      }
    if (finite != 1) single_mesh_ = kNone;
  }

  std::optional<Hit> intersect(const Ray& world_ray) const override {
    Ray ray = world_ray;
    // Filled in place and returned as is (no copy of the Hit: see set_hit).
    std::optional<Hit> result(std::in_place);
    Hit& best = *result;
    bool found = intersect_planes(ray, best);
    if (single_mesh_ != kNone) {
      // One mesh: its own BVH is the whole tree (the top level would hold
      // one box), called straight (not through intersect_object's switch).
      const Object& object = scene_.objects[single_mesh_];
      const Mesh& mesh = scene_.meshes[object.shape];
      const MeshBvh& mesh_bvh = mesh_bvhs_[object.shape];
      found |= object.transform == kNoTransform
                   ? intersect_mesh(mesh, &mesh_bvh, single_mesh_, ray, best)
                   : intersect_mesh(mesh, &mesh_bvh, single_mesh_, to_object_space(scene_, object, ray), best);
    } else {
      traverse_closest_leaves(bvh_, ray, [&](uint32_t first, uint32_t count, Ray& r) {
        return leaf_closest(first, count, r, best, found);
      });
    }
    if (!found) result.reset();
    return result;
  }

  void intersect_packet(const Ray* rays, int count, std::optional<Hit>* hits) const override {
    if (count <= 0) return;  // make_ray_packet reads rays[0]
    if (count > kPacketSize) return Accelerator::intersect_packet(rays, count, hits);
    if (single_mesh_ == kNone) return intersect_objects_packet(rays, count, hits);
    // The steps of intersect() ray by ray, with the mesh traced as a packet:
    // planes first (they bound t_max), then the mesh, then the refinement.
    const Object& object = scene_.objects[single_mesh_];
    const MeshBvh& mesh_bvh = mesh_bvhs_[object.shape];
    // Rays bounded by the planes' hits, in the mesh's space (copies only when
    // there are planes or a transform).
    const Ray* object_rays = rays;
    PacketSlots<Ray> copies;
    for (int i = 0; i < count; ++i) hits[i].reset();
    if (!planes_.empty() || object.transform != kNoTransform) {
      for (int i = 0; i < count; ++i) {
        Ray ray = rays[i];
        // Into the answer itself: a Hit built apart, two fields set and then
        // copied whole, made the copy wait for those stores.
        if (!intersect_planes(ray, hits[i].emplace())) hits[i].reset();
        copies[i] = to_object_space(scene_, object, ray);
      }
      object_rays = copies.data();
    }
    RayPacket packet = make_ray_packet(object_rays, count);
    if (!intersect_mesh_packet(mesh_bvh, packet)) {
      for (int i = 0; i < count; ++i) {
        Hit h;
        if (intersect_mesh(scene_.meshes[object.shape], &mesh_bvh, single_mesh_, object_rays[i], h)) hits[i] = h;
      }
      return;
    }
    for (int i = 0; i < count; ++i) {
      if (packet.triangle[i] == kNoTriangle) continue;
      const Ray& r = object_rays[i];
      // The vertices from the block the kernel just read, as intersect_mesh does.
      Hit& hit = hits[i].emplace();
      const Triangle4& block = mesh_bvh.blocks[packet.slot[i] / 4];
      const int lane = static_cast<int>(packet.slot[i] % 4);
      const TriangleHit h = triangle_plane_hit(BlockTriangle{block, lane}, r);
      hit.vertices = block_vertices(block, lane);
      const double t = h.t > r.t_min && h.t < r.t_max ? h.t : static_cast<double>(packet.t_max[i]);
      set_hit(hit, t, single_mesh_, h.b1, h.b2, 0, packet.triangle[i]);
    }
  }

  bool occluded(const Ray& ray) const override { return first_blocker(ray).has_value(); }

  void occluded_packet(const Ray* rays, int count, bool* blocked, uint32_t& cache) const override {
    if (count > kPacketSize) return Accelerator::occluded_packet(rays, count, blocked, cache);
    if (single_mesh_ == kNone) return occluded_objects_packet(rays, count, blocked, cache);
    // Planes ray by ray; the rays they leave open go through the mesh as one
    // packet: blocked when the packet's closest-hit kernel finds any hit in
    // the ray's interval, which is exactly when occluded_mesh_bvh finds one
    // (the same float triangle test and interval, every leaf the ray's box
    // test reaches).
    const Object& object = scene_.objects[single_mesh_];
    const MeshBvh& mesh_bvh = mesh_bvhs_[object.shape];
    PacketSlots<Ray> open;
    int index[kPacketSize];
    const int n = rays_past_planes(rays, count, blocked, &object, open.data(), index);
    if (n == 0) return;
    RayPacket packet = make_ray_packet(open.data(), n);
    if (!intersect_mesh_packet(mesh_bvh, packet)) {
      for (int k = 0; k < n; ++k) blocked[index[k]] = occluded_mesh_bvh(mesh_bvh, open[k]);
      return;
    }
    for (int k = 0; k < n; ++k) blocked[index[k]] = packet.triangle[k] != kNoTriangle;
  }

  bool occluded_cached(const Ray& ray, uint32_t& cache) const override {
    // Any blocker answers an any-hit query, so the cached one, when it
    // blocks, gives the same answer as the traversal.
    // When it does not, the traversal skips it: a mesh would otherwise be
    // traversed twice for every unblocked ray.
    if (cache != kNoShadowBlocker && cache < scene_.objects.size() && occludes_object(scene_, cache, ray, &mesh_bvhs_))
      return true;
    const std::optional<uint32_t> blocker = first_blocker_except(ray, cache);
    if (blocker) cache = *blocker;
    return blocker.has_value();
  }

  std::optional<uint32_t> first_blocker(const Ray& ray) const override { return first_blocker_except(ray, kNone); }

  // The first object found to block the ray, leaving out `skip` (known not to).
  std::optional<uint32_t> first_blocker_except(const Ray& ray, uint32_t skip) const {
    for (const PlaneSlot& p : planes_)
      if (p.object != skip && blocks(p, ray)) return p.object;
    if (single_mesh_ != kNone)
      return single_mesh_ != skip && occludes_object(scene_, single_mesh_, ray, &mesh_bvhs_)
                 ? std::optional<uint32_t>(single_mesh_)
                 : std::nullopt;
    std::optional<uint32_t> blocker;
    traverse_any_leaves(bvh_, ray, [&](uint32_t first, uint32_t count, const Ray& r) {
      const uint32_t object = leaf_blocker(first, count, r, skip);
      if (object != kNone) blocker = object;
      return object != kNone;
    });
    return blocker;
  }

  // The infinite planes against `ray`: the nearest hit into `best`, ray.t_max lowered to it.
  bool intersect_planes(Ray& ray, Hit& best) const {
    bool found = false;
    for (const PlaneSlot& p : planes_) {
      if (p.transformed) {
        if (intersect_object(scene_, p.object, ray, best)) {
          ray.t_max = best.t;
          found = true;
        }
        continue;
      }
      double t = 0;
      if (plane_crossing(p.plane, ray, t)) {
        set_hit(best, t, p.object, 0, 0, 0, 0);
        best.vertices = {};
        ray.t_max = t;
        found = true;
      }
    }
    return found;
  }

  // The objects of a leaf of the tree (slots first .. first + count) against
  // `r`: a nearer hit into `best` (`found` says whether it holds one), and
  // r.t_max lowered to it. Of two hits at the same distance the lower object
  // index wins, as in brute force, and within a polygon the lower triangle
  // index: the answer must not depend on the order leaves are visited in,
  // which differs between a ray alone and in a packet. So a leaf is tested up
  // to just past the best distance (its objects there are compared), and
  // r.t_max is set back to that distance after.
  bool leaf_closest(uint32_t first, uint32_t count, Ray& r, Hit& best, bool& found) const {
    // Locals, not the references: the compiler then keeps them in registers.
    bool have = found, hit = false;
    double best_t = have ? best.t : r.t_max;
    uint32_t best_object = have ? best.object : 0, best_part = have ? best.primitive : 0;
    if (have) r.t_max = double_above(best_t);
    auto better = [&](double t, uint32_t object, uint32_t part) {
      return !have || t < best_t ||
             (t == best_t && (object < best_object || (object == best_object && part < best_part)));
    };
    auto took = [&](double t, uint32_t object, uint32_t part) {
      have = hit = true;
      best_t = t;
      best_object = object;
      best_part = part;
      r.t_max = double_above(t);
    };
    // Any object through intersect_object, into a scratch hit: `best` keeps
    // its hit when the new one loses the tie; a polygon's triangle alone.
    auto test_slot = [&](const Slot& slot) {
      if (slot.triangle != kWholeObject) {
        const auto h = intersect_triangle(slot_triangle(slot), r);
        if (h && better(h->t, slot.object, slot.triangle)) {
          set_hit(best, h->t, slot.object, h->b1, h->b2, 0, slot.triangle);
          best.vertices = {};
          took(h->t, slot.object, slot.triangle);
        }
        return;
      }
      Hit h;
      if (intersect_object(scene_, slot.object, r, h, &mesh_bvhs_) && better(h.t, slot.object, h.primitive)) {
        best = h;
        took(h.t, slot.object, h.primitive);
      }
    };
    if (const uint32_t leaf = leaf_[first]; leaf != kNone) {
      for (int lanes = triangle_leaves_[leaf].maybe_hit(r); lanes; lanes &= lanes - 1)
        test_slot(slots_[first + static_cast<uint32_t>(__builtin_ctz(static_cast<unsigned>(lanes)))]);
    } else {
      for (uint32_t i = first; i < first + count; ++i) {
        const Slot& slot = slots_[i];
        if (!slot.is_sphere) {
          test_slot(slot);
          continue;
        }
        // intersect_object's sphere case, without its two lookups.
        if (const auto t = intersect_sphere(slot.sphere, r); t && better(*t, slot.object, 0)) {
          set_hit(best, *t, slot.object, 0, 0, 0, 0);
          best.vertices = {};
          took(*t, slot.object, 0);
        }
      }
    }
    if (have) r.t_max = best_t;
    found = have;
    return hit;
  }

  // The first object of a leaf found to block `r`, leaving out `skip`; kNone when none does.
  uint32_t leaf_blocker(uint32_t first, uint32_t count, const Ray& r, uint32_t skip) const {
    auto blocks = [&](const Slot& slot) {
      if (slot.object == skip) return false;
      if (slot.is_sphere) return intersect_sphere(slot.sphere, r).has_value();
      if (slot.triangle == kWholeObject) return occludes_object(scene_, slot.object, r, &mesh_bvhs_);
      return intersect_triangle(slot_triangle(slot), r).has_value();
    };
    if (const uint32_t leaf = leaf_[first]; leaf != kNone) {
      for (int lanes = triangle_leaves_[leaf].maybe_hit(r); lanes; lanes &= lanes - 1) {
        const Slot& slot = slots_[first + static_cast<uint32_t>(__builtin_ctz(static_cast<unsigned>(lanes)))];
        if (blocks(slot)) return slot.object;
      }
      return kNone;
    }
    for (uint32_t i = first; i < first + count; ++i)
      if (blocks(slots_[i])) return slots_[i].object;
    return kNone;
  }

  // intersect() for each ray, the tree traced as one packet: planes ray by
  // ray first (they bound t_max), then every leaf a ray's own box test
  // reaches is tested for that ray as intersect() tests it.
  void intersect_objects_packet(const Ray* rays, int count, std::optional<Hit>* hits) const {
    PacketSlots<Ray> r;
    // Each ray's best hit is kept in its answer itself: a copy at the end
    // read 80 bytes at once that leaf_closest had just written field by
    // field (a failed store-to-load forwarding).
    bool found[kPacketSize];
    for (int i = 0; i < count; ++i) {
      r[i] = rays[i];
      found[i] = intersect_planes(r[i], hits[i].emplace());
    }
    RayPacket packet = make_ray_packet(r.data(), count, PacketTMax::as_is);  // as traverse_closest_leaves
    const bool traced = traverse_packet_closest(bvh_, packet, [&](uint32_t first, uint32_t n, int mask) {
      int lowered = 0;
      for (; mask; mask &= mask - 1) {
        const int i = __builtin_ctz(static_cast<unsigned>(mask));
        if (leaf_closest(first, n, r[i], *hits[i], found[i])) {
          packet.t_max[i] = clamp_to_float(r[i].t_max);
          lowered |= 1 << i;
        }
      }
      return lowered;
    });
    if (!traced) {
      for (int i = 0; i < count; ++i)
        traverse_closest_leaves(bvh_, r[i], [&](uint32_t first, uint32_t n, Ray& ray) {
          return leaf_closest(first, n, ray, *hits[i], found[i]);
        });
    }
    for (int i = 0; i < count; ++i)
      if (!found[i]) hits[i].reset();
  }

  // occluded_cached for each ray, the tree traced as one packet: planes ray
  // by ray, then the open rays through the tree together. The cached blocker
  // is not asked first: the packet meets a blocker about as soon (spheres
  // render 0.160 -> 0.155 s without it); it is still set, for rays asked one
  // by one.
  void occluded_objects_packet(const Ray* rays, int count, bool* blocked, uint32_t& cache) const {
    PacketSlots<Ray> open;
    int index[kPacketSize];
    const int n = rays_past_planes(rays, count, blocked, nullptr, open.data(), index);
    if (n == 0) return;
    RayPacket packet = make_ray_packet(open.data(), n, PacketTMax::as_is);  // as traverse_any_leaves
    uint32_t blocker = kNone;
    const int result = traverse_packet_any(bvh_, packet, [&](uint32_t first, uint32_t c, int mask) {
      int now_blocked = 0;
      for (; mask; mask &= mask - 1) {
        const int k = __builtin_ctz(static_cast<unsigned>(mask));
        if (const uint32_t object = leaf_blocker(first, c, open[k], kNone); object != kNone) {
          blocker = object;
          now_blocked |= 1 << k;
        }
      }
      return now_blocked;
    });
    if (result < 0) {  // not coherent: ray by ray
      for (int k = 0; k < n; ++k) blocked[index[k]] = occluded_cached(open[k], cache);
      return;
    }
    for (int k = 0; k < n; ++k) blocked[index[k]] = result >> k & 1;
    if (blocker != kNone) cache = blocker;
  }

  size_t memory_bytes() const override {
    size_t bytes = bvh_.nodes.capacity() * sizeof(BvhNode) + bvh_.primitives.capacity() * sizeof(uint32_t) +
                   slots_.capacity() * sizeof(Slot) + leaf_.capacity() * sizeof(uint32_t) +
                   triangle_leaves_.capacity() * sizeof(TriangleLeaf) + planes_.capacity() * sizeof(PlaneSlot);
    for (const MeshBvh& b : mesh_bvhs_) bytes += b.memory_bytes();
    return bytes;
  }

 private:
  static constexpr uint32_t kNone = ~0u;
  // What a leaf tests, in the tree's order (slots_[k] is bvh_.primitives[k]):
  // the object (or one triangle of a polygon), and an untransformed sphere's own numbers, so that a
  // sphereflake's leaves read one array instead of objects[] and spheres[].
  struct Slot {
    Sphere sphere;
    uint32_t object = 0;
    uint32_t triangle = kWholeObject;  // a polygon's triangle (Part)
    bool is_sphere = false;
  };
  // The polygon triangle a slot of one holds (slot.triangle != kWholeObject).
  Triangle slot_triangle(const Slot& slot) const {
    return polygon_triangle(scene_.polygons[scene_.objects[slot.object].shape], slot.triangle);
  }
  // An infinite plane, tested before the tree (its own numbers, as for spheres).
  struct PlaneSlot {
    Plane plane;
    uint32_t object = 0;
    bool transformed = false;  // never made by the loader; tested through intersect_object
  };
  // A shadow packet's first step: blocked[i] for the rays a plane blocks;
  // the others into open[0 .. n) (in `object`'s space when given), index[k]
  // saying which ray open[k] is. Returns n.
  int rays_past_planes(const Ray* rays, int count, bool* blocked, const Object* object, Ray* open, int* index) const {
    int n = 0;
    for (int i = 0; i < count; ++i) {
      blocked[i] = std::any_of(planes_.begin(), planes_.end(), [&](const PlaneSlot& p) { return blocks(p, rays[i]); });
      if (blocked[i]) continue;
      open[n] = object ? to_object_space(scene_, *object, rays[i]) : rays[i];
      index[n++] = i;
    }
    return n;
  }
  // Whether the plane blocks `ray` (any-hit).
  bool blocks(const PlaneSlot& p, const Ray& ray) const {
    double t = 0;
    return p.transformed ? occludes_object(scene_, p.object, ray) : plane_crossing(p.plane, ray, t);
  }
  const Scene& scene_;
  std::vector<PlaneSlot> planes_;
  uint32_t single_mesh_ = kNone;
  std::vector<MeshBvh> mesh_bvhs_;
  Bvh bvh_;
  std::vector<Slot> slots_;
  // Per slot: for a leaf's first slot, its TriangleLeaf when the leaf is of
  // plain triangles alone; else kNone.
  std::vector<uint32_t> leaf_;
  std::vector<TriangleLeaf> triangle_leaves_;
};

}  // namespace

std::unique_ptr<Accelerator> build_accelerator(const Scene& scene, const AcceleratorOptions& options) {
  const BufferRecycling recycling;  // the build's big buffers reuse each other's pages (huge_pages.h)
  std::unique_ptr<Accelerator> accel = options.backend == AccelBackend::embree
                                           ? build_embree_accelerator(scene, options)
                                           : std::make_unique<BvhAccelerator>(scene, options);
  release_recycled_buffer();  // the build's last one, or the mesh file's
  return accel;
}

}  // namespace glint
