// Transform: an affine map of 3-space (a 4x4 matrix whose last row is 0 0 0 1)
// together with its inverse, so points, directions and normals can be moved
// both ways. Normals go through the inverse transpose.
#pragma once

#include <array>
#include <optional>

#include "glint/math/bounds.h"

namespace glint {

// Row-major 3x4: m[r][c], c == 3 is the translation column.
using Affine = std::array<std::array<double, 4>, 3>;

struct Transform {
  Affine m = identity_affine();
  Affine inv = identity_affine();

  static constexpr Affine identity_affine() { return {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}}; }

  // nullopt when the linear part is singular (|det| tiny next to its scale).
  static std::optional<Transform> from_affine(const Affine& a);
  static Transform translate(const Vec3& t);
  static Transform scale(const Vec3& s);                           // s != 0
  static Transform rotate(const Vec3& unit_axis, double degrees);  // right-hand rule

  Vec3 point(const Vec3& p) const { return apply(m, p, 1.0); }
  Vec3 vector(const Vec3& v) const { return apply(m, v, 0.0); }
  Vec3 inverse_point(const Vec3& p) const { return apply(inv, p, 1.0); }
  Vec3 inverse_vector(const Vec3& v) const { return apply(inv, v, 0.0); }
  // Normal of the transformed surface (not normalized): inverse transpose.
  Vec3 normal(const Vec3& n) const {
    return {inv[0][0] * n.x + inv[1][0] * n.y + inv[2][0] * n.z, inv[0][1] * n.x + inv[1][1] * n.y + inv[2][1] * n.z,
            inv[0][2] * n.x + inv[1][2] * n.y + inv[2][2] * n.z};
  }
  Bounds3 bounds(const Bounds3& b) const;  // world box around a transformed box

  bool is_identity() const { return m == identity_affine(); }

 private:
  static Vec3 apply(const Affine& a, const Vec3& p, double w) {
    return {a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3] * w,
            a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3] * w,
            a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3] * w};
  }
};

// b after a: (compose(b, a)).point(p) == b.point(a.point(p)).
Transform compose(const Transform& b, const Transform& a);

}  // namespace glint
