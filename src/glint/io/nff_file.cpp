#include "glint/io/nff_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "glint/io/file_io.h"
#include "glint/io/json.h"
#include "glint/io/nff/nff_parts.h"
#include "glint/io/scene_loader.h"
#include "glint/math/vec3.h"
#include "glint/scene/scene.h"

namespace glint {

// The file as read (nff/nff_parts.h); this file writes the JSON document of
// `glint convert` and the API from it, and hands it to nff/nff_scene.cpp for
// the Scene that load_scene returns.
using namespace nff;

namespace {

// --- nlohmann's document (convert, the API) ---------------------------------------

using Json = nlohmann::ordered_json;

// Element by element: nlohmann's initializer-list constructors copy every
// element and were a quarter of the time to read a big NFF file.
Json vec(const Vec3& v) {
  Json a(Json::value_t::array);
  auto& items = a.get_ref<Json::array_t&>();
  items.reserve(3);
  items.emplace_back(v.x);
  items.emplace_back(v.y);
  items.emplace_back(v.z);
  return a;
}
Json vec(const double* p) { return vec(Vec3(p[0], p[1], p[2])); }

Json object_json(const Parts& parts, const nff::Object& o) {
  const double* x = parts.numbers.data() + o.first;
  Json j(Json::value_t::object);
  switch (o.shape) {
    case Shape::sphere:
      j["type"] = "sphere";
      j["center"] = vec(x);
      j["radius"] = x[3];
      break;
    case Shape::cylinder:
      j["type"] = "cylinder";
      j["base"] = vec(x);
      j["apex"] = vec(x + 3);
      j["radius"] = x[6];
      j["caps"] = false;  // NFF cones and cylinders are open
      break;
    case Shape::cone:
      j["type"] = "cone";
      j["base"] = vec(x);
      j["apex"] = vec(x + 3);
      j["base_radius"] = x[6];
      j["apex_radius"] = x[7];
      j["caps"] = false;
      break;
    case Shape::polygon: {
      j["type"] = "polygon";
      Json vertices = Json::array(), normals = Json::array();
      for (uint32_t i = 0; i < o.vertices; ++i) vertices.push_back(vec(x + 3 * i));
      j["vertices"] = std::move(vertices);
      if (o.normals) {
        for (uint32_t i = 0; i < o.vertices; ++i) normals.push_back(vec(x + 3 * (o.vertices + i)));
        j["normals"] = std::move(normals);
      }
      break;
    }
  }
  if (o.material) j["material"] = material_name(o.material);
  return j;
}

Json material_json(const nff::Material& m) {
  Json j;
  j["ambient"] = vec(m.color);
  j["diffuse"] = vec(m.color);
  j["specular"] = m.ks;
  j["shininess"] = m.shininess;
  j["reflectivity"] = m.ks;
  j["transparency"] = m.transparency;
  if (m.transparency > 0) {
    // A transmitting surface bends light and, with fresnel, reflects some:
    // the reflected ray the SPD statistics count for it.
    j["ior"] = m.ior;
    j["fresnel"] = true;
  }
  return j;
}

NffScene to_nff_scene(Parts&& parts) {
  NffScene scene;
  scene.filename = parts.filename;
  scene.angle = parts.view.angle;
  Json& doc = scene.document;
  const View& v = parts.view;
  Json& render = doc["render"];
  render["width"] = v.width;
  render["height"] = v.height;
  render["samples_per_pixel"] = 1;
  render["max_depth"] = 5;
  render["background"] = vec(parts.background);
  Json& camera = doc["camera"];
  camera["position"] = vec(v.from);
  camera["look_at"] = vec(v.at);
  camera["up"] = vec(v.up);
  camera["fov_y"] = v.fov_y;
  auto origin = [&](Section section, size_t index) { scene.origins.insert(origin_of(parts, section, index)); };
  for (size_t i = 0; i < std::size(kRenderKeys); ++i) origin(Section::render, i);
  for (size_t i = 0; i < std::size(kCameraKeys); ++i) origin(Section::camera, i);
  if (!parts.materials.empty()) {
    Json& materials = doc["materials"];
    for (size_t i = 0; i < parts.materials.size(); ++i) {
      materials[material_name(static_cast<uint32_t>(i + 1))] = material_json(parts.materials[i]);
      origin(Section::material, i);
    }
  }
  if (!parts.lights.empty()) {
    const double gray = light_gray(parts);
    Json lights = Json::array();
    for (size_t i = 0; i < parts.lights.size(); ++i) {
      const nff::Light& l = parts.lights[i];
      const Json c = l.color ? vec(*l.color) : Json(gray);
      lights.push_back(Json{{"type", "point"}, {"position", vec(l.position)}, {"diffuse", c}, {"specular", c}});
      origin(Section::light, i);
    }
    lights.push_back(Json{{"type", "ambient"}, {"ambient", gray}});
    origin(Section::light, parts.lights.size());
    doc["lights"] = std::move(lights);
  }
  Json objects = Json::array();
  objects.get_ref<Json::array_t&>().reserve(parts.objects.size());
  scene.origins.reserve(scene.origins.size() + parts.objects.size());
  for (size_t i = 0; i < parts.objects.size(); ++i) {
    objects.push_back(object_json(parts, parts.objects[i]));
    origin(Section::object, i);
  }
  doc["objects"] = std::move(objects);
  return scene;
}

}  // namespace

bool is_nff_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".nff";
}

