// Bounds3: an axis-aligned box, the currency of the BVH.
#pragma once

#include "glint/math/ray.h"

namespace glint {

struct Bounds3 {
  Vec3 lo{kInfinity, kInfinity, kInfinity};
  Vec3 hi{-kInfinity, -kInfinity, -kInfinity};

  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(const Vec3& p) {
    lo = min(lo, p);
    hi = max(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = min(lo, b.lo);
    hi = max(hi, b.hi);
  }
  Vec3 center() const { return 0.5 * (lo + hi); }
  Vec3 diagonal() const { return hi - lo; }
  double surface_area() const {
    if (empty()) return 0.0;
    Vec3 d = diagonal();
    return 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  int longest_axis() const {
    Vec3 d = diagonal();
    return d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
  }
};

}  // namespace glint
