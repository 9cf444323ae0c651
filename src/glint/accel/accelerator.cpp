#include "glint/accel/accelerator.h"

#include "glint/accel/bvh.h"
#include "glint/geometry/shapes.h"

namespace glint {

namespace {

// `ray` is in the object's own space.
inline bool intersect_shape(const Scene& scene, const Object& object, uint32_t index, const Ray& ray,
                            Hit& hit) {
  switch (object.type) {
    case ShapeType::sphere:
      if (auto t = intersect_sphere(scene.spheres[object.shape], ray)) {
        hit = Hit{*t, index, 0, 0, 0};
        return true;
      }
      return false;
    case ShapeType::plane:
      if (auto t = intersect_plane(scene.planes[object.shape], ray)) {
        hit = Hit{*t, index, 0, 0, 0};
        return true;
      }
      return false;
    case ShapeType::triangle:
      if (auto h = intersect_triangle(scene.triangles[object.shape], ray)) {
        hit = Hit{h->t, index, h->b1, h->b2, 0};
        return true;
      }
      return false;
    case ShapeType::box:
      if (auto h = intersect_box(scene.boxes[object.shape], ray)) {
        hit = Hit{h->t, index, 0, 0, h->face};
        return true;
      }
      return false;
  }
  return false;
}

}  // namespace

bool intersect_object(const Scene& scene, uint32_t index, const Ray& world_ray, Hit& hit) {
  const Object& object = scene.objects[index];
  if (object.transform == kNoTransform) return intersect_shape(scene, object, index, world_ray, hit);
  // Same t in both spaces: the direction is mapped, not renormalized.
  const Transform& xf = scene.transforms[object.transform];
  Ray ray = world_ray;
  ray.origin = xf.inverse_point(world_ray.origin);
  ray.direction = xf.inverse_vector(world_ray.direction);
  return intersect_shape(scene, object, index, ray, hit);
}

namespace {

class BvhAccelerator final : public Accelerator {
 public:
  BvhAccelerator(const Scene& scene, const AcceleratorOptions& options) : scene_(scene) {
    std::vector<Bounds3> bounds(scene.objects.size());
    for (uint32_t i = 0; i < scene.objects.size(); ++i) {
      if (scene.objects[i].type == ShapeType::plane)
        planes_.push_back(i);
      else
        bounds[i] = object_bounds(scene, i);
    }
    BvhBuildOptions build_options;
    build_options.threads = options.threads;
    bvh_ = build_bvh(bounds, build_options, scene.camera.position);
  }

  std::optional<Hit> intersect(const Ray& world_ray) const override {
    Ray ray = world_ray;
    Hit best;
    bool found = false;
    for (uint32_t p : planes_) {
      if (intersect_object(scene_, p, ray, best)) {
        ray.t_max = best.t;
        found = true;
      }
    }
    found |= traverse_closest(bvh_, ray, [&](uint32_t object, Ray& r) {
      if (!intersect_object(scene_, object, r, best)) return false;
      r.t_max = best.t;
      return true;
    });
    if (!found) return std::nullopt;
    return best;
  }

  bool occluded(const Ray& ray) const override { return first_blocker(ray).has_value(); }

  std::optional<uint32_t> first_blocker(const Ray& ray) const override {
    Hit scratch;
    for (uint32_t p : planes_)
      if (intersect_object(scene_, p, ray, scratch)) return p;
    std::optional<uint32_t> blocker;
    traverse_any(bvh_, ray, [&](uint32_t object, const Ray& r) {
      if (!intersect_object(scene_, object, r, scratch)) return false;
      blocker = object;
      return true;
    });
    return blocker;
  }

  size_t memory_bytes() const override {
    return bvh_.nodes.capacity() * sizeof(Bvh4Node) + bvh_.primitives.capacity() * sizeof(uint32_t) +
           planes_.capacity() * sizeof(uint32_t);
  }

 private:
  const Scene& scene_;
  std::vector<uint32_t> planes_;
  Bvh bvh_;
};

class BruteForceAccelerator final : public Accelerator {
 public:
  explicit BruteForceAccelerator(const Scene& scene) : scene_(scene) {}

  std::optional<Hit> intersect(const Ray& world_ray) const override {
    Ray ray = world_ray;
    Hit best;
    bool found = false;
    for (uint32_t i = 0; i < scene_.objects.size(); ++i) {
      if (intersect_object(scene_, i, ray, best)) {
        ray.t_max = best.t;
        found = true;
      }
    }
    if (!found) return std::nullopt;
    return best;
  }
  bool occluded(const Ray& ray) const override { return first_blocker(ray).has_value(); }
  std::optional<uint32_t> first_blocker(const Ray& ray) const override {
    Hit scratch;
    for (uint32_t i = 0; i < scene_.objects.size(); ++i)
      if (intersect_object(scene_, i, ray, scratch)) return i;
    return std::nullopt;
  }
  size_t memory_bytes() const override { return 0; }

 private:
  const Scene& scene_;
};

}  // namespace

std::unique_ptr<Accelerator> build_accelerator(const Scene& scene, const AcceleratorOptions& options) {
  return std::make_unique<BvhAccelerator>(scene, options);
}

std::unique_ptr<Accelerator> build_brute_force(const Scene& scene) {
  return std::make_unique<BruteForceAccelerator>(scene);
}

}  // namespace glint
