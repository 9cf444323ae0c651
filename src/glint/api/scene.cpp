// The public Scene: its document is the truth, and every state of it is
// checked by the loader itself (parse_scene), so an edit meets exactly the
// rules and messages of the scene file. The arrays of meshes added from
// memory (add_mesh) stay beside the document, named in it by id, and go to
// the loader as they are: a large mesh is never turned into JSON text and
// parsed back on each edit; only to_json() and get() write it out.
#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <functional>
#include <optional>
#include <set>
#include <type_traits>

#include "glint/api/scene_state.h"
#include "glint/io/file_io.h"
#include "glint/io/mesh_scene.h"
#include "glint/io/nff_file.h"
#include "glint/io/scene_loader.h"

namespace glint::api {

namespace {

using Json = nlohmann::ordered_json;

// One step of a path: an object key or an array index.
struct Step {
  std::string key;
  bool is_index = false;
  size_t index = 0;
};

// "lights[0].position" -> lights, [0], position. Keys may be quoted in
// brackets for names with dots: materials["my.gold"].
std::vector<Step> parse_path(std::string_view path) {
  std::vector<Step> steps;
  size_t i = 0;
  auto bad = [&](const std::string& why) -> Error {
    return Error(SourceLocation{}, std::string(path), "bad path: " + why);
  };
  while (i < path.size()) {
    if (path[i] == '[') {
      const size_t close = path.find(']', i);
      if (close == std::string_view::npos) throw bad("unclosed [");
      std::string_view inside = path.substr(i + 1, close - i - 1);
      Step s;
      if (inside.size() >= 2 && inside.front() == '"' && inside.back() == '"') {
        s.key = std::string(inside.substr(1, inside.size() - 2));
      } else {
        const auto [end, ec] = std::from_chars(inside.data(), inside.data() + inside.size(), s.index);
        if (ec != std::errc() || end != inside.data() + inside.size() || inside.empty())
          throw bad("expected an index in []");
        s.is_index = true;
      }
      steps.push_back(std::move(s));
      i = close + 1;
      if (i < path.size() && path[i] == '.') ++i;
    } else {
      size_t end = i;
      while (end < path.size() && path[end] != '.' && path[end] != '[') ++end;
      if (end == i) throw bad("empty key");
      steps.push_back({std::string(path.substr(i, end - i))});
      i = end;
      if (i < path.size() && path[i] == '.') ++i;
    }
  }
  if (steps.empty()) throw bad("empty path");
  return steps;
}

// --- mesh arrays beside the document ------------------------------------

bool is_array_key(std::string_view key) {
  return key == "vertices" || key == "triangles" || key == "normals" || key == "uvs";
}

bool is_attached(const Json& node) { return node.is_object() && node.contains(kAttachedMeshKey); }

// A float of the arrays as the document gives it: the shortest decimal that
// reads back to the same float (0.1f is 0.1, not 0.10000000149011612), so the
// document shows the values as they were most likely given, and loads back
// to exactly the floats the scene renders with.
// -0 is written -0.0: JSON readers (Python's too) take "-0" for the integer 0.
char* write_float(char* at, char* end, float x) {
  if (x == 0 && std::signbit(x)) return std::copy_n("-0.0", 4, at);
  return std::to_chars(at, end, x).ptr;
}
double float_value(float x) {
  char text[32];
  char* end = write_float(text, text + sizeof text, x);
  double d = 0;
  std::from_chars(text, end, d);
  return d;
}

Json float_rows(const std::vector<float>& values, size_t k) {
  Json out = Json::array();
  out.get_ref<Json::array_t&>().reserve(values.size() / k);
  for (size_t i = 0; i + k <= values.size(); i += k) {
    Json row = Json::array();
    for (size_t c = 0; c < k; ++c) row.push_back(float_value(values[i + c]));
    out.push_back(std::move(row));
  }
  return out;
}

// The same rows as compact JSON text, written directly (a large mesh is not
// built as millions of JSON values first): the values of float_rows(...).dump().
template <class T>
void append_rows(std::string& out, const std::vector<T>& values, size_t k) {
  char text[32];
  out.push_back('[');
  for (size_t i = 0; i + k <= values.size(); i += k) {
    out.append(i ? ",[" : "[");
    for (size_t c = 0; c < k; ++c) {
      if (c) out.push_back(',');
      char* end = nullptr;
      if constexpr (std::is_same_v<T, float>) end = write_float(text, text + sizeof text, values[i + c]);
      else end = std::to_chars(text, text + sizeof text, values[i + c]).ptr;
      out.append(text, end);
    }
    out.push_back(']');
  }
  out.push_back(']');
}

// The object {"type": "mesh", ..., "$arrays": id} as the inline mesh it
// stands for: the id replaced by "vertices", "triangles" (and "normals",
// "uvs" when given), at its place among the keys.
void expand(Json& object, const AttachedMeshes& meshes) {
  const auto id = object.find(kAttachedMeshKey);
  if (id == object.end() || !id->is_number_unsigned()) return;
  const auto it = meshes.find(id->get<uint64_t>());
  if (it == meshes.end()) return;
  const MeshArrays& a = *it->second;
  Json out = Json::object();
  for (auto& item : object.items()) {
    if (item.key() != kAttachedMeshKey) {
      out[item.key()] = std::move(item.value());
      continue;
    }
    out["vertices"] = float_rows(a.positions, 3);
    Json triangles = Json::array();
    triangles.get_ref<Json::array_t&>().reserve(a.triangles.size() / 3);
    for (size_t i = 0; i + 3 <= a.triangles.size(); i += 3)
      triangles.push_back(Json::array({a.triangles[i], a.triangles[i + 1], a.triangles[i + 2]}));
    out["triangles"] = std::move(triangles);
    if (!a.normals.empty()) out["normals"] = float_rows(a.normals, 3);
    if (!a.uvs.empty()) out["uvs"] = float_rows(a.uvs, 2);
  }
  object = std::move(out);
}

// expand(object).dump(): the object with its arrays, as compact text.
std::string attached_text(const Json& object, const MeshArrays& a) {
  std::string out = "{";
  out.reserve(16 * (a.positions.size() + a.triangles.size() + a.normals.size() + a.uvs.size()));
  for (const auto& item : object.items()) {
    if (out.size() > 1) out.push_back(',');
    if (item.key() != kAttachedMeshKey) {
      out += Json(item.key()).dump() + ":" + item.value().dump();
      continue;
    }
    out += "\"vertices\":";
    append_rows(out, a.positions, 3);
    out += ",\"triangles\":";
    append_rows(out, a.triangles, 3);
    if (!a.normals.empty()) {
      out += ",\"normals\":";
      append_rows(out, a.normals, 3);
    }
    if (!a.uvs.empty()) {
      out += ",\"uvs\":";
      append_rows(out, a.uvs, 2);
    }
  }
  return out + "}";
}

// Every attached mesh in `node` written out (what the caller shows or writes).
void expand_all(Json& node, const AttachedMeshes& meshes) {
  if (meshes.empty()) return;
  if (is_attached(node)) return expand(node, meshes);
  if (node.is_object()) {
    for (auto& item : node.items())
      if (item.value().is_object() || item.value().is_array()) expand_all(item.value(), meshes);
  } else if (node.is_array()) {
    for (Json& v : node) {
      if (!v.is_object()) return;  // numbers, rows of numbers: no objects inside
      expand_all(v, meshes);
    }
  }
}

// The value at `steps` (nullptr when absent). With `create`, the last step
// may be a missing object key, which is added. A step into the arrays of an
// attached mesh ("objects[3].vertices") writes that object out first, so the
// caller sees (or edits) them as JSON; its "$arrays" id is not a place.
Json* find(Json& root, const std::vector<Step>& steps, bool create, std::string_view path,
           const AttachedMeshes* meshes) {
  Json* at = &root;
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    const bool last = i + 1 == steps.size();
    if (s.is_index) {
      if (!at->is_array() || s.index >= at->size()) return nullptr;
      at = &(*at)[s.index];
    } else {
      if (s.key == kAttachedMeshKey) return nullptr;
      if (meshes && is_array_key(s.key) && is_attached(*at)) expand(*at, *meshes);
      if (!at->is_object()) {
        if (create && last && at->is_null()) *at = Json::object();
        else return nullptr;
      }
      auto it = at->find(s.key);
      if (it == at->end()) {
        if (!(create && last)) {
          // A missing section ("render", "lights") may be created on the way.
          if (!create) return nullptr;
          (*at)[s.key] = Json::object();
          at = &(*at)[s.key];
          continue;
        }
        (*at)[s.key] = nullptr;
        return &(*at)[s.key];
      }
      at = &*it;
    }
  }
  (void)path;
  return at;
}

// find() for reading: the document is left as it is. A step into the arrays
// of an attached mesh writes that one object out into `scratch` and goes on
// there; the result points into the document or into `scratch`.
const Json* lookup(const Json& root, const std::vector<Step>& steps, const AttachedMeshes& meshes,
                   std::optional<Json>& scratch) {
  const Json* at = &root;
  for (const Step& s : steps) {
    if (s.is_index) {
      if (!at->is_array() || s.index >= at->size()) return nullptr;
      at = &(*at)[s.index];
      continue;
    }
    if (s.key == kAttachedMeshKey) return nullptr;
    if (!scratch && is_array_key(s.key) && is_attached(*at)) {
      scratch = *at;
      expand(*scratch, meshes);
      at = &*scratch;
    }
    if (!at->is_object()) return nullptr;
    const auto it = at->find(s.key);
    if (it == at->end()) return nullptr;
    at = &*it;
  }
  return at;
}

Json parse_value(std::string_view json_text, std::string_view what) {
  Json v = Json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (v.is_discarded())
    throw Error(SourceLocation{}, std::string(what), "not valid JSON: " + std::string(json_text.substr(0, 80)));
  return v;
}

size_t hash_combine(size_t seed, size_t v) { return seed ^ (v + 0x9e3779b97f4a7c15ULL + (seed << 6) + (seed >> 2)); }

template <typename T>
size_t hash_bytes(const std::vector<T>& values) {
  return std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
}

// Objects (but their materials), animation and the meshes' triangles (from
// files or attached arrays): what the
// acceleration structure is built from. The triangles as read, not the files' sizes and
// times: a file rewritten within the clock's granularity keeps its time, and
// one that changes between its reading and a look at its time would pair
// the new time with the old triangles. (Hashing is far cheaper than reading.)
size_t compute_geometry_key(const Json& document, const glint::Scene& scene) {
  size_t key = 0;
  if (auto it = document.find("objects"); it != document.end()) {
    // Which material an object uses is shading, not geometry: the
    // acceleration structure never looks at it.
    Json objects = *it;
    if (objects.is_array())
      for (Json& o : objects)
        if (o.is_object()) o.erase("material");
    key = std::hash<std::string>{}(objects.dump());
  }
  if (auto it = document.find("animation"); it != document.end())
    key = hash_combine(key, std::hash<std::string>{}(it->dump()));
  for (const Mesh& mesh : scene.meshes) {
    key = hash_combine(key, std::hash<std::string>{}(mesh.file));
    key = hash_combine(key, hash_bytes(mesh.positions));
    key = hash_combine(key, hash_bytes(mesh.indices));
  }
  return key;
}

// The value at a JSON pointer, or null.
Json at_pointer(const Json& document, const char* pointer) {
  const Json::json_pointer p(pointer);
  return document.contains(p) ? document.at(p) : Json();
}

std::shared_ptr<const Scene::State> make_state(Json document, glint::Scene scene, AttachedMeshes meshes,
                                               std::optional<NffView> nff, std::filesystem::path base_dir,
                                               std::string name, std::shared_ptr<FileCache> files,
                                               std::optional<size_t> geometry_key = std::nullopt) {
  auto state = std::make_shared<Scene::State>();
  state->files = std::move(files);
  // Arrays no object names any more (the object was removed, replaced or
  // written out as JSON) are let go.
  std::set<uint64_t> used;
  if (auto objects = document.find("objects"); objects != document.end() && objects->is_array())
    for (const Json& o : *objects)
      if (is_attached(o) && o[kAttachedMeshKey].is_number_unsigned()) used.insert(o[kAttachedMeshKey].get<uint64_t>());
  std::erase_if(meshes, [&](const auto& m) { return !used.count(m.first); });
  // An NFF view keeps following the rendered height while its camera and
  // height are the file's (docs/nff.md).
  if (nff && at_pointer(document, "/camera") == nff->camera && at_pointer(document, "/render/height") == nff->height)
    scene.camera.row_center_angle = nff->angle;
  state->geometry_key = geometry_key ? *geometry_key : compute_geometry_key(document, scene);
  state->document = std::move(document);
  state->meshes = std::move(meshes);
  state->nff = std::move(nff);
  state->scene = std::make_shared<const glint::Scene>(std::move(scene));
  state->base_dir = std::move(base_dir);
  state->name = std::move(name);
  return state;
}

// The loader's verdict on an edited document. Its messages point into text
// the user never saw, so they keep the path and the problem only.
glint::Scene check(const Json& document, const AttachedMeshes& meshes, const Scene::State& from) {
  try {
    return parse_scene(document.dump(), from.name, from.base_dir, default_memory_budget(),
                       meshes.empty() ? nullptr : &meshes, from.files.get());
  } catch (const Error& e) {
    if (e.path().empty() || e.message().size() < e.path().size() + 2)
      throw Error(SourceLocation{from.name, 0, 0}, e.message());
    throw Error(SourceLocation{from.name, 0, 0}, e.path(), e.message().substr(e.path().size() + 2));
  }
}

Scene from_json_with(std::string_view json_text, const std::filesystem::path& base_dir, std::string_view name,
                     std::shared_ptr<FileCache> files) {
  glint::Scene scene =
      parse_scene(std::string(json_text), std::string(name), base_dir, default_memory_budget(), nullptr, files.get());
  std::string_view text = json_text;
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  Json document = Json::parse(text.begin(), text.end());
  return Scene(make_state(std::move(document), std::move(scene), {}, std::nullopt, base_dir, std::string(name),
                          std::move(files)));
}

}  // namespace

