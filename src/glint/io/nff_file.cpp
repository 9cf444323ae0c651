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

// The file as read (nff/nff_parts.h); this file writes the two documents.
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

// --- the loader's document, built in memory ----------------------------------------

// The same document as to_nff_scene's, one part per line (json.h's
// DocumentBuilder): an error's line names the part, `lines` says which.
struct NffDocument {
  json::Document document;
  struct Part {
    Section section = Section::none;
    uint32_t index = 0;
  };
  std::vector<Part> lines;  // lines[k]: line k + 1
  Parts parts;
};

class DocumentWriter {
 public:
  DocumentWriter(const Parts& parts, std::vector<NffDocument::Part>& lines)
      : parts_(parts), b_(parts.filename), lines_(lines) {
    const size_t parts_count = parts.objects.size() + parts.materials.size() + parts.lights.size() + 20;
    lines_.reserve(parts_count);
    lines_.push_back({});  // line 1: the root
    // A part is at most 20 values and keys of some 50 bytes of keys, and a
    // polygon's or cone's numbers are a node each, plus an array per vertex.
    b_.reserve(20 * parts_count + 2 * parts.numbers.size(), 64 * parts_count);
  }

  json::Document write() {
    const View& v = parts_.view;
    b_.begin_object();
    section("render");
    part(Section::render, 0, "width").number(v.width);
    part(Section::render, 1, "height").number(v.height);
    part(Section::render, 2, "samples_per_pixel").number(1);
    part(Section::render, 3, "max_depth").number(5);
    part(Section::render, 4, "background").triple(parts_.background);
    b_.end();
    section("camera");
    part(Section::camera, 0, "position").triple(v.from);
    part(Section::camera, 1, "look_at").triple(v.at);
    part(Section::camera, 2, "up").triple(v.up);
    part(Section::camera, 3, "fov_y").number(v.fov_y);
    b_.end();
    if (!parts_.materials.empty()) {
      section("materials");
      for (size_t i = 0; i < parts_.materials.size(); ++i) material(i);
      b_.end();
    }
    if (!parts_.lights.empty()) {
      section("lights", true);
      const double gray = light_gray(parts_);
      for (size_t i = 0; i < parts_.lights.size(); ++i) light(i, gray);
      part(Section::light, static_cast<uint32_t>(parts_.lights.size()));
      b_.begin_object();
      b_.key("type");
      b_.string("ambient");
      b_.key("ambient");
      b_.number(gray);
      b_.end();
      b_.end();
    }
    section("objects", true);
    for (size_t i = 0; i < parts_.objects.size(); ++i) object(i);
    b_.end();
    b_.end();
    return b_.document();
  }

 private:
  // So that part(...).number(...) reads as one line.
  struct Value {
    json::DocumentBuilder& b;
    void number(double x) { b.number(x); }
    void triple(const Vec3& t) { b.triple(t.x, t.y, t.z); }
  };

  void line(Section s, uint32_t index) {
    b_.next_line();
    lines_.push_back({s, index});
  }
  // A section's key and opening bracket, on a line of their own.
  void section(const char* key, bool array = false) {
    line(Section::none, 0);
    b_.key(key);
    if (array) b_.begin_array();
    else b_.begin_object();
  }
  // A member of render or camera, or (without key) an item of a section.
  Value part(Section s, uint32_t index, const char* key = nullptr) {
    line(s, index);
    if (key) b_.key(key);
    return Value{b_};
  }
  void triple(const double* p) { b_.triple(p[0], p[1], p[2]); }
  void vec(const Vec3& v) { b_.triple(v.x, v.y, v.z); }

  void material(size_t i) {
    const nff::Material& m = parts_.materials[i];
    part(Section::material, static_cast<uint32_t>(i), nullptr);
    b_.key(material_name(static_cast<uint32_t>(i + 1)));
    b_.begin_object();
    b_.key("ambient");
    vec(m.color);
    b_.key("diffuse");
    vec(m.color);
    b_.key("specular");
    b_.number(m.ks);
    b_.key("shininess");
    b_.number(m.shininess);
    b_.key("reflectivity");
    b_.number(m.ks);
    b_.key("transparency");
    b_.number(m.transparency);
    if (m.transparency > 0) {
      b_.key("ior");
      b_.number(m.ior);
      b_.key("fresnel");
      b_.boolean(true);
    }
    b_.end();
  }

