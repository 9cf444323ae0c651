#include "glint/render/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "glint/geometry/csg.h"
#include "glint/geometry/shapes.h"
#include "glint/geometry/torus.h"

namespace glint {

int wrap_texel(long long i, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::clamp: return static_cast<int>(std::clamp<long long>(i, 0, n - 1));
    case TextureWrap::mirror: {
      long long m = i % (2LL * n);
      if (m < 0) m += 2LL * n;
      return static_cast<int>(m < n ? m : 2LL * n - 1 - m);
    }
    case TextureWrap::repeat: break;
  }
  long long m = i % n;
  return static_cast<int>(m < 0 ? m + n : m);
}

namespace {

// Reduces a coordinate to one period of the wrap mode before it becomes a
// texel index, so huge u, v neither overflow nor lose the fraction; NaN -> 0.
double reduce(double t, TextureWrap wrap) {
  if (!std::isfinite(t)) return 0.0;
  switch (wrap) {
    case TextureWrap::repeat: return t - std::floor(t);
    case TextureWrap::mirror: return t - 2.0 * std::floor(0.5 * t);
    case TextureWrap::clamp: return std::clamp(t, -1.0, 2.0);
  }
  return t;
}

Color texel(const TextureImage& image, int x, int y) {
  return to_vec3(image.texels[static_cast<size_t>(y) * static_cast<size_t>(image.width) + static_cast<size_t>(x)]);
}

// The bilinear blend of the four texels around continuous texel coordinates
// (x, y) (texel centers at whole numbers, y down from the top row), each
// axis wrapped by its own mode.
Color bilinear(const TextureImage& image, double x, double y, TextureWrap wrap_x, TextureWrap wrap_y) {
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const auto ix = static_cast<long long>(x0), iy = static_cast<long long>(y0);
  const int xa = wrap_texel(ix, image.width, wrap_x), xb = wrap_texel(ix + 1, image.width, wrap_x);
  const int ya = wrap_texel(iy, image.height, wrap_y), yb = wrap_texel(iy + 1, image.height, wrap_y);
  const Color top = (1.0 - fx) * texel(image, xa, ya) + fx * texel(image, xb, ya);
  const Color bottom = (1.0 - fx) * texel(image, xa, yb) + fx * texel(image, xb, yb);
  return (1.0 - fy) * top + fy * bottom;
}

}  // namespace

Color sample_image(const TextureImage& image, double u, double v, TextureWrap wrap) {
  if (image.width <= 0 || image.height <= 0) return Color(0.0);
  return bilinear(image, reduce(u, wrap) * image.width - 0.5, (1.0 - reduce(v, wrap)) * image.height - 0.5, wrap,
                  wrap);
}

Color evaluate_texture(const Scene& scene, const Texture& texture, UV uv) {
  const double u = uv.u * texture.scale_u + texture.offset_u;
  const double v = uv.v * texture.scale_v + texture.offset_v;
  if (texture.kind == TextureKind::checker) {
    if (!std::isfinite(u) || !std::isfinite(v)) return texture.even;
    const double cells = std::floor(u) + std::floor(v);
    return std::fmod(std::abs(cells), 2.0) == 0.0 ? texture.even : texture.odd;
  }
  return sample_image(scene.texture_images[texture.image], u, v, texture.wrap);
}

EnvironmentLookup sample_environment(const Scene& scene, const Environment& environment, const Vec3& direction) {
  EnvironmentLookup out;
  const TextureImage& image = scene.texture_images[environment.image];
  const double len = length(direction);
  const Vec3 d = len > 0.0 ? direction / len : Vec3(0, 0, -1);
  double u = 0.5 + std::atan2(d.x, -d.z) / (2.0 * std::numbers::pi) + environment.rotate / 360.0;
  u -= std::floor(u);
  if (!(u >= 0.0 && u < 1.0)) u = 0.0;  // NaN, or a u just below 1 that rounded up
  out.u = u;
  out.v = std::acos(std::clamp(d.y, -1.0, 1.0)) / std::numbers::pi;
  if (image.width <= 0 || image.height <= 0) return out;
  // u wraps around the sphere, v stops at the poles (row 0 is straight up).
  out.color = environment.scale * bilinear(image, out.u * image.width - 0.5, out.v * image.height - 0.5,
                                           TextureWrap::repeat, TextureWrap::clamp);
  return out;
}