Scene load_scene_with(const std::filesystem::path& path, std::shared_ptr<FileCache> files) {
  // A bare mesh file: its framing scene is the document (io/mesh_scene.h).
  if (is_mesh_file(path))
    return from_json_with(mesh_scene_json(path), path.parent_path(), path.string(), std::move(files));
  glint::Scene scene = load_scene(path, files.get());  // every check, with file:line:col
  if (is_nff_path(path)) {
    // An NFF file's document is the glint JSON its reader makes (docs/nff.md).
    NffScene nff = read_nff_file(path);
    NffView view{nff.angle, at_pointer(nff.document, "/camera"), at_pointer(nff.document, "/render/height")};
    return Scene(make_state(std::move(nff.document), std::move(scene), {}, std::move(view), path.parent_path(),
                            path.string(), std::move(files)));
  }
  const std::vector<unsigned char> bytes = read_file(path);
  size_t skip = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF ? 3 : 0;
  Json document = Json::parse(bytes.begin() + static_cast<std::ptrdiff_t>(skip), bytes.end());
  return Scene(make_state(std::move(document), std::move(scene), {}, std::nullopt, path.parent_path(), path.string(),
                          std::move(files)));
}

Scene Scene::load(const std::filesystem::path& path) { return load_scene_with(path, nullptr); }

