// The public Scene: its document is the truth, and every state of it is
// checked by the loader itself (parse_scene), so an edit meets exactly the
// rules and messages of the scene file.
#include <charconv>
#include <functional>

#include "glint/api/scene_state.h"
#include "glint/io/file_io.h"
#include "glint/io/nff_file.h"
#include "glint/io/mesh_scene.h"
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

// The value at `steps` (nullptr when absent). With `create`, the last step
// may be a missing object key, which is added.
Json* find(Json& root, const std::vector<Step>& steps, bool create, std::string_view path) {
  Json* at = &root;
  for (size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    const bool last = i + 1 == steps.size();
    if (s.is_index) {
      if (!at->is_array() || s.index >= at->size()) return nullptr;
      at = &(*at)[s.index];
    } else {
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

Json parse_value(std::string_view json_text, std::string_view what) {
  Json v = Json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (v.is_discarded()) throw Error(SourceLocation{}, std::string(what), "not valid JSON: " + std::string(json_text.substr(0, 80)));
  return v;
}

size_t hash_combine(size_t seed, size_t v) { return seed ^ (v + 0x9e3779b97f4a7c15ULL + (seed << 6) + (seed >> 2)); }

template <typename T>
size_t hash_bytes(const std::vector<T>& values) {
  return std::hash<std::string_view>{}(
      std::string_view(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)));
}

// Objects, animation and the mesh files' triangles: what the acceleration
// structure is built from. The triangles as read, not the files' sizes and
// times: a file rewritten within the clock's granularity keeps its time, and
// one that changes between its reading and a look at its time would pair
// the new time with the old triangles. (Hashing is far cheaper than reading.)
size_t compute_geometry_key(const Json& document, const glint::Scene& scene) {
  size_t key = 0;
  if (auto it = document.find("objects"); it != document.end()) key = std::hash<std::string>{}(it->dump());
  if (auto it = document.find("animation"); it != document.end())
    key = hash_combine(key, std::hash<std::string>{}(it->dump()));
  for (const Mesh& mesh : scene.meshes) {
    key = hash_combine(key, std::hash<std::string>{}(mesh.file));
    key = hash_combine(key, hash_bytes(mesh.positions));
    key = hash_combine(key, hash_bytes(mesh.indices));
  }
  return key;
}

std::shared_ptr<const Scene::State> make_state(Json document, glint::Scene scene, std::filesystem::path base_dir,
                                               std::string name, std::shared_ptr<FileCache> files) {
  auto state = std::make_shared<Scene::State>();
  state->files = std::move(files);
  state->geometry_key = compute_geometry_key(document, scene);
  state->document = std::move(document);
  state->scene = std::make_shared<const glint::Scene>(std::move(scene));
  state->base_dir = std::move(base_dir);
  state->name = std::move(name);
  return state;
}

// The loader's verdict on an edited document. Its messages point into text
// the user never saw, so they keep the path and the problem only.
glint::Scene check(const Json& document, const Scene::State& from) {
  try {
    return parse_scene(document.dump(), from.name, from.base_dir, default_memory_budget(), from.files.get());
  } catch (const Error& e) {
    if (e.path().empty() || e.message().size() < e.path().size() + 2) throw Error(SourceLocation{from.name, 0, 0}, e.message());
    throw Error(SourceLocation{from.name, 0, 0}, e.path(), e.message().substr(e.path().size() + 2));
  }
}

Scene from_json_with(std::string_view json_text, const std::filesystem::path& base_dir, std::string_view name,
                     std::shared_ptr<FileCache> files) {
  glint::Scene scene = parse_scene(std::string(json_text), std::string(name), base_dir, default_memory_budget(), files.get());
  std::string_view text = json_text;
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  Json document = Json::parse(text.begin(), text.end());
  return Scene(make_state(std::move(document), std::move(scene), base_dir, std::string(name), std::move(files)));
}

}  // namespace

Scene load_scene_with(const std::filesystem::path& path, std::shared_ptr<FileCache> files) {
  // A bare mesh file: its framing scene is the document (io/mesh_scene.h).
  if (is_mesh_file(path)) return from_json_with(mesh_scene_json(path), path.parent_path(), path.string(), std::move(files));
  glint::Scene scene = load_scene(path, files.get());  // every check, with file:line:col
  if (is_nff_path(path)) {
    // An NFF file's document is the glint JSON its reader makes (docs/nff.md).
    Json document = read_nff_file(path).document;
    return Scene(make_state(std::move(document), std::move(scene), path.parent_path(), path.string(), std::move(files)));
  }
  const std::vector<unsigned char> bytes = read_file(path);
  size_t skip = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF ? 3 : 0;
  Json document = Json::parse(bytes.begin() + static_cast<std::ptrdiff_t>(skip), bytes.end());
  return Scene(make_state(std::move(document), std::move(scene), path.parent_path(), path.string(), std::move(files)));
}

Scene Scene::load(const std::filesystem::path& path) { return load_scene_with(path, nullptr); }

Scene Scene::from_json(std::string_view json_text, const std::filesystem::path& base_dir, std::string_view name) {
  return from_json_with(json_text, base_dir, name, nullptr);
}

std::string Scene::to_json(int indent) const { return state_->document.dump(indent); }
const std::filesystem::path& Scene::base_dir() const { return state_->base_dir; }
const std::string& Scene::name() const { return state_->name; }

std::string Scene::get(std::string_view path) const {
  Json copy = state_->document;  // find() wants a mutable root; documents are small
  const Json* v = find(copy, parse_path(path), false, path);
  if (!v) throw Error(SourceLocation{state_->name, 0, 0}, std::string(path), "not in the scene");
  return v->dump();
}

bool Scene::has(std::string_view path) const {
  Json copy = state_->document;
  return find(copy, parse_path(path), false, path) != nullptr;
}

namespace {

// Applies `edit` to a copy of the document and checks the result; the
// scene changes only when the loader accepts it.
std::shared_ptr<const Scene::State> edited(const Scene::State& from, const std::function<void(Json&)>& edit) {
  Json document = from.document;
  edit(document);
  glint::Scene scene = check(document, from);
  return make_state(std::move(document), std::move(scene), from.base_dir, from.name, from.files);
}

void set_value(Json& document, std::string_view path, Json value) {
  Json* at = find(document, parse_path(path), true, path);
  if (!at) throw Error(SourceLocation{}, std::string(path), "no such place in the scene");
  *at = std::move(value);
}

}  // namespace

Scene reread_files(const Scene& scene) { return Scene(edited(*scene.state(), [](Json&) {})); }

void Scene::set_json(std::string_view path, std::string_view json_value) {
  Json value = parse_value(json_value, path);
  state_ = edited(*state_, [&](Json& d) { set_value(d, path, std::move(value)); });
}
void Scene::set(std::string_view path, double value) {
  state_ = edited(*state_, [&](Json& d) { set_value(d, path, value); });
}
void Scene::set(std::string_view path, int value) {
  state_ = edited(*state_, [&](Json& d) { set_value(d, path, value); });
}
void Scene::set(std::string_view path, bool value) {
  state_ = edited(*state_, [&](Json& d) { set_value(d, path, value); });
}
void Scene::set(std::string_view path, const std::array<double, 3>& value) {
  state_ = edited(*state_, [&](Json& d) { set_value(d, path, Json::array({value[0], value[1], value[2]})); });
}
void Scene::set_string(std::string_view path, std::string_view value) {
  state_ = edited(*state_, [&](Json& d) { set_value(d, path, std::string(value)); });
}

void Scene::erase(std::string_view path) {
  state_ = edited(*state_, [&](Json& d) {
    std::vector<Step> steps = parse_path(path);
    const Step last = steps.back();
    steps.pop_back();
    Json* parent = steps.empty() ? &d : find(d, steps, false, path);
    if (parent && last.is_index && parent->is_array() && last.index < parent->size()) {
      parent->erase(last.index);
      return;
    }
    if (parent && !last.is_index && parent->is_object() && parent->erase(last.key) == 1) return;
    throw Error(SourceLocation{}, std::string(path), "not in the scene");
  });
}

void Scene::append_json(std::string_view array_path, std::string_view json_value) {
  Json value = parse_value(json_value, array_path);
  state_ = edited(*state_, [&](Json& d) {
    Json* at = find(d, parse_path(array_path), true, array_path);
    if (!at) throw Error(SourceLocation{}, std::string(array_path), "no such place in the scene");
    if (at->is_null()) *at = Json::array();
    if (!at->is_array()) throw Error(SourceLocation{}, std::string(array_path), "not an array");
    at->push_back(std::move(value));
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