void plane_frame(const Vec3& n, Vec3& e_u, Vec3& e_v) {
  const bool y_largest = std::abs(n.y) >= std::abs(n.x) && std::abs(n.y) >= std::abs(n.z);
  const Vec3 r = y_largest ? Vec3(0, 0, 1) : Vec3(0, -1, 0);
  e_u = normalize(cross(n, r));
  e_v = cross(n, e_u);
}

UV sphere_uv(const Vec3& d) {
  const double theta = std::acos(std::clamp(d.y, -1.0, 1.0));
  return {0.5 + std::atan2(d.x, d.z) / (2.0 * std::numbers::pi), 1.0 - theta / std::numbers::pi};
}

namespace {

// Where t lies between lo and hi along +axis (sign > 0) or -axis, as 0..1.
double along(double t, double lo, double hi, double sign) {
  return sign > 0 ? (t - lo) / (hi - lo) : (hi - t) / (hi - lo);
}

UV barycentric_uv(const UV& a, const UV& b, const UV& c, double b1, double b2) {
  const double b0 = 1.0 - b1 - b2;
  return {b0 * a.u + b1 * b.u + b2 * c.u, b0 * a.v + b1 * b.v + b2 * c.v};
}

// A disk of radius r (offset q from its center, unit normal n) covers the
// unit square once: the square of side 2r around it, along the plane frame
// of n, so that u and v run from 0 to 1 across the disk (0.5 at the center).
UV disk_uv(const Vec3& q, const Vec3& n, double r) {
  Vec3 e_u, e_v;
  plane_frame(n, e_u, e_v);
  if (!(r > 0)) return {0.5, 0.5};
  return {0.5 + dot(q, e_u) / (2.0 * r), 0.5 + dot(q, e_v) / (2.0 * r)};
}

// Each face shows the unit square once, oriented by the plane frame of its
// outward normal (whose axes are box axes, up to sign). q in the box's space.
UV box_uv(const Box& b, int face, const Vec3& q) {
  Vec3 e_u, e_v;
  plane_frame(box_face_normal(face), e_u, e_v);
  UV uv;
  for (int axis = 0; axis < 3; ++axis) {
    if (e_u[axis] != 0) uv.u = along(q[axis], b.lo[axis], b.hi[axis], e_u[axis]);
    if (e_v[axis] != 0) uv.v = along(q[axis], b.lo[axis], b.hi[axis], e_v[axis]);
  }
  return uv;
}

UV cone_uv(const Cone& c, int part, const Vec3& q) {
  const Vec3 rel = q - c.base;
  const double h = dot(rel, c.axis);
  const Vec3 radial = rel - h * c.axis;
  if (part == kConeSide) {
    // Angle about the axis by the right-hand rule from ref_u, and height.
    const double angle = std::atan2(dot(radial, cross(c.axis, c.ref_u)), dot(radial, c.ref_u));
    double u = angle / (2.0 * std::numbers::pi);
    if (u < 0) u += 1.0;
    return {u, h / c.length};
  }
  // A cap: its square of side 2r, as a disk with the cap's outward normal.
  const bool apex = part == kConeApexCap;
  return disk_uv(radial, apex ? c.axis : -c.axis, apex ? c.apex_radius : c.base_radius);
}

// u: the angle about the axis from the plane frame's e_u (right-hand rule);
// v: the angle about the tube, 0 at the outer equator, growing toward +axis.
UV torus_uv(const Torus& t, const Vec3& q) {
  Vec3 e_u, e_v;
  plane_frame(t.axis, e_u, e_v);
  const Vec3 rel = q - t.center;
  const double h = dot(rel, t.axis);
  const Vec3 radial = rel - h * t.axis;
  const double rl = length(radial);
  const double two_pi = 2.0 * std::numbers::pi;
  double u = std::atan2(dot(radial, cross(t.axis, e_u)), dot(radial, e_u)) / two_pi;
  double v = std::atan2(h, rl - t.major_radius) / two_pi;
  if (u < 0) u += 1.0;
  if (v < 0) v += 1.0;
  return {u, v};
}

}  // namespace