Scene Scene::from_json(std::string_view json_text, const std::filesystem::path& base_dir, std::string_view name) {
  return from_json_with(json_text, base_dir, name, nullptr);
}

std::string Scene::to_json(int indent) const {
  const State& s = *state_;
  if (s.meshes.empty()) return s.document.dump(indent);
  Json document = s.document;
  auto objects = document.find("objects");
  if (indent >= 0 || objects == document.end() || !objects->is_array()) {
    expand_all(document, s.meshes);
    return document.dump(indent);
  }
  // Compact text (Python's to_dict() reads this): each attached object
  // stands in as a marker string, replaced by the object's text once the
  // rest is written.
  std::vector<std::string> texts;
  const std::string marker = "\x01glint-attached-mesh:";
  for (Json& o : *objects) {
    if (!is_attached(o)) continue;
    const auto it =
        o[kAttachedMeshKey].is_number_unsigned() ? s.meshes.find(o[kAttachedMeshKey].get<uint64_t>()) : s.meshes.end();
    if (it == s.meshes.end()) continue;
    texts.push_back(attached_text(o, *it->second));
    o = marker + std::to_string(texts.size() - 1);
  }
  const std::string text = document.dump();
  std::string out;
  size_t from = 0;
  for (size_t i = 0; i < texts.size(); ++i) {
    const std::string quoted = Json(marker + std::to_string(i)).dump();
    const size_t at = text.find(quoted, from);
    out.append(text, from, at - from);
    out += texts[i];
    from = at + quoted.size();
  }
  out.append(text, from);
  return out;
}
const std::filesystem::path& Scene::base_dir() const { return state_->base_dir; }
const std::string& Scene::name() const { return state_->name; }

