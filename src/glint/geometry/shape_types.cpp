#include "glint/geometry/shape_types.h"

#include <cmath>

namespace glint {

Cone make_cone(const Vec3& base, const Vec3& apex, double base_radius, double apex_radius, bool caps) {
  Cone c;
  c.base = base;
  c.apex = apex;
  c.base_radius = base_radius;
  c.apex_radius = apex_radius;
  c.caps = caps;
  const Vec3 d = apex - base;
  c.length = length(d);
  c.axis = d / c.length;
  // u = 0 lies along the plane frame's e_u of the axis (as for a plane with
  // that normal): +x for a +y axis.
  const Vec3& a = c.axis;
  const bool y_largest = std::abs(a.y) >= std::abs(a.x) && std::abs(a.y) >= std::abs(a.z);
  c.ref_u = normalize(cross(a, y_largest ? Vec3(0, 0, 1) : Vec3(0, -1, 0)));
  return c;
}

}  // namespace glint
