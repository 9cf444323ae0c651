// evaluate_hit: where a hit is, which way the surface faces there and what
// it reflects there, for every kind of shape: the geometry the shading
// formula (integrator.cpp) starts from.
#include <algorithm>
#include <array>
#include <cmath>

#include "glint/geometry/csg.h"
#include "glint/geometry/shapes.h"
#include "glint/geometry/torus.h"
#include "glint/render/integrator.h"
#include "glint/render/texture.h"

namespace glint {

namespace {

const Transform* xf_of(const Scene& scene, const Object& object) {
  return object.transform == kNoTransform ? nullptr : &scene.transforms[object.transform];
}

// The hit point in the object's own space, from the ray (as the
// intersection test saw it: same t).
Vec3 object_point(const Scene& scene, const Object& object, const Ray& ray, double t) {
  const Transform* xf = xf_of(scene, object);
  return xf ? xf->inverse_point(ray.origin) + t * xf->inverse_vector(ray.direction) : ray.at(t);
}

// Point and normal from object space to world space (normal through the
// inverse transpose), into sp.
void to_world(const Transform* xf, const Vec3& p_obj, const Vec3& n_obj, SurfacePoint& sp) {
  sp.p = xf ? xf->point(p_obj) : p_obj;
  sp.geometric_normal = xf ? normalize(xf->normal(n_obj)) : n_obj;
}

// A cylinder's or cone's hit: the lateral surface's outward normal, or a
// cap's axis direction away from the solid (docs: "Quadric and polygon
// normals"). The point is put back on the surface it hit, which removes
// the rounding of the ray's arithmetic.
void cone_geometry(const Cone& c, int part, const Vec3& p_obj, const Transform* xf, SurfacePoint& sp) {
  const Vec3 rel = p_obj - c.base;
  const double h = dot(rel, c.axis);
  const Vec3 radial = rel - h * c.axis;
  const double rl = length(radial);
  if (part == kConeBaseCap || part == kConeApexCap) {
    to_world(xf, (part == kConeApexCap ? c.apex : c.base) + radial, cone_normal(c, part, p_obj), sp);
    return;
  }
  const double k = (c.apex_radius - c.base_radius) / c.length;
  const double hc = std::clamp(h, 0.0, c.length);
  const Vec3 out = rl > 0.0 ? radial / rl : c.ref_u;
  const Vec3 p_side = c.base + hc * c.axis + (c.base_radius + k * hc) * out;
  to_world(xf, rl > 0.0 ? p_side : p_obj, cone_normal(c, part, p_obj), sp);
}

// A polygon's hit: the point on the triangle that was hit, the polygon's
// normal (first three vertices, by the right-hand rule in world space, as for
// triangles) and, with vertex normals, their interpolation on that fan triangle.
void polygon_geometry(const Polygon& poly, const Hit& hit, const Transform* xf, SurfacePoint& sp) {
  const std::array<uint32_t, 3>& tri = poly.triangles[hit.primitive];
  const Vec3& v0 = poly.vertices[tri[0]];
  const Vec3 p_obj = v0 + hit.b1 * (poly.vertices[tri[1]] - v0) + hit.b2 * (poly.vertices[tri[2]] - v0);
  sp.p = xf ? xf->point(p_obj) : p_obj;
  if (xf) {
    const Vec3 e1 = xf->vector(poly.vertices[1] - poly.vertices[0]);
    const Vec3 e2 = xf->vector(poly.vertices[2] - poly.vertices[0]);
    sp.geometric_normal = normalize(cross(e1, e2));
  } else {
    sp.geometric_normal = poly.normal;
  }
  sp.shading_normal = sp.geometric_normal;
  if (poly.normals.empty()) return;
  Vec3 n[3];
  for (int i = 0; i < 3; ++i) {
    n[i] = poly.normals[tri[i]];  // unit (the loader normalized them)
    if (xf) n[i] = normalize(xf->normal(n[i]));
  }
  const Vec3 s = (1.0 - hit.b1 - hit.b2) * n[0] + hit.b1 * n[1] + hit.b2 * n[2];
  const double len = length(s);
  if (len > 0.0 && std::isfinite(len)) sp.shading_normal = s / len;
}

// Where the hit is and which way the surface faces there.
SurfacePoint evaluate_geometry(const Scene& scene, const Ray& ray, const Hit& hit) {
  const Object& object = scene.objects[hit.object];
  SurfacePoint sp;
  sp.material = object.material;
  switch (object.type) {
    case ShapeType::sphere: {
      const Sphere& s = scene.spheres[object.shape];
      Vec3 p_obj;
      if (object.transform == kNoTransform) {
        p_obj = ray.at(hit.t);
      } else {
        const Transform& xf = scene.transforms[object.transform];
        p_obj = xf.inverse_point(ray.origin) + hit.t * xf.inverse_vector(ray.direction);
      }
      // Project back onto the sphere: removes the hit point's rounding error.
      const Vec3 n_obj = normalize(p_obj - s.center);
      p_obj = s.center + s.radius * n_obj;
      if (object.transform == kNoTransform) {
        sp.p = p_obj;
        sp.geometric_normal = n_obj;
      } else {
        const Transform& xf = scene.transforms[object.transform];
        sp.p = xf.point(p_obj);
        sp.geometric_normal = normalize(xf.normal(n_obj));
      }
      break;
    }
    case ShapeType::box: {
      Vec3 n_obj = box_face_normal(hit.face);
      sp.p = ray.at(hit.t);
      if (object.transform != kNoTransform) n_obj = scene.transforms[object.transform].normal(n_obj);
      sp.geometric_normal = normalize(n_obj);
      break;
    }
    case ShapeType::triangle: {
      const Triangle& t = scene.triangles[object.shape];
      const Vec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0;
      sp.p = t.v0 + hit.b1 * e1 + hit.b2 * e2;
      sp.geometric_normal = normalize(cross(e1, e2));
      break;
    }
    case ShapeType::mesh: {
      const Mesh& mesh = scene.meshes[object.shape];
      const Triangle t = to_triangle(hit.vertices);
      const Vec3 e1 = t.v1 - t.v0, e2 = t.v2 - t.v0;
      const Vec3 p_obj = t.v0 + hit.b1 * e1 + hit.b2 * e2;
      Vec3 ng = cross(e1, e2);
      const Transform* xf = object.transform == kNoTransform ? nullptr : &scene.transforms[object.transform];
      sp.p = xf ? xf->point(p_obj) : p_obj;
      sp.geometric_normal = normalize(xf ? xf->normal(ng) : ng);
      sp.shading_normal = sp.geometric_normal;
      // Meshes only shaded flat have no vertex normals (scene loader).
      if (object.smooth && mesh.corner_normals.size() == mesh.indices.size()) {
        const Vec3f* corner = &mesh.corner_normals[3 * static_cast<size_t>(hit.primitive)];
        Vec3 n0 = to_vec3(corner[0]), n1 = to_vec3(corner[1]), n2 = to_vec3(corner[2]);
        if (xf) {
          // Vertex normals through the inverse transpose, each normalized
          // before interpolation (the contract's order).
          n0 = normalize(xf->normal(n0));
          n1 = normalize(xf->normal(n1));
          n2 = normalize(xf->normal(n2));
        }
        const Vec3 n = (1.0 - hit.b1 - hit.b2) * n0 + hit.b1 * n1 + hit.b2 * n2;
        const double len = length(n);
        if (len > 0.0 && std::isfinite(len)) sp.shading_normal = n / len;
      }
      if (object.material == kMeshMaterials) sp.material = mesh.triangle_material[hit.primitive];
      return sp;
    }
    case ShapeType::cylinder:
    case ShapeType::cone:
      cone_geometry(scene.cones[object.shape], hit.face, object_point(scene, object, ray, hit.t), xf_of(scene, object),
                    sp);
      break;
    case ShapeType::disk: {
      const Disk& d = scene.disks[object.shape];
      Vec3 p_obj = object_point(scene, object, ray, hit.t);
      p_obj -= dot(p_obj - d.center, d.normal) * d.normal;  // onto the disk's plane exactly
      to_world(xf_of(scene, object), p_obj, d.normal, sp);
      break;
    }
    case ShapeType::polygon: {
      polygon_geometry(scene.polygons[object.shape], hit, xf_of(scene, object), sp);
      return sp;
    }
    case ShapeType::torus: {
      const Vec3 p_obj = object_point(scene, object, ray, hit.t);
      to_world(xf_of(scene, object), p_obj, torus_normal(scene.tori[object.shape], p_obj), sp);
      break;
    }
    case ShapeType::csg: {
      // The leaf's surface, its normal turned out of the result where the
      // leaf was subtracted, and the leaf's material.
      const CsgLeaf& leaf = scene.csgs[object.shape].leaves[hit.primitive];
      const Vec3 p_obj = object_point(scene, object, ray, hit.t);
      const Vec3 p_leaf = leaf.transform ? leaf.transform->inverse_point(p_obj) : p_obj;
      Vec3 n = csg_leaf_normal(leaf, hit.face / 2, p_leaf);
      if (leaf.transform) n = normalize(leaf.transform->normal(n));
      if (hit.face & 1) n = -n;
      to_world(xf_of(scene, object), p_obj, n, sp);
      sp.material = leaf.material;
      break;
    }
    case ShapeType::plane: {
      const Plane& pl = scene.planes[object.shape];
      sp.p = ray.at(hit.t);
      sp.p -= dot(sp.p - pl.point, pl.normal) * pl.normal;  // onto the plane exactly
      sp.geometric_normal = pl.normal;
      break;
    }
  }
  sp.shading_normal = sp.geometric_normal;
  return sp;
}

}  // namespace

SurfacePoint evaluate_hit(const Scene& scene, const Ray& ray, const Hit& hit) {
  SurfacePoint sp = evaluate_geometry(scene, ray, hit);
  const Material& m = scene.materials[sp.material];
  sp.reflectance = {m.ambient, m.diffuse, m.specular};
  if (m.textured()) {  // plain colors never get here: no uv, no lookups
    sp.textured = true;
    sp.uv = surface_uv(scene, hit, sp.p);
    if (m.ambient_texture != kNoTexture)
      sp.reflectance.ambient = evaluate_texture(scene, scene.textures[m.ambient_texture], sp.uv);
    if (m.diffuse_texture != kNoTexture)
      sp.reflectance.diffuse = evaluate_texture(scene, scene.textures[m.diffuse_texture], sp.uv);
    if (m.specular_texture != kNoTexture)
      sp.reflectance.specular = evaluate_texture(scene, scene.textures[m.specular_texture], sp.uv);
  }
  return sp;
}

}  // namespace glint
