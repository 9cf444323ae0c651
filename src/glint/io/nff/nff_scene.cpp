// An NFF file's parts straight to a Scene, with no JSON document in between:
// the mapping of docs/scene-format.md ("NFF scenes"), and the JSON loader's
// checks on the values that mapping makes (a zero radius, a negative color,
// a degenerate polygon), each reported at the NFF entity behind it in the
// loader's words. The JSON text `glint convert` writes is the other road to
// the same scene: tests/test_nff.cpp and fuzz/fuzz_nff.cpp hold the two to
// the same scenes and the same errors.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "glint/geometry/polygon.h"
#include "glint/io/loader/scene_reader.h"
#include "glint/io/nff/nff_parts.h"
#include "glint/io/scene_loader.h"

namespace glint::nff {

namespace {

using loader::format_number;

class SceneBuilder {
 public:
  SceneBuilder(const Parts& parts, std::vector<Error>* errors) : parts_(parts), errors_(errors) {}

  Scene build() {
    collect([&] { render(); });
    collect([&] { camera(); });
    material_index_.assign(parts_.materials.size(), 0);  // a broken material: the default one
    for (size_t i = 0; i < parts_.materials.size(); ++i) collect([&] { material(i); });
    if (!parts_.lights.empty()) {
      const double gray = light_gray(parts_);
      for (size_t i = 0; i < parts_.lights.size(); ++i) collect([&] { point_light(i, gray); });
      glint::Light ambient;
      ambient.type = LightType::ambient;
      ambient.ambient = Color(gray);
      ambient.diffuse = ambient.specular = Color(0.0);
      scene_.lights.push_back(ambient);
    }
    scene_.objects.reserve(parts_.objects.size());
    for (size_t i = 0; i < parts_.objects.size(); ++i) collect([&] { object(i); });
    // The view's angle spans the rows' centers: fov_y follows the rendered height.
    scene_.camera.row_center_angle = parts_.view.angle;
    return std::move(scene_);
  }

 private:
  // Runs `step`; a glint::Error it throws is recorded when collecting (one
  // per section, material, light and object, as the loader does), else
  // passed on.
  template <class Step>
  void collect(Step&& step) {
    if (!errors_) return step();
    try {
      step();
    } catch (const Error& e) {
      errors_->push_back(e);
    }
  }

  // The problem with `key` of a part ("" for the part itself: a render or
  // camera member), at its entity: "s: radius: must be > 0 (got 0)".
  [[noreturn]] void fail(Section section, size_t index, const std::string& key, const std::string& what) const {
    const NffOrigin origin = origin_of(parts_, section, index).second;
    throw Error(origin.where, origin.entity + ": " + (key.empty() ? what : key + ": " + what));
  }
  // The loader's checks of one value, in its words.
  Color color(const Color& c, Section section, size_t index, const std::string& key) const {
    for (int axis = 0; axis < 3; ++axis)
      if (!std::isfinite(c[axis]))
        fail(section, index, key + "[" + std::to_string(axis) + "]", "must be a finite number");
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(section, index, key, "color components must be >= 0");
    return c;
  }
  double positive(double x, Section section, size_t index, const std::string& key) const {
    if (!(x > 0)) fail(section, index, key, "must be > 0 (got " + format_number(x) + ")");
    return x;
  }
  double non_negative(double x, Section section, size_t index, const std::string& key) const {
    if (!(x >= 0)) fail(section, index, key, "must be >= 0 (got " + format_number(x) + ")");
    return x;
  }

  void render() {
    const View& v = parts_.view;
    RenderSettings& s = scene_.render;
    s.width = v.width;
    s.height = v.height;
    s.samples_per_pixel = 1;
    s.max_depth = 5;
    s.background = color(parts_.background, Section::render, 4, "");
    try {
      check_image_size(v.width, v.height, {});
    } catch (const Error& e) {
      fail(Section::render, 0, "", e.message());
    }
  }

  void camera() {
    const View& v = parts_.view;
    Camera& cam = scene_.camera;
    cam.position = v.from;
    cam.look_at = v.at;
    // As the loader reads a direction (the reader made `up` unit already;
    // this keeps the very bits the loader would hold).
    cam.up = *unit_direction(v.up);
    cam.fov_y = v.fov_y;
    if (!(cam.fov_y > 0 && cam.fov_y < 180))
      fail(Section::camera, 3, "",
           "must be between 0 and 180 degrees, exclusive (got " + format_number(cam.fov_y) + ")");
  }

