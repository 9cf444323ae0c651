// The Embree backend: Intel Embree's BVH and kernels behind our Accelerator
// interface. Each mesh becomes an Embree scene of its own (built once) and
// each mesh object an instance of it; spheres, boxes, single triangles,
// cylinders, cones, disks and polygons are one Embree user geometry whose
// callbacks run our own double-precision tests (intersect_object); infinite planes are tested apart, as in our BVH.
// Embree traces mesh triangles in float; the winning triangle is then re-intersected in double (refine_mesh_hit), so
// shading sees the same t and barycentrics as with our BVH and the two backends give the same image up to float ties.
#include "glint/accel/accelerator.h"
#include "glint/error.h"

#if GLINT_HAVE_EMBREE

#include <embree3/rtcore.h>

#include <atomic>
#include <cmath>
#include <string>
#include <thread>

#include "glint/math/transform.h"

namespace glint {

namespace {

// Embree's callbacks get the context pointer we pass to rtcIntersect1 or
// rtcOccluded1; this struct extends it (Embree's documented pattern) with the
// world ray in double and what our user-geometry tests found.
struct QueryContext {
  RTCIntersectContext embree;  // must be first
  const Ray* world_ray;
  Hit user_hit;          // nearest analytic-shape hit so far
  uint32_t blocker = 0;  // occlusion: the object that blocked
};

float round_down(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -INFINITY) : f;
}
float round_up(double v) {
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, INFINITY) : f;
}

