#include "glint/math/transform.h"

#include <cmath>
#include <numbers>

namespace glint {

namespace {

Affine multiply(const Affine& b, const Affine& a) {
  Affine r{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? b[i][3] : 0.0;
      for (int k = 0; k < 3; ++k) s += b[i][k] * a[k][j];
      r[i][j] = s;
    }
  }
  return r;
}

}  // namespace

std::optional<Transform> Transform::from_affine(const Affine& a) {
  // Judge singularity on the linear part divided by its largest entry, so
  // huge or tiny but well-conditioned scales neither overflow nor fail.
  double scale = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) scale = std::max(scale, std::abs(a[i][j]));
  if (!(scale > 0.0) || !std::isfinite(scale)) return std::nullopt;
  double u[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) u[i][j] = a[i][j] / scale;
  const double unit_det = u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) -
                          u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
                          u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0]);
  if (!(std::abs(unit_det) > 1e-12)) return std::nullopt;
  // Inverse of the scaled 3x3 part by cofactors, then undo the scaling:
  // inverse(a) = inverse(u) / scale. The translation follows.
  const double id = 1.0 / (unit_det * scale);
  Affine inv{};
  inv[0][0] = (u[1][1] * u[2][2] - u[1][2] * u[2][1]) * id;
  inv[0][1] = (u[0][2] * u[2][1] - u[0][1] * u[2][2]) * id;
  inv[0][2] = (u[0][1] * u[1][2] - u[0][2] * u[1][1]) * id;
  inv[1][0] = (u[1][2] * u[2][0] - u[1][0] * u[2][2]) * id;
  inv[1][1] = (u[0][0] * u[2][2] - u[0][2] * u[2][0]) * id;
  inv[1][2] = (u[0][2] * u[1][0] - u[0][0] * u[1][2]) * id;
  inv[2][0] = (u[1][0] * u[2][1] - u[1][1] * u[2][0]) * id;
  inv[2][1] = (u[0][1] * u[2][0] - u[0][0] * u[2][1]) * id;
  inv[2][2] = (u[0][0] * u[1][1] - u[0][1] * u[1][0]) * id;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(inv[i][j])) return std::nullopt;
  for (int i = 0; i < 3; ++i) inv[i][3] = -(inv[i][0] * a[0][3] + inv[i][1] * a[1][3] + inv[i][2] * a[2][3]);
  Transform t;
  t.m = a;
  t.inv = inv;
  return t;
}

Transform Transform::translate(const Vec3& v) {
  Transform t;
  t.m[0][3] = v.x;
  t.m[1][3] = v.y;
  t.m[2][3] = v.z;
  t.inv[0][3] = -v.x;
  t.inv[1][3] = -v.y;
  t.inv[2][3] = -v.z;
  return t;
}

Transform Transform::scale(const Vec3& s) {
  Transform t;
  for (int i = 0; i < 3; ++i) {
    t.m[i][i] = s[i];
    t.inv[i][i] = 1.0 / s[i];
  }
  return t;
}

Transform Transform::rotate(const Vec3& a, double degrees) {
  // Rodrigues' formula; the inverse of a rotation is its transpose.
  const double rad = degrees * std::numbers::pi / 180.0;
  const double c = std::cos(rad), s = std::sin(rad), k = 1.0 - c;
  Transform t;
  t.m = {{{c + a.x * a.x * k, a.x * a.y * k - a.z * s, a.x * a.z * k + a.y * s, 0},
          {a.y * a.x * k + a.z * s, c + a.y * a.y * k, a.y * a.z * k - a.x * s, 0},
          {a.z * a.x * k - a.y * s, a.z * a.y * k + a.x * s, c + a.z * a.z * k, 0}}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.inv[i][j] = t.m[j][i];
  return t;
}

Bounds3 Transform::bounds(const Bounds3& b) const {
  Bounds3 out;
  for (int corner = 0; corner < 8; ++corner) {
    out.extend(point({corner & 1 ? b.hi.x : b.lo.x, corner & 2 ? b.hi.y : b.lo.y, corner & 4 ? b.hi.z : b.lo.z}));
  }
  return out;
}

Transform compose(const Transform& b, const Transform& a) {
  Transform t;
  t.m = multiply(b.m, a.m);
  t.inv = multiply(a.inv, b.inv);
  return t;
}

}  // namespace glint
