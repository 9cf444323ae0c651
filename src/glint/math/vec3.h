// Vec3: the 3-vector of doubles used for points, directions, normals and RGB
// colors alike. Shading is done in double so the formula's values come out
// exact to well below the 1e-5 the tests (and users comparing renderers) ask for.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

namespace glint {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3(double v) : x(v), y(v), z(v) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  constexpr Vec3& operator*=(double s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr Vec3& operator*=(const Vec3& o) {
    x *= o.x;
    y *= o.y;
    z *= o.z;
    return *this;
  }
  constexpr Vec3& operator/=(double s) { return *this *= 1.0 / s; }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
constexpr Vec3 operator*(Vec3 a, const Vec3& b) { return a *= b; }  // per component (colors)
constexpr Vec3 operator/(Vec3 a, double s) { return a /= s; }

constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(const Vec3& v) { return v / length(v); }
inline Vec3 min(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 max(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline double max_abs_component(const Vec3& v) {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}
inline bool is_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool is_black(const Vec3& c) { return c.x == 0 && c.y == 0 && c.z == 0; }
// d / |d| without overflow or underflow of the length (the largest component
// divides first, so 1e300 or 1e-300 components work), or nullopt for a zero
// or non-finite d: how a scene's directions are read.
inline std::optional<Vec3> unit_direction(const Vec3& d) {
  const double big = max_abs_component(d);
  if (!(big > 0) || !std::isfinite(big)) return std::nullopt;
  const Vec3 s = d / big;
  return s / length(s);
}

// Mirror direction of d about the normal n (unit n; d need not be unit).
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.0 * dot(d, n) * n; }

using Color = Vec3;

// Compact storage for mesh data (positions, normals); math is done in Vec3.
struct Vec3f {
  float x = 0, y = 0, z = 0;
};
inline Vec3 to_vec3(const Vec3f& v) { return {v.x, v.y, v.z}; }
inline Vec3f to_vec3f(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

}  // namespace glint
