// The scene reader behind io/scene_loader.h: one class that walks a parsed
// scene document and returns a checked Scene, its member functions defined
// by section (render_camera.cpp, materials.cpp, lights.cpp, objects.cpp,
// meshes.cpp, animation.cpp; paths and messages in scene_reader.cpp). The
// checks for single values (numbers, vectors, colors, enum names) stay here,
// inline: every section uses them, for every value of a large scene.
// Internal to io/ (not installed).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "glint/error.h"
#include "glint/io/json.h"
#include "glint/io/memory_limit.h"
#include "glint/io/scene_loader.h"
#include "glint/scene/scene.h"
#include "glint/util/strings.h"

namespace glint::loader {

using json::Value;
using Keys = std::vector<std::string_view>;

// Text from the scene file as it appears in a message: control characters
// escaped (a message is one line) and long text cut short.
std::string printable(std::string_view s);
std::string quote_text(std::string_view s);
std::string quoted_list(const Keys& keys);
std::string format_number(double v);

// Where a value sits in the document ("objects[3].radius"), kept as a chain
// of stack references while the reader descends and formatted only when a
// message needs it: a million objects cost no string building.
class Path {
 public:
  Path(const char* name) : name_(name) {}  // NOLINT: a literal path ("render.width")
  Path(const Path& parent, std::string_view key) : parent_(&parent), name_(key) {}
  Path(const Path& parent, size_t index) : parent_(&parent), index_(index), is_index_(true) {}

  bool empty() const { return parent_ == nullptr && name_.empty(); }
  std::string_view last_key() const { return name_; }
  std::string str() const;

 private:
  const Path* parent_ = nullptr;
  std::string_view name_;
  size_t index_ = 0;
  bool is_index_ = false;
};

// Reads one scene document. Each reader function takes the value and its
// path in the document (for messages) and returns checked data.
class SceneReader {
 public:
  SceneReader(const json::Document& doc, std::filesystem::path base_dir, size_t memory_budget = default_memory_budget(),
              const AttachedMeshes* attached = nullptr, FileCache* files = nullptr)
      : doc_(doc), base_dir_(std::move(base_dir)), attached_(attached), memory_budget_(memory_budget), files_(files) {}

  // With `errors`, problems are collected (one per material, light, object
  // or section) and reading goes on; without, the first one is thrown.
  Scene read(std::vector<Error>* errors = nullptr);

 private:
  // --- errors and shapes of values -------------------------------------
  // Runs `step`; a glint::Error it throws is recorded when collecting, else
  // passed on. Returns whether the step succeeded.
  template <class Step>
  bool collect(Step&& step) {
    if (!errors_) {
      step();
      return true;
    }
    try {
      step();
      return true;
    } catch (const Error& e) {
      errors_->push_back(e);
      return false;
    }
  }

  [[noreturn]] void fail(const Value& at, const Path& path, const std::string& what) const {
    throw Error(at.location(), path.empty() ? std::string() : path.str(), what);
  }

  static Path join(const Path& path, std::string_view key) { return Path(path, key); }
  static Path index(const Path& path, size_t i) { return Path(path, i); }

  void expect_object(const Value& v, const Path& path) const {
    if (!v.is_object()) fail(v, path, std::string("expected an object, got ") + v.kind_name());
  }
  void expect_array(const Value& v, const Path& path) const {
    if (!v.is_array()) fail(v, path, std::string("expected an array, got ") + v.kind_name());
  }

  // Every key must be one of `allowed`; an unknown one is an error with a hint.
  void check_keys(const Value& obj, const Path& path, const Keys& allowed) const {
    for (size_t i = 0; i < obj.size(); ++i) {
      const std::string_view key = obj.key(i);
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string what = "unknown key " + quote_text(key);
      const std::string hint = closest_match(key, allowed);
      if (!hint.empty()) what += " (did you mean \"" + hint + "\"?)";
      else what += " (expected one of " + quoted_list(allowed) + ")";
      throw Error(obj.key_location(i), path.empty() ? std::string() : path.str(), what);
    }
  }