std::string Scene::get(std::string_view path) const {
  std::optional<Json> scratch;
  const Json* v = lookup(state_->document, parse_path(path), state_->meshes, scratch);
  if (!v) throw Error(SourceLocation{state_->name, 0, 0}, std::string(path), "not in the scene");
  if (state_->meshes.empty()) return v->dump();
  Json value = *v;  // attached arrays below it are written out (large meshes: only when asked for, as here)
  expand_all(value, state_->meshes);
  return value.dump();
}

bool Scene::has(std::string_view path) const {
  std::optional<Json> scratch;
  return lookup(state_->document, parse_path(path), state_->meshes, scratch) != nullptr;
}

namespace {

// Whether an edit at `path` is checked by reading its section alone: render,
// camera and lights name nothing else in the scene, and nothing else names
// them but an animation's keys (then the whole scene is read again).
bool reads_alone(const Json& document, std::string_view path) {
  if (document.contains("animation")) return false;
  const std::string_view top = path.substr(0, path.find_first_of(".["));
  return top == "render" || top == "camera" || top == "lights";
}

// Applies `edit` (at `path`) to a copy of the document (and of the table of
// attached arrays, which shares them) and checks the result; the scene
// changes only when the loader accepts it. An edit of render, camera or
// lights reads those three alone, with the loader's checks and words, into a
// copy of the scene before: its objects, meshes and textures are not read
// again, and its geometry key holds.
using Edit = std::function<void(Json&, AttachedMeshes&)>;
std::shared_ptr<const Scene::State> edited(const Scene::State& from, std::string_view path, const Edit& edit) {
  Json document = from.document;
  AttachedMeshes meshes = from.meshes;
  edit(document, meshes);
  if (reads_alone(document, path)) {
    Json alone = Json::object();
    for (const char* key : {"render", "camera", "lights"})
      if (const auto it = document.find(key); it != document.end()) alone[key] = *it;
    alone["objects"] = Json::array();
    glint::Scene part = check(alone, {}, from);
    glint::Scene scene = *from.scene;
    scene.render = part.render;
    scene.camera = part.camera;
    scene.lights = std::move(part.lights);
    return make_state(std::move(document), std::move(scene), std::move(meshes), from.nff, from.base_dir, from.name,
                      from.files, from.geometry_key);
  }
  glint::Scene scene = check(document, meshes, from);
  return make_state(std::move(document), std::move(scene), std::move(meshes), from.nff, from.base_dir, from.name,
                    from.files);
}

void set_value(Json& document, const AttachedMeshes& meshes, std::string_view path, Json value) {
  Json* at = find(document, parse_path(path), true, path, &meshes);
  if (!at) throw Error(SourceLocation{}, std::string(path), "no such place in the scene");
  *at = std::move(value);
}

// A new id for attached arrays, unique in the process: copies of a scene
// share their arrays, and an id always names the same arrays.
uint64_t next_mesh_id() {
  static std::atomic<uint64_t> next{1};
  return next++;
}

// add_mesh's checks, named as Python's glint.Scene.add_mesh names its
// arguments: sizes, index range, finite values.
void check_mesh_arrays(const MeshArrays& a, const std::string& scene_name) {
  auto fail = [&](std::string path, const std::string& what) -> Error {
    return Error(SourceLocation{scene_name, 0, 0}, std::move(path), what);
  };
  auto finite_rows = [&](const std::vector<float>& v, size_t k, const char* name) {
    for (size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        throw fail(std::string(name) + "[" + std::to_string(i / k) + "]", "not a finite number");
  };
  if (a.positions.size() % 3 != 0) throw fail("vertices", "expected 3 floats per vertex");
  const size_t n = a.positions.size() / 3;
  if (n == 0) throw fail("vertices", "no vertices");
  if (n > UINT32_MAX) throw fail("vertices", "more than 2^32 - 1 vertices");
  if (a.triangles.size() % 3 != 0) throw fail("triangles", "expected 3 indices per triangle");
  if (a.triangles.empty()) throw fail("triangles", "no triangles");
  for (size_t i = 0; i < a.triangles.size(); ++i)
    if (a.triangles[i] >= n)
      throw fail("triangles[" + std::to_string(i / 3) + "]", "vertex index " + std::to_string(a.triangles[i]) +
                                                                 " out of range (" + std::to_string(n) + " vertices)");
  if (!a.normals.empty() && a.normals.size() != 3 * n)
    throw fail("normals",
               "expected one per vertex (" + std::to_string(n) + "), got " + std::to_string(a.normals.size() / 3));
  if (!a.uvs.empty() && a.uvs.size() != 2 * n)
    throw fail("uvs", "expected one per vertex (" + std::to_string(n) + "), got " + std::to_string(a.uvs.size() / 2));
  finite_rows(a.positions, 3, "vertices");
  finite_rows(a.normals, 3, "normals");
  finite_rows(a.uvs, 2, "uvs");
}

}  // namespace

Scene reread_files(const Scene& scene) {
  return Scene(edited(*scene.state(), "", [](Json&, AttachedMeshes&) {}));
}

void Scene::set_json(std::string_view path, std::string_view json_value) {
  Json value = parse_value(json_value, path);
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) { set_value(d, m, path, std::move(value)); });
}
void Scene::set(std::string_view path, double value) {
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) { set_value(d, m, path, value); });
}
void Scene::set(std::string_view path, int value) {
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) { set_value(d, m, path, value); });
}
void Scene::set(std::string_view path, bool value) {
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) { set_value(d, m, path, value); });
}
void Scene::set(std::string_view path, const std::array<double, 3>& value) {
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) {
    set_value(d, m, path, Json::array({value[0], value[1], value[2]}));
  });
}
void Scene::set_string(std::string_view path, std::string_view value) {
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) { set_value(d, m, path, std::string(value)); });
}

