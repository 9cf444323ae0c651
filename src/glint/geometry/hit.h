// What a ray traversal finds (Hit), apart from the accelerator that finds it,
// so shading code (render/texture.h) can take a Hit without the accelerator.
#pragma once

#include <array>
#include <cstdint>

#include "glint/geometry/shape_types.h"
#include "glint/math/ray.h"
#include "glint/math/vec3.h"

namespace glint {

// A mesh triangle's vertices as the mesh stores them (floats).
using TriangleVertices = std::array<Vec3f, 3>;

// What traversal finds: enough to shade later, nothing more.
struct Hit {
  double t = kInfinity;
  uint32_t object = 0;
  double b1 = 0, b2 = 0;   // triangle barycentrics
  int face = 0;            // box face
  uint32_t primitive = 0;  // mesh objects: the triangle
  // Mesh objects: that triangle's vertices in the mesh's space (floats, as
  // meshes store them), copied where the traversal had them in cache.
  // Shading reading them again through the mesh's index and vertex arrays
  // missed the cache on big meshes.
  TriangleVertices vertices{};
};

inline TriangleVertices to_vertices(const Triangle& t) { return {to_vec3f(t.v0), to_vec3f(t.v1), to_vec3f(t.v2)}; }
inline Triangle to_triangle(const TriangleVertices& v) { return {to_vec3(v[0]), to_vec3(v[1]), to_vec3(v[2])}; }

}  // namespace glint