  Value require(const Value& obj, const Path& path, std::string_view key) const {
    if (auto v = obj.find(key)) return *v;
    fail(obj, path.empty() ? Path("scene") : path, "missing required key \"" + std::string(key) + "\"");
  }

  double number(const Value& v, const Path& path) const {
    if (!v.is_number()) fail(v, path, std::string("expected a number, got ") + v.kind_name());
    const double x = v.as_number();
    if (!std::isfinite(x)) fail(v, path, "must be a finite number");
    return x;
  }
  double positive(const Value& v, const Path& path) const {
    const double x = number(v, path);
    if (!(x > 0)) fail(v, path, "must be > 0 (got " + format_number(x) + ")");
    return x;
  }
  double non_negative(const Value& v, const Path& path) const {
    const double x = number(v, path);
    if (!(x >= 0)) fail(v, path, "must be >= 0 (got " + format_number(x) + ")");
    return x;
  }
  int integer(const Value& v, const Path& path, int lo, int hi) const {
    const double x = number(v, path);
    if (!v.is_integer() || x != std::floor(x)) fail(v, path, "expected a whole number, got " + format_number(x));
    if (x < lo) fail(v, path, "must be >= " + std::to_string(lo) + " (got " + format_number(x) + ")");
    if (x > hi) fail(v, path, "must be <= " + std::to_string(hi) + " (got " + format_number(x) + ")");
    return static_cast<int>(x);
  }
  bool boolean(const Value& v, const Path& path) const {
    if (!v.is_bool()) fail(v, path, std::string("expected true or false, got ") + v.kind_name());
    return v.as_bool();
  }
  std::string string(const Value& v, const Path& path) const {
    if (!v.is_string()) fail(v, path, std::string("expected a string, got ") + v.kind_name());
    return std::string(v.as_string());
  }
  // One of `names`, with a hint for near misses.
  size_t choice(const Value& v, const Path& path, const Keys& names, const char* what) const {
    const std::string s = string(v, path);
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == s) return i;
    std::string msg = std::string("unknown ") + what + " " + quote_text(s);
    const std::string hint = closest_match(s, names);
    msg += hint.empty() ? " (expected one of " + quoted_list(names) + ")" : " (did you mean \"" + hint + "\"?)";
    fail(v, path, msg);
  }

