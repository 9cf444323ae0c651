// The brute-force accelerator: every object tested for every ray. The
// reference that tests compare the BVH and Embree against.
#include "glint/accel/accelerator.h"

namespace glint {
namespace {

class BruteForceAccelerator final : public Accelerator {
 public:
  explicit BruteForceAccelerator(const Scene& scene) : scene_(scene) {}

  std::optional<Hit> intersect(const Ray& world_ray) const override {
    Ray ray = world_ray;
    // Filled in place and returned as is (no copy of the Hit: see set_hit).
    std::optional<Hit> result(std::in_place);
    Hit& best = *result;
    bool found = false;
    for (uint32_t i = 0; i < scene_.objects.size(); ++i) {
      if (intersect_object(scene_, i, ray, best)) {
        ray.t_max = best.t;
        found = true;
      }
    }
    if (!found) result.reset();
    return result;
  }
  bool occluded(const Ray& ray) const override { return first_blocker(ray).has_value(); }
  std::optional<uint32_t> first_blocker(const Ray& ray) const override {
    for (uint32_t i = 0; i < scene_.objects.size(); ++i)
      if (occludes_object(scene_, i, ray)) return i;
    return std::nullopt;
  }
  size_t memory_bytes() const override { return 0; }

 private:
  const Scene& scene_;
};

}  // namespace

std::unique_ptr<Accelerator> build_brute_force(const Scene& scene) {
  return std::make_unique<BruteForceAccelerator>(scene);
}

}  // namespace glint
