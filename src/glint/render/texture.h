// Textures at a hit: the surface coordinates (u, v) of a point on each kind of
// shape, and a texture's value there (bilinear image lookup with wrap modes,
// or a checkerboard). The conventions are in docs/scene-format.md, "Textures".
#pragma once

#include "glint/geometry/hit.h"
#include "glint/scene/scene.h"

namespace glint {

// A texel index i wrapped into [0, n) by the mode (mirror: ... 1 0 | 0 1 ... n-1 | n-1 ...).
int wrap_texel(long long i, int n, TextureWrap wrap);

// Bilinear lookup: u runs left to right, v bottom to top; texel (i, j) (row j
// from the top) has its center at u = (i + 0.5)/width, v = 1 - (j + 0.5)/height.
Color sample_image(const TextureImage& image, double u, double v, TextureWrap wrap);

// The texture's value at surface coordinates `uv` (after its scale and offset).
Color evaluate_texture(const Scene& scene, const Texture& texture, UV uv);

// The orthonormal frame (e_u, e_v) of a plane with unit normal n: e_u = n x r,
// e_v = n x e_u, where r = +z when |n.y| is n's largest component, else -y.
// A floor (n = +y) gets e_u = +x, e_v = -z; a wall facing +z gets +x, +y.
void plane_frame(const Vec3& n, Vec3& e_u, Vec3& e_v);

// Spherical coordinates of a unit direction d from a sphere's center, in
// object space: u = 0.5 + atan2(d.x, d.z) / 2pi (u = 0.5 faces +z, growing
// toward +x), v = 1 - theta / pi with theta the angle from +y (v = 1 at the top).
UV sphere_uv(const Vec3& d);

// The environment seen along a direction (render.environment): u, v of the
// latitude-longitude map (u from atan2(d.x, -d.z), v = 0 straight up; row 0
// at the top), bilinear, u wrapping and v clamped, times the scale.
struct EnvironmentLookup {
  double u = 0, v = 0;
  Color color;
};
EnvironmentLookup sample_environment(const Scene& scene, const Environment& environment, const Vec3& direction);

// (u, v) of the hit at world point p (the point evaluate_hit gives).
UV surface_uv(const Scene& scene, const Hit& hit, const Vec3& p);

}  // namespace glint