void Scene::erase(std::string_view path) {
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) {
    std::vector<Step> steps = parse_path(path);
    const Step last = steps.back();
    steps.pop_back();
    Json* parent = steps.empty() ? &d : find(d, steps, false, path, &m);
    if (parent && last.is_index && parent->is_array() && last.index < parent->size()) {
      parent->erase(last.index);
      return;
    }
    if (parent && !last.is_index && last.key != kAttachedMeshKey) {
      if (is_array_key(last.key) && is_attached(*parent)) expand(*parent, m);
      if (parent->is_object() && parent->erase(last.key) == 1) return;
    }
    throw Error(SourceLocation{}, std::string(path), "not in the scene");
  });
}

void Scene::append_json(std::string_view array_path, std::string_view json_value) {
  Json value = parse_value(json_value, array_path);
  state_ = edited(*state_, array_path, [&](Json& d, AttachedMeshes& m) {
    Json* at = find(d, parse_path(array_path), true, array_path, &m);
    if (!at) throw Error(SourceLocation{}, std::string(array_path), "no such place in the scene");
    if (at->is_null()) *at = Json::array();
    if (!at->is_array()) throw Error(SourceLocation{}, std::string(array_path), "not an array");
    at->push_back(std::move(value));
  });
}

void Scene::update_json(std::string_view path, std::string_view json_object) {
  Json values = parse_value(json_object, path);
  if (!values.is_object()) throw Error(SourceLocation{}, std::string(path), "expected an object of keys to set");
  state_ = edited(*state_, path, [&](Json& d, AttachedMeshes& m) {
    Json* at = find(d, parse_path(path), true, path, &m);  // a missing section ("render") is added
    if (at && at->is_null()) *at = Json::object();
    if (!at || !at->is_object()) throw Error(SourceLocation{}, std::string(path), "no such object in the scene");
    for (auto& item : values.items()) {
      if (item.key() == kAttachedMeshKey) throw Error(SourceLocation{}, std::string(path), "no such key \"$arrays\"");
      if (is_array_key(item.key()) && is_attached(*at)) expand(*at, m);
      (*at)[item.key()] = std::move(item.value());
    }
  });
}

