#pragma once
// The parts of one NFF file as read (io/nff/nff_reader.cpp), before the
// Scene (io/nff/nff_scene.cpp) or the JSON document of convert and the API
// (io/nff_file.cpp) is made from them: plain structs, one reading for both.
// Internal to io/.

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "glint/error.h"
#include "glint/io/nff_file.h"
#include "glint/math/vec3.h"
#include "glint/scene/scene.h"

namespace glint::nff {

// --- the file as read: plain parts ----------------------------------------------

struct Where {
  int line = 0, column = 0;
};

struct View {
  Vec3 from, at, up;  // up: made perpendicular to the view direction
  double angle = 45, fov_y = 45;
  int width = 0, height = 0;
  Where v, from_t, at_t, up_t, angle_t, resolution_t;
};

struct Material {  // already in glint's terms
  Vec3 color;      // Kd * (r, g, b): ambient and diffuse
  double ks = 0, shininess = 1, transparency = 0, ior = 1;
  Where at;
};

struct Light {
  Vec3 position;
  std::optional<Vec3> color;
  Where at;
};

enum class Shape : uint8_t { sphere, cylinder, cone, polygon };

struct Object {
  Shape shape = Shape::sphere;
  bool normals = false;   // polygon: `pp`
  uint32_t material = 0;  // 0: none (before the first `f`), else materials[material - 1]
  uint32_t first = 0;     // its numbers start at Parts::numbers[first]:
  uint32_t vertices = 0;  //   sphere: center, radius; cylinder: base, apex, radius;
  Where at;               //   cone: base, apex, base radius, apex radius;
};                        //   polygon: `vertices` points, then as many normals for `pp`

struct Parts {
  std::string filename;
  View view;
  std::optional<Where> background_at;
  Vec3 background{0.0};
  std::vector<Material> materials;
  std::vector<Light> lights;
  std::vector<Object> objects;
  std::vector<double> numbers;
};

inline const char* entity_of(const Object& o) {
  switch (o.shape) {
    case Shape::sphere: return "s";
    case Shape::cylinder:
    case Shape::cone: return "c";
    case Shape::polygon: return o.normals ? "pp" : "p";
  }
  return "";
}

// Reads one NFF file's text; the first problem is thrown as an Error at its
// file:line:col.
Parts read_parts(std::string_view text, std::string filename);

// The scene of the parts (nff/nff_scene.cpp), by the same mapping as the
// JSON document and with the JSON loader's checks, each problem at its
// entity. With `errors`, problems are collected (one per section, material,
// light and object) and building goes on; without, the first is thrown.
Scene build_scene(const Parts& parts, std::vector<Error>* errors = nullptr);

// --- where each part of the document came from ----------------------------------

// The document's parts, in its order: render's and camera's members, the
// materials, the lights (the ambient one last), the objects.
enum class Section : uint8_t { none, render, camera, material, light, object };

inline constexpr const char* kRenderKeys[] = {"width", "height", "samples_per_pixel", "max_depth", "background"};
inline constexpr const char* kCameraKeys[] = {"position", "look_at", "up", "fov_y"};

inline std::string material_name(uint32_t k) { return "f" + std::to_string(k); }

// The document path of part `index` of `section` ("render.width",
// "materials.f2", "lights[0]", "objects[7]") and the NFF entity behind it.
std::pair<std::string, NffOrigin> origin_of(const Parts& parts, Section section, size_t index);

// The SPD's suggestion for lights of unstated intensity: sqrt(n)/(2n) each,
// and as much again for the ambient term.
inline double light_gray(const Parts& parts) {
  const double n = static_cast<double>(parts.lights.size());
  return std::sqrt(n) / (2.0 * n);
}

// `e`, an error of the JSON loader about the part at `path`, as the same
// problem at the NFF entity: "objects[3].radius: must be > 0" -> "s: radius: must be > 0".
Error at_entity(const std::string& path, const NffOrigin& origin, const Error& e);

}  // namespace glint::nff