class EmbreeAccelerator final : public Accelerator {
 public:
  EmbreeAccelerator(const Scene& scene, const AcceleratorOptions& options) : scene_(scene) {
    const int threads =
        options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const std::string config = "threads=" + std::to_string(threads);
    device_ = rtcNewDevice(config.c_str());
    if (!device_) throw Error("embree: cannot create a device (" + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    rtcSetDeviceMemoryMonitorFunction(device_, &EmbreeAccelerator::monitor_memory, this);

    // One Embree scene per mesh, shared by its instances.
    mesh_scenes_.reserve(scene.meshes.size());
    for (const Mesh& mesh : scene.meshes) {
      RTCScene mesh_scene = rtcNewScene(device_);
      // Robust mode: Embree's watertight triangle test, so no ray slips
      // between adjacent triangles (the default mode leaks on shared edges).
      rtcSetSceneFlags(mesh_scene, RTC_SCENE_FLAG_ROBUST);
      RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      // Copied, not shared: Embree reads vertex buffers 16 bytes at a time
      // and needs padding after the last vertex that our vector lacks.
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
          geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
      if (vertices)
        for (size_t i = 0; i < mesh.positions.size(); ++i) {
          vertices[3 * i + 0] = mesh.positions[i].x;
          vertices[3 * i + 1] = mesh.positions[i].y;
          vertices[3 * i + 2] = mesh.positions[i].z;
        }
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                                 3 * sizeof(uint32_t), mesh.triangle_count());
      rtcCommitGeometry(geometry);
      rtcAttachGeometry(mesh_scene, geometry);
      rtcReleaseGeometry(geometry);
      rtcCommitScene(mesh_scene);
      mesh_scenes_.push_back(mesh_scene);
      check("building a mesh");
    }

    top_ = rtcNewScene(device_);
    rtcSetSceneFlags(top_, RTC_SCENE_FLAG_ROBUST);
    std::vector<uint32_t> analytic;
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
      const Object& object = scene.objects[i];
      if (object.type == ShapeType::plane) {
        planes_.push_back(i);
      } else if (object.type == ShapeType::mesh) {
        RTCGeometry instance = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(instance, mesh_scenes_[object.shape]);
        float xfm[12];
        const Transform& t = object.transform == kNoTransform ? Transform{} : scene.transforms[object.transform];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) xfm[4 * r + c] = static_cast<float>(t.m[r][c]);
        rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
        rtcCommitGeometry(instance);
        const unsigned id = rtcAttachGeometry(top_, instance);
        rtcReleaseGeometry(instance);
        if (instance_object_.size() <= id) instance_object_.resize(id + 1);
        instance_object_[id] = i;
      } else {
        analytic.push_back(i);
      }
    }
    analytic_objects_ = std::move(analytic);
    if (!analytic_objects_.empty()) {
      RTCGeometry user = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(user, static_cast<unsigned>(analytic_objects_.size()));
      rtcSetGeometryUserData(user, this);
      rtcSetGeometryBoundsFunction(user, &EmbreeAccelerator::analytic_bounds, this);
      rtcSetGeometryIntersectFunction(user, &EmbreeAccelerator::analytic_intersect);
      rtcSetGeometryOccludedFunction(user, &EmbreeAccelerator::analytic_occluded);
      rtcCommitGeometry(user);
      rtcAttachGeometry(top_, user);
      rtcReleaseGeometry(user);
    }
    rtcCommitScene(top_);
    check("building the scene");
  }

  ~EmbreeAccelerator() override {
    if (top_) rtcReleaseScene(top_);
    for (RTCScene s : mesh_scenes_) rtcReleaseScene(s);
    rtcReleaseDevice(device_);
  }

  std::optional<Hit> intersect(const Ray& world_ray) const override {
    Ray ray = world_ray;
    std::optional<Hit> plane_hit;
    for (uint32_t p : planes_) {
      Hit h;
      if (intersect_object(scene_, p, ray, h)) {
        ray.t_max = h.t;
        plane_hit = h;
      }
    }
    QueryContext ctx;
    rtcInitIntersectContext(&ctx.embree);
    ctx.world_ray = &ray;
    RTCRayHit rh;
    set_ray(ray, rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(top_, &ctx.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return plane_hit;
    Hit hit = ctx.user_hit;
    if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
      const uint32_t object = instance_object_[rh.hit.instID[0]];
      hit = refine_mesh_hit(scene_, object, rh.hit.primID, ray);
      // The double refinement of a float hit at a grazing angle can leave the
      // interval: keep Embree's own values then.
      if (!(hit.t > ray.t_min && hit.t < ray.t_max)) {
        hit.t = rh.ray.tfar;
        hit.b1 = rh.hit.u;
        hit.b2 = rh.hit.v;
      }
    }
    // Embree's interval is a little wider than ours (float rounding).
    if (!(hit.t > ray.t_min && hit.t < ray.t_max)) return plane_hit;
    return hit;
  }

  bool occluded(const Ray& ray) const override {
    for (uint32_t p : planes_)
      if (occludes_object(scene_, p, ray)) return true;
    return embree_occluded(ray).has_value();
  }

  std::optional<uint32_t> first_blocker(const Ray& ray) const override {
    for (uint32_t p : planes_)
      if (occludes_object(scene_, p, ray)) return p;
    const std::optional<uint32_t> blocker = embree_occluded(ray);
    if (!blocker || *blocker != kMeshBlocker) return blocker;
    // A mesh triangle blocked; Embree's any-hit query does not say which
    // instance, and only tools ask: name the nearest hit instead.
    if (auto h = intersect(ray)) return h->object;
    for (uint32_t i = 0; i < scene_.objects.size(); ++i)
      if (scene_.objects[i].type == ShapeType::mesh && occludes_object(scene_, i, ray)) return i;
    return std::nullopt;
  }

  size_t memory_bytes() const override { return static_cast<size_t>(std::max<int64_t>(0, bytes_.load())); }

 private:
  static constexpr uint32_t kNoBlocker = ~0u, kMeshBlocker = ~0u - 1;

  // Embree's any-hit query: nothing, an analytic object, or kMeshBlocker.
  std::optional<uint32_t> embree_occluded(const Ray& ray) const {
    QueryContext ctx;
    rtcInitIntersectContext(&ctx.embree);
    ctx.world_ray = &ray;
    ctx.blocker = kNoBlocker;
    RTCRay r;
    set_ray(ray, r);
    rtcOccluded1(top_, &ctx.embree, &r);
    if (r.tfar >= 0.0f) return std::nullopt;  // Embree sets tfar to -inf on a hit
    return ctx.blocker != kNoBlocker ? ctx.blocker : kMeshBlocker;
  }

  static void set_ray(const Ray& ray, RTCRay& r) {
    r.org_x = static_cast<float>(ray.origin.x);
    r.org_y = static_cast<float>(ray.origin.y);
    r.org_z = static_cast<float>(ray.origin.z);
    r.dir_x = static_cast<float>(ray.direction.x);
    r.dir_y = static_cast<float>(ray.direction.y);
    r.dir_z = static_cast<float>(ray.direction.z);
    // A little wider than the double interval; the double tests and the
    // refinement decide what is really inside it.
    r.tnear = std::max(0.0f, round_down(ray.t_min) * (1.0f - 0x1p-20f));
    r.tfar = ray.t_max >= 3.0e38 ? INFINITY : round_up(ray.t_max) * (1.0f + 0x1p-20f);
    r.time = 0.0f;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
  }

  void check(const char* what) const {
    const RTCError e = rtcGetDeviceError(device_);
    if (e == RTC_ERROR_OUT_OF_MEMORY) throw Error(std::string("embree: out of memory ") + what);
    if (e != RTC_ERROR_NONE) throw Error(std::string("embree: error ") + std::to_string(e) + " " + what);
  }

  static bool monitor_memory(void* self, ssize_t bytes, bool /*post*/) {
    static_cast<EmbreeAccelerator*>(self)->bytes_ += bytes;
    return true;
  }

  static void analytic_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* self = static_cast<const EmbreeAccelerator*>(args->geometryUserPtr);
    const Bounds3 b = object_bounds(self->scene_, self->analytic_objects_[args->primID]);
    RTCBounds* out = args->bounds_o;
    out->lower_x = round_down(b.lo.x);
    out->lower_y = round_down(b.lo.y);
    out->lower_z = round_down(b.lo.z);
    out->upper_x = round_up(b.hi.x);
    out->upper_y = round_up(b.hi.y);
    out->upper_z = round_up(b.hi.z);
  }

  // Our double test on the world ray, bounded by what Embree has found so far.
  static void analytic_intersect(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* self = static_cast<const EmbreeAccelerator*>(args->geometryUserPtr);
    auto* ctx = reinterpret_cast<QueryContext*>(args->context);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);  // N == 1: rtcIntersect1
    Ray ray = *ctx->world_ray;
    if (rh->ray.tfar < ray.t_max) ray.t_max = rh->ray.tfar;
    Hit hit;
    if (!intersect_object(self->scene_, self->analytic_objects_[args->primID], ray, hit)) return;
    ctx->user_hit = hit;
    rh->ray.tfar = static_cast<float>(hit.t);
    rh->hit.geomID = args->geomID;
    rh->hit.primID = args->primID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rh->hit.u = rh->hit.v = 0.0f;
  }

  static void analytic_occluded(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* self = static_cast<const EmbreeAccelerator*>(args->geometryUserPtr);
    auto* ctx = reinterpret_cast<QueryContext*>(args->context);
    auto* ray = reinterpret_cast<RTCRay*>(args->ray);
    const uint32_t object = self->analytic_objects_[args->primID];
    if (!occludes_object(self->scene_, object, *ctx->world_ray)) return;
    ctx->blocker = object;
    ray->tfar = -INFINITY;
  }

  const Scene& scene_;
  RTCDevice device_ = nullptr;
  RTCScene top_ = nullptr;
  std::vector<RTCScene> mesh_scenes_;
  std::vector<uint32_t> instance_object_;   // top-level geometry id -> object
  std::vector<uint32_t> analytic_objects_;  // user primitive id -> object
  std::vector<uint32_t> planes_;
  std::atomic<int64_t> bytes_{0};
};

}  // namespace

bool embree_available() { return true; }

std::unique_ptr<Accelerator> build_embree_accelerator(const Scene& scene, const AcceleratorOptions& options) {
  return std::make_unique<EmbreeAccelerator>(scene, options);
}

}  // namespace glint

#else  // built without Embree

namespace glint {

bool embree_available() { return false; }

std::unique_ptr<Accelerator> build_embree_accelerator(const Scene&, const AcceleratorOptions&) {
  throw Error("this glint was built without Embree (install libembree-dev and rebuild with -DGLINT_EMBREE=ON)");
}

}  // namespace glint

#endif