void Scene::add_mesh(MeshArrays arrays, std::string_view object_json) {
  check_mesh_arrays(arrays, state_->name);
  const Json keys = parse_value(object_json, "add_mesh");
  if (!keys.is_object()) throw Error(SourceLocation{}, "add_mesh: expected the object's keys as a JSON object");
  Json object = Json::object();
  object["type"] = "mesh";
  for (const auto& item : keys.items()) {
    if (item.key() == "type" && item.value() != "mesh")
      throw Error(SourceLocation{}, "type", "add_mesh makes a mesh (got " + item.value().dump() + ")");
    if (is_array_key(item.key()) || item.key() == "file" || item.key() == kAttachedMeshKey)
      throw Error(SourceLocation{}, item.key(), "given by the arrays; not a key here");
    object[item.key()] = item.value();
  }
  const uint64_t id = next_mesh_id();
  object[kAttachedMeshKey] = id;
  auto shared = std::make_shared<const MeshArrays>(std::move(arrays));
  state_ = edited(*state_, "objects", [&](Json& d, AttachedMeshes& m) {
    m.emplace(id, shared);
    Json* objects = find(d, parse_path("objects"), true, "objects", &m);
    if (objects->is_null()) *objects = Json::array();
    if (!objects->is_array()) throw Error(SourceLocation{}, "objects", "not an array");
    objects->push_back(std::move(object));
  });
}

std::vector<std::string> Scene::warnings() const { return state_->scene->warnings; }
int Scene::width() const { return state_->scene->render.width; }
int Scene::height() const { return state_->scene->render.height; }
size_t Scene::object_count() const { return state_->scene->objects.size(); }
size_t Scene::light_count() const { return state_->scene->lights.size(); }
size_t Scene::geometry_key() const { return state_->geometry_key; }

std::vector<std::string> Scene::material_names() const {
  std::vector<std::string> names;
  if (auto it = state_->document.find("materials"); it != state_->document.end() && it->is_object())
    for (const auto& [name, _] : it->items()) names.push_back(name);
  return names;
}

}  // namespace glint::api
