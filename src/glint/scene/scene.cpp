#include "glint/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "glint/geometry/csg.h"
#include "glint/geometry/shapes.h"
#include "glint/geometry/torus.h"

namespace glint {

Scene::Scene() {
  Material default_material;
  default_material.name = "default";
  materials.push_back(default_material);
}

uint32_t add_material(Scene& scene, Material material) {
  scene.materials.push_back(std::move(material));
  return static_cast<uint32_t>(scene.materials.size() - 1);
}

namespace {

uint32_t add_object(Scene& scene, ShapeType type, size_t shape, uint32_t material, uint32_t transform = kNoTransform) {
  Object object;
  object.type = type;
  object.shape = static_cast<uint32_t>(shape);
  object.material = material;
  object.transform = transform;
  scene.objects.push_back(std::move(object));
  return static_cast<uint32_t>(scene.objects.size() - 1);
}

uint32_t add_transform(Scene& scene, const std::optional<Transform>& transform) {
  if (!transform || transform->is_identity()) return kNoTransform;
  scene.transforms.push_back(*transform);
  return static_cast<uint32_t>(scene.transforms.size() - 1);
}

}  // namespace

uint32_t add_sphere(Scene& scene, const Sphere& sphere, uint32_t material, const std::optional<Transform>& transform) {
  scene.spheres.push_back(sphere);
  return add_object(scene, ShapeType::sphere, scene.spheres.size() - 1, material, add_transform(scene, transform));
}

uint32_t add_plane(Scene& scene, const Plane& plane, uint32_t material, const std::optional<Transform>& transform) {
  Plane world = plane;
  if (transform) {
    world.point = transform->point(plane.point);
    world.normal = transform->normal(plane.normal);
  }
  world.normal = normalize(world.normal);
  scene.planes.push_back(world);
  return add_object(scene, ShapeType::plane, scene.planes.size() - 1, material);
}

uint32_t add_triangle(Scene& scene, const Triangle& triangle, uint32_t material,
                      const std::optional<Transform>& transform) {
  Triangle world = triangle;
  if (transform) {
    world.v0 = transform->point(triangle.v0);
    world.v1 = transform->point(triangle.v1);
    world.v2 = transform->point(triangle.v2);
  }
  scene.triangles.push_back(world);
  return add_object(scene, ShapeType::triangle, scene.triangles.size() - 1, material);
}

uint32_t add_box(Scene& scene, const Box& box, uint32_t material, const std::optional<Transform>& transform) {
  scene.boxes.push_back(box);
  return add_object(scene, ShapeType::box, scene.boxes.size() - 1, material, add_transform(scene, transform));
}

double fov_y_for_row_center_angle(double row_center_angle, int height) {
  if (height < 2) return row_center_angle;
  const double half = 0.5 * row_center_angle * std::numbers::pi / 180.0;
  return 2.0 * std::atan(std::tan(half) * height / (height - 1.0)) * 180.0 / std::numbers::pi;
}

double camera_fov_y(const Camera& camera, int height) {
  return camera.row_center_angle ? fov_y_for_row_center_angle(*camera.row_center_angle, height) : camera.fov_y;
}

uint32_t add_cone(Scene& scene, const Cone& cone, uint32_t material, const std::optional<Transform>& transform,
                  bool cylinder) {
  scene.cones.push_back(cone);
  return add_object(scene, cylinder ? ShapeType::cylinder : ShapeType::cone, scene.cones.size() - 1, material,
                    add_transform(scene, transform));
}

uint32_t add_disk(Scene& scene, const Disk& disk, uint32_t material, const std::optional<Transform>& transform) {
  scene.disks.push_back(disk);
  return add_object(scene, ShapeType::disk, scene.disks.size() - 1, material, add_transform(scene, transform));
}

uint32_t add_polygon(Scene& scene, Polygon polygon, uint32_t material, const std::optional<Transform>& transform) {
  polygon.bounds = Bounds3{};
  for (const Vec3& v : polygon.vertices) polygon.bounds.extend(v);
  scene.polygons.push_back(std::move(polygon));
  return add_object(scene, ShapeType::polygon, scene.polygons.size() - 1, material, add_transform(scene, transform));
}

uint32_t add_torus(Scene& scene, const Torus& torus, uint32_t material, const std::optional<Transform>& transform) {
  scene.tori.push_back(torus);
  return add_object(scene, ShapeType::torus, scene.tori.size() - 1, material, add_transform(scene, transform));
}

uint32_t add_csg(Scene& scene, Csg csg, uint32_t material, const std::optional<Transform>& transform) {
  csg.bounds = csg_bounds(csg);
  scene.csgs.push_back(std::move(csg));
  return add_object(scene, ShapeType::csg, scene.csgs.size() - 1, material, add_transform(scene, transform));
}

uint32_t add_mesh(Scene& scene, Mesh mesh) {
  mesh.bounds = Bounds3{};
  for (const Vec3f& p : mesh.positions) mesh.bounds.extend(to_vec3(p));
  scene.meshes.push_back(std::move(mesh));
  return static_cast<uint32_t>(scene.meshes.size() - 1);
}

uint32_t add_mesh_object(Scene& scene, uint32_t mesh, uint32_t material, bool smooth,
                         const std::optional<Transform>& transform) {
  const uint32_t index = add_object(scene, ShapeType::mesh, mesh, material, add_transform(scene, transform));
  scene.objects[index].smooth = smooth;
  return index;
}

Bounds3 object_bounds(const Scene& scene, uint32_t index) {
  const Object& object = scene.objects[index];
  Bounds3 b;
  switch (object.type) {
    case ShapeType::sphere: {
      const Sphere& s = scene.spheres[object.shape];
      b.extend(s.center - Vec3(s.radius));
      b.extend(s.center + Vec3(s.radius));
      break;
    }
    case ShapeType::box:
      b.extend(scene.boxes[object.shape].lo);
      b.extend(scene.boxes[object.shape].hi);
      break;
    case ShapeType::triangle: {
      const Triangle& t = scene.triangles[object.shape];
      b.extend(t.v0);
      b.extend(t.v1);
      b.extend(t.v2);
      break;
    }
    case ShapeType::mesh: b = scene.meshes[object.shape].bounds; break;
    case ShapeType::cylinder:
    case ShapeType::cone: b = cone_bounds(scene.cones[object.shape]); break;
    case ShapeType::disk: b = disk_bounds(scene.disks[object.shape]); break;
    case ShapeType::polygon: b = scene.polygons[object.shape].bounds; break;
    case ShapeType::torus: b = torus_bounds(scene.tori[object.shape]); break;
    case ShapeType::csg: b = scene.csgs[object.shape].bounds; break;
    case ShapeType::plane: return b;
  }
  if (object.transform != kNoTransform) b = scene.transforms[object.transform].bounds(b);
  return b;
}

double auto_epsilon(const Scene& scene) {
  // Doubles carry ~16 digits; 1e-7 of the scene's extent leaves a wide margin
  // over intersection round-off while staying invisible at any image size.
  double scale = max_abs_component(scene.camera.position);
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].type == ShapeType::plane) {
      scale = std::max(scale, max_abs_component(scene.planes[scene.objects[i].shape].point));
      continue;
    }
    Bounds3 b = object_bounds(scene, i);
    scale = std::max(scale, std::max(max_abs_component(b.lo), max_abs_component(b.hi)));
  }
  return 1e-7 * std::max(1.0, scale);
}

}  // namespace glint