  void light(size_t i, double gray) {
    const nff::Light& l = parts_.lights[i];
    part(Section::light, static_cast<uint32_t>(i));
    b_.begin_object();
    b_.key("type");
    b_.string("point");
    b_.key("position");
    vec(l.position);
    for (const char* key : {"diffuse", "specular"}) {
      b_.key(key);
      if (l.color) vec(*l.color);
      else b_.number(gray);
    }
    b_.end();
  }

  void object(size_t i) {
    const nff::Object& o = parts_.objects[i];
    const double* x = parts_.numbers.data() + o.first;
    part(Section::object, static_cast<uint32_t>(i));
    b_.begin_object();
    b_.key("type");
    switch (o.shape) {
      case Shape::sphere:
        b_.string("sphere");
        b_.key("center");
        triple(x);
        b_.key("radius");
        b_.number(x[3]);
        break;
      case Shape::cylinder:
        b_.string("cylinder");
        b_.key("base");
        triple(x);
        b_.key("apex");
        triple(x + 3);
        b_.key("radius");
        b_.number(x[6]);
        b_.key("caps");
        b_.boolean(false);
        break;
      case Shape::cone:
        b_.string("cone");
        b_.key("base");
        triple(x);
        b_.key("apex");
        triple(x + 3);
        b_.key("base_radius");
        b_.number(x[6]);
        b_.key("apex_radius");
        b_.number(x[7]);
        b_.key("caps");
        b_.boolean(false);
        break;
      case Shape::polygon:
        b_.string("polygon");
        b_.key("vertices");
        b_.begin_array();
        for (uint32_t k = 0; k < o.vertices; ++k) triple(x + 3 * k);
        b_.end();
        if (o.normals) {
          b_.key("normals");
          b_.begin_array();
          for (uint32_t k = 0; k < o.vertices; ++k) triple(x + 3 * (o.vertices + k));
          b_.end();
        }
        break;
    }
    if (o.material) {
      b_.key("material");
      char name[16];
      const int n = std::snprintf(name, sizeof name, "f%u", o.material);
      b_.string(std::string_view(name, static_cast<size_t>(n)));
    }
    b_.end();
  }

  const Parts& parts_;
  json::DocumentBuilder b_;
  std::vector<NffDocument::Part>& lines_;
};

NffDocument nff_document(std::string_view text, const std::string& filename) {
  Parts parts = read_parts(text, filename);
  std::vector<NffDocument::Part> lines;
  json::Document document = DocumentWriter(parts, lines).write();
  return NffDocument{std::move(document), std::move(lines), std::move(parts)};
}

NffDocument nff_document(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = read_file(path);
  return nff_document(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

// A loader error in an NFF document, at the entity behind its line.
Error nff_document_error(const NffDocument& doc, const Error& e) {
  const SourceLocation& at = e.location();
  if (at.line >= 1 && static_cast<size_t>(at.line) <= doc.lines.size()) {
    const NffDocument::Part& p = doc.lines[static_cast<size_t>(at.line) - 1];
    if (p.section != Section::none) {
      const auto [path, origin] = origin_of(doc.parts, p.section, p.index);
      return at_entity(path, origin, e);
    }
  }
  return Error(SourceLocation{doc.parts.filename, 0, 0}, e.message());
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

json::Document nff_loader_document(std::string_view text, const std::string& filename) {
  return nff_document(text, filename).document;
}

Scene load_nff_scene(const std::filesystem::path& path) {
  const NffDocument doc = nff_document(path);
  Scene scene;
  try {
    scene = read_scene_document(doc.document, path.parent_path());
  } catch (const Error& e) {
    throw nff_document_error(doc, e);
  }
  // The view's angle spans the rows' centers: fov_y follows the rendered height.
  scene.camera.row_center_angle = doc.parts.view.angle;
  return scene;
}

std::vector<Error> validate_nff_scene(const std::filesystem::path& path) {
  std::vector<Error> errors;
  try {
    const NffDocument doc = nff_document(path);
    for (const Error& e : validate_scene_document(doc.document, path.parent_path()))
      errors.push_back(nff_document_error(doc, e));
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