  void material(size_t i) {
    const nff::Material& m = parts_.materials[i];
    glint::Material mat;
    mat.name = material_name(static_cast<uint32_t>(i + 1));
    mat.ambient = color(m.color, Section::material, i, "ambient");
    mat.diffuse = mat.ambient;
    mat.specular = color(Color(m.ks), Section::material, i, "specular");
    mat.shininess = positive(m.shininess, Section::material, i, "shininess");
    mat.reflectivity = mat.specular;
    mat.transparency = non_negative(m.transparency, Section::material, i, "transparency");
    if (m.transparency > 0) {
      // A transmitting surface bends light and, with fresnel, reflects some:
      // the reflected ray the SPD statistics count for it.
      mat.ior = positive(m.ior, Section::material, i, "ior");
      mat.fresnel = true;
    }
    material_index_[i] = add_material(scene_, std::move(mat));
  }

  void point_light(size_t i, double gray) {
    const nff::Light& l = parts_.lights[i];
    glint::Light light;
    light.type = LightType::point;
    light.diffuse = light.specular = l.color ? color(*l.color, Section::light, i, "diffuse") : Color(gray);
    light.position = l.position;
    scene_.lights.push_back(std::move(light));
  }

  void object(size_t i) {
    const nff::Object& o = parts_.objects[i];
    const double* x = parts_.numbers.data() + o.first;
    const uint32_t material = o.material ? material_index_[o.material - 1] : 0;
    switch (o.shape) {
      case Shape::sphere: {
        Sphere s;
        s.center = Vec3(x[0], x[1], x[2]);
        s.radius = positive(x[3], Section::object, i, "radius");
        add_sphere(scene_, s, material);
        return;
      }
      case Shape::cylinder:
      case Shape::cone: {
        const bool cylinder = o.shape == Shape::cylinder;
        const Vec3 base(x[0], x[1], x[2]), apex(x[3], x[4], x[5]);
        if (apex == base) fail(Section::object, i, "apex", "must differ from \"base\" (the axis needs a length)");
        if (!std::isfinite(length(apex - base)))
          fail(Section::object, i, "apex", "too far from \"base\" (the axis length overflows)");
        double r0 = 0, r1 = 0;
        if (cylinder) {
          r0 = r1 = positive(x[6], Section::object, i, "radius");
        } else {
          r0 = non_negative(x[6], Section::object, i, "base_radius");
          r1 = non_negative(x[7], Section::object, i, "apex_radius");
          if (r0 == 0 && r1 == 0)
            fail(Section::object, i, "apex_radius", "\"base_radius\" and \"apex_radius\" cannot both be 0");
        }
        add_cone(scene_, make_cone(base, apex, r0, r1, false), material, std::nullopt, cylinder);  // NFF's are open
        return;
      }
      case Shape::polygon: {
        std::vector<Vec3> vertices, normals;
        vertices.reserve(o.vertices);
        for (uint32_t k = 0; k < o.vertices; ++k) vertices.emplace_back(x[3 * k], x[3 * k + 1], x[3 * k + 2]);
        if (o.normals) {
          normals.reserve(o.vertices);
          const double* n = x + 3 * o.vertices;
          for (uint32_t k = 0; k < o.vertices; ++k) {
            const auto unit = unit_direction(Vec3(n[3 * k], n[3 * k + 1], n[3 * k + 2]));
            if (!unit) fail(Section::object, i, "normals[" + std::to_string(k) + "]", "must be a non-zero vector");
            normals.push_back(*unit);
          }
        }
        PolygonBuild built = make_polygon(std::move(vertices), std::move(normals));
        if (!built.error.empty())
          fail(Section::object, i, built.error_at_normals ? "normals" : "vertices", built.error);
        add_polygon(scene_, std::move(built.polygon), material);
        return;
      }
    }
  }

  const Parts& parts_;
  std::vector<Error>* errors_;
  Scene scene_;
  std::vector<uint32_t> material_index_;  // NFF material k + 1 -> Scene::materials
};

}  // namespace

Scene build_scene(const Parts& parts, std::vector<Error>* errors) { return SceneBuilder(parts, errors).build(); }

}  // namespace glint::nff