  Vec3 vec3(const Value& v, const Path& path) const {
    if (!v.is_array() || v.size() != 3)
      fail(v, path,
           std::string("expected [x, y, z], got ") +
               (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.kind_name())));
    return {number(v[0], index(path, 0)), number(v[1], index(path, 1)), number(v[2], index(path, 2))};
  }
  static std::optional<Vec3> unit(const Vec3& d) { return unit_direction(d); }
  Vec3 direction(const Value& v, const Path& path) const {
    const auto d = unit(vec3(v, path));
    if (!d) fail(v, path, "must be a non-zero vector");
    return *d;
  }
  // A color: [r, g, b] or one number meaning gray; never negative.
  Color color(const Value& v, const Path& path) const {
    Color c;
    if (v.is_number()) {
      c = Color(number(v, path));
    } else if (v.is_array() && v.size() == 3) {
      c = vec3(v, path);
    } else {
      fail(v, path,
           std::string("expected a color ([r, g, b] or a number), got ") +
               (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.kind_name())));
    }
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(v, path, "color components must be >= 0");
    return c;
  }

  // --- files named in the scene (scene_reader.cpp) ---------------------
  std::filesystem::path beside_scene(std::string_view name) const;
  static std::string file_key(const std::filesystem::path& file);

  // --- render and camera (render_camera.cpp) -----------------------------
  void read_render(const Value& r);
  PixelFilter pixel_filter(const Value& v) const;
  double unit_interval(const Value& v, const Path& path) const;
  AdaptiveSampling adaptive(const Value& v, int samples_per_pixel) const;
  Fog fog(const Value& v, const Color& background) const;
  Environment environment(const Value& v);
  void read_camera(const Value& c);

  // --- materials and textures (materials.cpp) ----------------------------
  void read_materials(const Value& m);
  void read_material(const Value& v, const Path& path);
  void reflectance(const Value& v, const Path& path, Color& c, uint32_t& texture);
  std::array<double, 2> pair(const Value& v, const Path& path) const;
  void read_uv_transform(const Value& v, const Path& path, Texture& t) const;
  uint32_t read_texture(const Value& v, const Path& path);
  uint32_t texture_image(const std::filesystem::path& file);
  uint32_t load_texture(const Value& v, const Path& path);

  // --- lights (lights.cpp) -----------------------------------------------
  void read_lights(const Value& list);
  void read_light(const Value& v, const Path& path);

  // --- objects and their shapes (objects.cpp) ----------------------------
  std::optional<Transform> read_transform(const Value& v, const Path& path) const;
  void read_objects(const Value& list);
  uint32_t material_ref(const Value& v, const Path& path) const;
  void read_object(const Value& v, const Path& path);
  Sphere read_sphere(const Value& v, const Path& path) const;
  Box read_box(const Value& v, const Path& path) const;
  Cone read_cone(const Value& v, const Path& path, bool cylinder) const;
  Torus read_torus(const Value& v, const Path& path) const;
  void read_csg_operation(const Value& v, const Path& path, uint32_t material, const std::optional<Transform>& to_csg,
                          Csg& csg, uint32_t node, int depth);
  void read_csg_child(const Value& v, const Path& path, uint32_t material, const std::optional<Transform>& to_csg,
                      Csg& csg, uint32_t node, int depth);
  uint32_t read_polygon(const Value& v, const Path& path, uint32_t material, const std::optional<Transform>& transform);

  // --- meshes: files, inline and attached (meshes.cpp) -------------------
  uint32_t load_mesh(const Value& v, const Path& path);
  uint32_t inline_mesh(const Value& v, const Path& path, bool smooth);
  void count_inline_mesh(const Value& v, const Path& path, size_t vertices, size_t triangles);
  uint32_t add_mesh_from_arrays(const Value& v, const Path& path, std::vector<Vec3f> positions,
                                std::vector<uint32_t> indices, const std::vector<Vec3f>& normals,
                                const std::vector<UVf>& uvs, bool smooth);
  uint32_t attached_mesh(const Value& v, const Path& path, bool smooth);
  Vec3f float_vec3(const Value& v, const Path& path) const;

  // --- animation (animation.cpp) -----------------------------------------
  void read_animation(const Value& a, const std::optional<Value>& objects);
  void read_camera_key(const Value& c, const Path& path, double time, CameraTracks& tracks) const;
  Vec3 scale_factors(const Value& s, const Path& p) const;
  Rotation rotation(const Value& r, const Path& p) const;
  void read_object_key(const Value& v, const Path& path, double time, ObjectTracks& tracks) const;
  bool find_animated_object(const Value& keyed, size_t m, const Path& path, const std::optional<Value>& objects,
                            ObjectTracks& tracks) const;

  const json::Document& doc_;
  std::filesystem::path base_dir_;
  const AttachedMeshes* attached_ = nullptr;
  std::vector<Error>* errors_ = nullptr;
  std::map<std::string, uint32_t> mesh_index_;           // canonical path -> Scene::meshes
  std::set<std::string> smooth_mesh_files_;              // canonical paths some object shades smoothly
  std::map<std::string, uint32_t> texture_image_index_;  // canonical path -> Scene::texture_images
  size_t memory_budget_;
  FileCache* files_;                               // or nullptr: read every file
  size_t mesh_vertices_ = 0, mesh_triangles_ = 0;  // of every mesh file loaded
  Scene scene_;
  std::map<std::string, uint32_t, std::less<>> material_index_;
  std::vector<size_t> object_json_index_;  // Scene::objects -> index in the "objects" array
};

}  // namespace glint::loader