UV surface_uv(const Scene& scene, const Hit& hit, const Vec3& p) {
  const Object& object = scene.objects[hit.object];
  const auto to_object = [&](const Vec3& q) {
    return object.transform == kNoTransform ? q : scene.transforms[object.transform].inverse_point(q);
  };
  switch (object.type) {
    case ShapeType::sphere: {
      const Sphere& s = scene.spheres[object.shape];
      return sphere_uv(normalize(to_object(p) - s.center));
    }
    case ShapeType::plane: {
      const Plane& pl = scene.planes[object.shape];
      Vec3 e_u, e_v;
      plane_frame(pl.normal, e_u, e_v);
      return {dot(p - pl.point, e_u), dot(p - pl.point, e_v)};
    }
    case ShapeType::box: return box_uv(scene.boxes[object.shape], hit.face, to_object(p));
    case ShapeType::triangle: {
      static constexpr std::array<UV, 3> kDefault{UV{0, 0}, UV{1, 0}, UV{0, 1}};
      const auto it = scene.triangle_uvs.find(object.shape);
      const std::array<UV, 3>& c = it == scene.triangle_uvs.end() ? kDefault : it->second;
      return barycentric_uv(c[0], c[1], c[2], hit.b1, hit.b2);
    }
    case ShapeType::cylinder:
    case ShapeType::cone: return cone_uv(scene.cones[object.shape], hit.face, to_object(p));
    case ShapeType::torus: return torus_uv(scene.tori[object.shape], to_object(p));
    case ShapeType::csg: {
      // The leaf's own (u, v), in its own space.
      const CsgLeaf& leaf = scene.csgs[object.shape].leaves[hit.primitive];
      const Vec3 q = leaf.transform ? leaf.transform->inverse_point(to_object(p)) : to_object(p);
      switch (leaf.type) {
        case CsgLeafType::sphere: return sphere_uv(normalize(q - leaf.sphere.center));
        case CsgLeafType::box: return box_uv(leaf.box, hit.face / 2, q);
        case CsgLeafType::cone: return cone_uv(leaf.cone, hit.face / 2, q);
        case CsgLeafType::torus: return torus_uv(leaf.torus, q);
      }
      return {};
    }
    case ShapeType::disk: {
      const Disk& d = scene.disks[object.shape];
      return disk_uv(to_object(p) - d.center, d.normal, d.radius);
    }
    case ShapeType::polygon: {
      // As a plane through vertex 0 with the polygon's normal, in object space.
      const Polygon& poly = scene.polygons[object.shape];
      Vec3 e_u, e_v;
      plane_frame(poly.normal, e_u, e_v);
      const Vec3 q = to_object(p) - poly.vertices[0];
      return {dot(q, e_u), dot(q, e_v)};
    }
    case ShapeType::mesh: {
      const Mesh& mesh = scene.meshes[object.shape];
      if (mesh.corner_uvs.empty()) return {hit.b1, hit.b2};
      const UVf* c = &mesh.corner_uvs[3 * static_cast<size_t>(hit.primitive)];
      return barycentric_uv({c[0].u, c[0].v}, {c[1].u, c[1].v}, {c[2].u, c[2].v}, hit.b1, hit.b2);
    }
  }
  return {};
}

}  // namespace glint
