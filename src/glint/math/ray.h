// Ray: origin, direction and the open interval (t_min, t_max) of distances
// along it that count as hits. Directions need not be unit length; t is in
// units of the direction's length, which lets shadow rays end exactly at a light.
#pragma once

#include <limits>

#include "glint/math/vec3.h"

namespace glint {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Ray {
  Vec3 origin;
  Vec3 direction;
  double t_min = 0.0;
  double t_max = kInfinity;

  Vec3 at(double t) const { return origin + t * direction; }
};

}  // namespace glint