NffScene read_nff(std::string_view text, const std::string& filename) {
  return to_nff_scene(read_parts(text, filename));
}

NffScene read_nff_file(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = read_file(path);
  return read_nff(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

Scene parse_nff_scene(std::string_view text, const std::string& filename) {
  const Parts parts = read_parts(text, filename);
  try {
    return build_scene(parts);
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{filename, 0, 0}, "out of memory while loading the scene");
  }
}

Scene load_nff_scene(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = read_file(path);
  return parse_nff_scene(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

std::vector<Error> validate_nff_scene(const std::filesystem::path& path) {
  std::vector<Error> errors;
  try {
    const std::vector<unsigned char> bytes = read_file(path);
    const Parts parts =
        read_parts(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
    build_scene(parts, &errors);
  } catch (const Error& e) {
    errors.push_back(e);  // the NFF itself is malformed: nothing more can be checked
  } catch (const std::bad_alloc&) {
    errors.push_back(Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene"));
  }
  return errors;
}

NffJsonText nff_json_text(const NffScene& scene) {
  NffJsonText out;
  auto line = [&out](const std::string& text, std::string path) {
    out.text += text;
    out.text += '\n';
    out.line_paths.push_back(std::move(path));
  };
  const Json& doc = scene.document;
  line("{", "");
  size_t k = 0;
  for (auto section = doc.begin(); section != doc.end(); ++section, ++k) {
    const std::string& key = section.key();
    const Json& v = section.value();
    const std::string comma = k + 1 < doc.size() ? "," : "";
    const std::string opening = "  " + Json(key).dump() + ": ";
    if (v.is_object()) {
      line(opening + "{", "");
      size_t i = 0;
      for (auto m = v.begin(); m != v.end(); ++m, ++i)
        line("    " + Json(m.key()).dump() + ": " + m.value().dump() + (i + 1 < v.size() ? "," : ""),
             key + "." + m.key());
      line("  }" + comma, "");
    } else if (v.is_array()) {
      line(opening + "[", "");
      for (size_t i = 0; i < v.size(); ++i)
        line("    " + v[i].dump() + (i + 1 < v.size() ? "," : ""), key + "[" + std::to_string(i) + "]");
      line("  ]" + comma, "");
    } else {
      line(opening + v.dump() + comma, key);
    }
  }
  line("}", "");
  return out;
}

Error nff_error(const NffScene& scene, const NffJsonText& json, const Error& e) {
  const SourceLocation& at = e.location();
  if (at.line >= 1 && static_cast<size_t>(at.line) <= json.line_paths.size()) {
    const std::string& path = json.line_paths[static_cast<size_t>(at.line) - 1];
    if (const auto it = scene.origins.find(path); it != scene.origins.end()) return at_entity(path, it->second, e);
  }
  return Error(SourceLocation{scene.filename, 0, 0}, e.message());
}

}  // namespace glint
