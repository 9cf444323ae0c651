#include "glint/io/scene_loader.h"

// GCC 12 warns falsely about std::string concatenation at -O3 (GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "glint/geometry/polygon.h"
#include "glint/io/json.h"
#include "glint/io/memory_limit.h"
#include "glint/io/file_cache.h"
#include "glint/io/mesh_file.h"
#include "glint/io/nff_file.h"
#include "glint/io/mesh_scene.h"
#include "glint/io/texture_file.h"
#include "glint/scene.h"  // api::MeshArrays (attached meshes)

namespace glint {

namespace {

using json::Value;
using Keys = std::vector<std::string_view>;

// Edits (insert, delete, substitute, swap two neighbours) between a and b,
// ignoring case: "widht" is one edit from "width".
size_t edit_distance(std::string_view a, std::string_view b) {
  if (a.size() > 256 || b.size() > 256) return std::max(a.size(), b.size());  // no hint for huge keys
  auto lower = [](char c) { return std::tolower(static_cast<unsigned char>(c)); };
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) && lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// Text from the scene file as it appears in a message: control characters
// escaped (a message is one line) and long text cut short.
std::string printable(std::string_view s) {
  constexpr size_t kMaxShown = 64;
  std::string out;
  size_t shown = s.size() > kMaxShown ? kMaxShown : s.size();
  while (shown < s.size() && shown > 0 && (static_cast<unsigned char>(s[shown]) & 0xC0) == 0x80)
    --shown;  // do not cut a UTF-8 sequence in two
  for (size_t i = 0; i < shown; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04X", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (shown < s.size()) out += "...";
  return out;
}

std::string quote_text(std::string_view s) { return "\"" + printable(s) + "\""; }

std::string quoted_list(const Keys& keys) {
  std::string out;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (i) out += ", ";
    out += "\"" + std::string(keys[i]) + "\"";
  }
  return out;
}

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

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
  std::string str() const {
    std::string out = parent_ ? parent_->str() : std::string();
    if (is_index_) return out + "[" + std::to_string(index_) + "]";
    if (!out.empty()) out += ".";
    return out + (parent_ ? printable(name_) : std::string(name_));
  }

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
  SceneReader(const json::Document& doc, std::filesystem::path base_dir,
              size_t memory_budget = default_memory_budget(), const AttachedMeshes* attached = nullptr,
              FileCache* files = nullptr)
      : doc_(doc), base_dir_(std::move(base_dir)), attached_(attached), memory_budget_(memory_budget), files_(files) {}

  // With `errors`, problems are collected (one per material, light, object
  // or section) and reading goes on; without, the first one is thrown.
  Scene read(std::vector<Error>* errors = nullptr) {
    errors_ = errors;
    const Value root = doc_.root();
    expect_object(root, "scene");
    collect([&] {
      check_keys(root, "", {"render", "camera", "materials", "lights", "objects", "animation", "$schema"});
    });
    if (auto r = root.find("render")) collect([&] { read_render(*r); });
    collect([&] { read_camera(require(root, "", "camera")); });
    if (auto m = root.find("materials")) collect([&] { read_materials(*m); });
    if (auto l = root.find("lights")) collect([&] { read_lights(*l); });
    collect([&] { read_objects(require(root, "", "objects")); });
    if (auto a = root.find("animation")) collect([&] { read_animation(*a, root.find("objects")); });
    return std::move(scene_);
  }

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
      if (!hint.empty())
        what += " (did you mean \"" + hint + "\"?)";
      else
        what += " (expected one of " + quoted_list(allowed) + ")";
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
    if (!v.is_integer() || x != std::floor(x))
      fail(v, path, "expected a whole number, got " + format_number(x));
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
      fail(v, path, std::string("expected [x, y, z], got ") +
                        (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.kind_name())));
    return {number(v[0], index(path, 0)), number(v[1], index(path, 1)), number(v[2], index(path, 2))};
  }
  // d / |d|, or nullopt for a zero (or non-finite) vector. Divides by the
  // largest component first, so huge (1e300) or tiny (1e-300) components
  // neither overflow nor underflow the length.
  static std::optional<Vec3> unit(const Vec3& d) {
    const double big = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    if (!(big > 0) || !std::isfinite(big)) return std::nullopt;
    const Vec3 s = d / big;
    return s / length(s);
  }
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
      fail(v, path, std::string("expected a color ([r, g, b] or a number), got ") +
                        (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.kind_name())));
    }
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(v, path, "color components must be >= 0");
    return c;
  }

  // --- sections ----------------------------------------------------------
  void read_render(const Value& r) {
    const Path path("render");
    expect_object(r, path);
    check_keys(r, path, {"width", "height", "samples_per_pixel", "max_depth", "shading_model", "background", "epsilon",
                         "pixel_filter", "adaptive"});
    RenderSettings& s = scene_.render;
    if (auto v = r.find("width")) s.width = integer(*v, "render.width", 1, 1 << 20);
    if (auto v = r.find("height")) s.height = integer(*v, "render.height", 1, 1 << 20);
    if (auto v = r.find("samples_per_pixel"))
      s.samples_per_pixel = integer(*v, "render.samples_per_pixel", 1, kMaxSamplesPerPixel);
    if (auto v = r.find("max_depth")) s.max_depth = integer(*v, "render.max_depth", 1, kMaxDepthLimit);
    if (auto v = r.find("shading_model"))
      s.shading_model = choice(*v, "render.shading_model", {"phong", "blinn-phong"}, "shading model") == 0
                            ? ShadingModel::phong
                            : ShadingModel::blinn_phong;
    if (auto v = r.find("background")) s.background = color(*v, "render.background");
    if (auto v = r.find("epsilon")) s.epsilon = positive(*v, "render.epsilon");
    if (auto v = r.find("pixel_filter")) s.pixel_filter = pixel_filter(*v);
    if (auto v = r.find("adaptive")) s.adaptive = adaptive(*v, s.samples_per_pixel);
    SourceLocation where = r.location();
    if (auto v = r.find("height")) where = v->location();
    if (auto v = r.find("width")) where = v->location();
    check_image_size(s.width, s.height, where);
  }

  // "gaussian", or {"type": "gaussian", "radius": 1.5, "sigma": 0.5}.
  PixelFilter pixel_filter(const Value& v) const {
    const Path path("render.pixel_filter");
    const Keys names = {"box", "gaussian", "mitchell"};
    PixelFilter f;
    if (v.is_object()) {
      check_keys(v, path, {"type", "radius", "sigma", "b", "c"});
      const Value type = require(v, path, "type");
      f.type = static_cast<FilterType>(choice(type, "render.pixel_filter.type", names, "pixel filter"));
    } else {
      f.type = static_cast<FilterType>(choice(v, path, names, "pixel filter"));
    }
    if (f.type == FilterType::gaussian) f.radius = kGaussianRadius;
    if (f.type == FilterType::mitchell) f.radius = kMitchellRadius;
    if (!v.is_object()) return f;
    const Keys allowed = f.type == FilterType::box        ? Keys{"type"}
                         : f.type == FilterType::gaussian ? Keys{"type", "radius", "sigma"}
                                                          : Keys{"type", "radius", "b", "c"};
    for (size_t i = 0; i < v.size(); ++i)
      if (std::find(allowed.begin(), allowed.end(), v.key(i)) == allowed.end())
        throw Error(v.key_location(i), path.str(), "key \"" + std::string(v.key(i)) + "\" does not apply to the " +
                                           std::string(names[static_cast<size_t>(f.type)]) + " filter");
    if (auto r = v.find("radius")) {
      f.radius = positive(*r, "render.pixel_filter.radius");
      if (f.radius > kMaxFilterRadius) fail(*r, "render.pixel_filter.radius", "must be <= 16 (got " + format_number(f.radius) + ")");
    }
    if (auto x = v.find("sigma")) f.sigma = positive(*x, "render.pixel_filter.sigma");
    if (auto x = v.find("b")) f.b = unit_interval(*x, "render.pixel_filter.b");
    if (auto x = v.find("c")) f.c = unit_interval(*x, "render.pixel_filter.c");
    return f;
  }
  double unit_interval(const Value& v, const Path& path) const {
    const double x = number(v, path);
    if (x < 0 || x > 1) fail(v, path, "must be between 0 and 1 (got " + format_number(x) + ")");
    return x;
  }

  // {"max_samples_per_pixel": M, "threshold": T}
  AdaptiveSampling adaptive(const Value& v, int samples_per_pixel) const {
    const Path path("render.adaptive");
    expect_object(v, path);
    check_keys(v, path, {"max_samples_per_pixel", "threshold"});
    AdaptiveSampling a;
    const Value m = require(v, path, "max_samples_per_pixel");
    a.max_samples_per_pixel = integer(m, "render.adaptive.max_samples_per_pixel", 1, kMaxSamplesPerPixel);
    if (a.max_samples_per_pixel < samples_per_pixel)
      fail(m, "render.adaptive.max_samples_per_pixel",
           "must be >= render.samples_per_pixel (" + std::to_string(samples_per_pixel) + ")");
    if (auto t = v.find("threshold")) a.threshold = non_negative(*t, "render.adaptive.threshold");
    return a;
  }

  void read_camera(const Value& c) {
    const Path path("camera");
    expect_object(c, path);
    check_keys(c, path, {"type", "position", "look_at", "up", "fov_y", "view_height"});
    Camera& cam = scene_.camera;
    if (auto v = c.find("type"))
      cam.type = choice(*v, "camera.type", {"perspective", "orthographic"}, "camera type") == 0
                     ? CameraType::perspective
                     : CameraType::orthographic;
    cam.position = vec3(require(c, path, "position"), "camera.position");
    const Value look_at = require(c, path, "look_at");
    cam.look_at = vec3(look_at, "camera.look_at");
    if (cam.look_at == cam.position) fail(look_at, "camera.look_at", "must differ from camera.position");
    if (auto v = c.find("up")) cam.up = direction(*v, "camera.up");
    if (auto v = c.find("fov_y")) {
      cam.fov_y = number(*v, "camera.fov_y");
      if (!(cam.fov_y > 0 && cam.fov_y < 180))
        fail(*v, "camera.fov_y", "must be between 0 and 180 degrees, exclusive (got " + format_number(cam.fov_y) + ")");
    }
    if (auto v = c.find("view_height")) cam.view_height = positive(*v, "camera.view_height");
    const auto forward = unit(cam.look_at - cam.position);
    if (!forward) fail(look_at, "camera.look_at", "too far from camera.position (the distance overflows)");
    if (!(length(cross(*forward, cam.up)) > 1e-9)) {
      const auto up = c.find("up");
      fail(up ? *up : c, up ? "camera.up" : "camera", "up is parallel to the view direction");
    }
  }

  void read_materials(const Value& m) {
    const Path materials_path("materials");
    expect_object(m, materials_path);
    for (size_t i = 0; i < m.size(); ++i) {
      const std::string name(m.key(i));
      const Path path(materials_path, name);
      const Value v = m.member(i);
      // A broken material still exists, so objects naming it report nothing more.
      if (!collect([&] { read_material(v, path); })) material_index_[name] = 0;
    }
  }

  void read_material(const Value& v, const Path& path) {
    const std::string name(path.last_key());
    expect_object(v, path);
    check_keys(v, path, {"ambient", "diffuse", "specular", "shininess", "reflectivity", "transparency", "ior", "fresnel"});
    Material mat;
    mat.name = name;
    if (auto x = v.find("ambient")) reflectance(*x, join(path, "ambient"), mat.ambient, mat.ambient_texture);
    if (auto x = v.find("diffuse")) reflectance(*x, join(path, "diffuse"), mat.diffuse, mat.diffuse_texture);
    if (auto x = v.find("specular")) reflectance(*x, join(path, "specular"), mat.specular, mat.specular_texture);
    if (auto x = v.find("shininess")) mat.shininess = positive(*x, join(path, "shininess"));
    if (auto x = v.find("reflectivity")) mat.reflectivity = color(*x, join(path, "reflectivity"));
    if (auto x = v.find("transparency")) mat.transparency = non_negative(*x, join(path, "transparency"));
    if (auto x = v.find("ior")) mat.ior = positive(*x, join(path, "ior"));
    if (auto x = v.find("fresnel")) mat.fresnel = boolean(*x, join(path, "fresnel"));
    material_index_[name] = add_material(scene_, std::move(mat));
  }

  // A reflectance is a color or a texture object (docs/scene-format.md, "Textures").
  void reflectance(const Value& v, const Path& path, Color& c, uint32_t& texture) {
    if (v.is_object()) {
      texture = read_texture(v, path);
      return;
    }
    if (v.is_string())
      fail(v, path, "expected a color ([r, g, b] or a number) or a texture object, got a string (an image is "
                    "written {\"texture\": " + quote_text(v.as_string()) + "})");
    c = color(v, path);
  }

  // [a, b] of finite numbers.
  std::array<double, 2> pair(const Value& v, const Path& path) const {
    if (!v.is_array() || v.size() != 2)
      fail(v, path, std::string("expected [u, v], got ") +
                        (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.kind_name())));
    return {number(v[0], index(path, 0)), number(v[1], index(path, 1))};
  }

  // `scale` (a number or [su, sv], non-zero) and `offset` ([ou, ov]) of a texture's uv.
  void read_uv_transform(const Value& v, const Path& path, Texture& t) const {
    if (auto x = v.find("scale")) {
      const Path p = join(path, "scale");
      const std::array<double, 2> s = x->is_number() ? std::array<double, 2>{number(*x, p), number(*x, p)} : pair(*x, p);
      if (s[0] == 0 || s[1] == 0) fail(*x, p, "must not be zero");
      t.scale_u = s[0];
      t.scale_v = s[1];
    }
    if (auto x = v.find("offset")) {
      const std::array<double, 2> o = pair(*x, join(path, "offset"));
      t.offset_u = o[0];
      t.offset_v = o[1];
    }
  }

  uint32_t read_texture(const Value& v, const Path& path) {
    const auto image = v.find("texture");
    const auto checker = v.find("checker");
    // An error at `key` of this object (the key, not its value, is what is misplaced).
    auto fail_at_key = [&](std::string_view key, const std::string& what) {
      for (size_t k = 0; k < v.size(); ++k)
        if (v.key(k) == key) throw Error(v.key_location(k), join(path, key).str(), what);
    };
    Texture t;
    if (image && checker) fail_at_key("checker", "give either \"texture\" or \"checker\", not both");
    if (checker) {
      // The checker's options live in its own object; say so for the usual slip.
      for (const char* key : {"scale", "offset"})
        if (v.find(key)) fail_at_key(key, std::string("put \"") + key + "\" inside \"checker\"");
      check_keys(v, path, {"checker"});
      const Path p = join(path, "checker");
      expect_object(*checker, p);
      check_keys(*checker, p, {"even", "odd", "scale", "offset"});
      t.kind = TextureKind::checker;
      t.even = color(require(*checker, p, "even"), join(p, "even"));
      t.odd = color(require(*checker, p, "odd"), join(p, "odd"));
      read_uv_transform(*checker, p, t);
    } else {
      check_keys(v, path, {"texture", "wrap", "scale", "offset", "checker"});
      if (!image) fail(v, path, "a texture object needs \"texture\" (an image file) or \"checker\"");
      if (auto x = v.find("wrap")) {
        static constexpr TextureWrap kWraps[] = {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror};
        t.wrap = kWraps[choice(*x, join(path, "wrap"), {"repeat", "clamp", "mirror"}, "wrap mode")];
      }
      read_uv_transform(v, path, t);
      t.image = load_texture(*image, join(path, "texture"));
    }
    scene_.textures.push_back(t);
    return static_cast<uint32_t>(scene_.textures.size() - 1);
  }

  // The key that identifies a file however it is written (textures and meshes are read once).
  // A file named in the scene: relative names are relative to the scene file's folder.
  std::filesystem::path beside_scene(std::string_view name) const {
    const std::filesystem::path file(name);
    return file.is_relative() ? base_dir_ / file : file;
  }

  static std::string file_key(const std::filesystem::path& file) {
    std::error_code ec;
    const std::filesystem::path key = std::filesystem::weakly_canonical(file, ec);
    return ec ? file.string() : key.string();
  }

  // Each image file is read once, however many textures use it. Throws
  // glint::Error naming the file for a missing or unreadable one.
  uint32_t texture_image(const std::filesystem::path& file) {
    const std::string key = file_key(file);
    if (auto it = texture_image_index_.find(key); it != texture_image_index_.end()) return it->second;
    scene_.texture_images.push_back(files_ ? *files_->texture(file) : load_texture_image(file));
    const auto index = static_cast<uint32_t>(scene_.texture_images.size() - 1);
    texture_image_index_[key] = index;
    return index;
  }

  uint32_t load_texture(const Value& v, const Path& path) {
    const std::string name = string(v, path);
    if (name.empty()) fail(v, path, "must name a texture file");
    const std::filesystem::path file = beside_scene(name);
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) fail(v, path, "texture file " + quote_text(file.string()) + " not found");
    try {
      return texture_image(file);
    } catch (const Error& e) {
      fail(v, path, "texture file " + quote_text(file.string()) + ": " + e.message());
    }
  }

  void read_lights(const Value& list) {
    expect_array(list, "lights");
    for (size_t i = 0; i < list.size(); ++i) collect([&] { read_light(list[i], index("lights", i)); });
  }

  void read_light(const Value& v, const Path& path) {
    expect_object(v, path);
    static const Keys types = {"point", "directional", "ambient", "spot", "area"};
    const LightType kinds[] = {LightType::point, LightType::directional, LightType::ambient,
                               LightType::spot, LightType::area};
    Light light;
    light.type = kinds[choice(require(v, path, "type"), join(path, "type"), types, "light type")];
    const std::string type_name(types[static_cast<size_t>(
        std::find(std::begin(kinds), std::end(kinds), light.type) - std::begin(kinds))]);

    Keys allowed = {"type", "name", "ambient", "color"};
    switch (light.type) {
      case LightType::ambient: break;
      case LightType::point: allowed.insert(allowed.end(), {"diffuse", "specular", "position", "attenuation"}); break;
      case LightType::directional: allowed.insert(allowed.end(), {"diffuse", "specular", "direction"}); break;
      case LightType::spot:
        allowed.insert(allowed.end(), {"diffuse", "specular", "position", "direction", "cutoff", "falloff", "attenuation"});
        break;
      case LightType::area:
        allowed.insert(allowed.end(), {"diffuse", "specular", "corner", "edge_u", "edge_v", "samples", "attenuation"});
        break;
    }
    // Keys that belong to other light types get a precise message.
    for (size_t k = 0; k < v.size(); ++k) {
      const std::string_view key = v.key(k);
      static const Keys any_light = {"diffuse", "specular", "position", "direction", "cutoff", "falloff",
                                     "attenuation", "corner", "edge_u", "edge_v", "samples"};
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end() &&
          std::find(any_light.begin(), any_light.end(), key) != any_light.end())
        throw Error(v.key_location(k), join(path, key).str(), std::string("not valid for ") +
                                           (light.type == LightType::ambient || light.type == LightType::area ? "an " : "a ") + type_name + " light");
    }
    check_keys(v, path, allowed);

    if (auto x = v.find("name")) light.name = string(*x, join(path, "name"));
    const auto col = v.find("color");
    if (col && (v.find("diffuse") || v.find("specular")))
      fail(*col, join(path, "color"), "give either \"color\" or \"diffuse\"/\"specular\", not both");
    if (light.type == LightType::ambient) {
      light.diffuse = light.specular = Color(0.0);
      if (col && v.find("ambient")) fail(*col, join(path, "color"), "give either \"color\" or \"ambient\", not both");
      if (col) light.ambient = color(*col, join(path, "color"));
    } else if (col) {
      light.diffuse = light.specular = color(*col, join(path, "color"));
    }
    if (auto x = v.find("ambient")) light.ambient = color(*x, join(path, "ambient"));
    if (auto x = v.find("diffuse")) light.diffuse = color(*x, join(path, "diffuse"));
    if (auto x = v.find("specular")) light.specular = color(*x, join(path, "specular"));

    if (light.type == LightType::point || light.type == LightType::spot)
      light.position = vec3(require(v, path, "position"), join(path, "position"));
    if (light.type == LightType::directional || light.type == LightType::spot)
      light.direction = direction(require(v, path, "direction"), join(path, "direction"));
    if (light.type == LightType::spot) {
      const Value c = require(v, path, "cutoff");
      light.cutoff = number(c, join(path, "cutoff"));
      if (!(light.cutoff > 0 && light.cutoff <= 180))
        fail(c, join(path, "cutoff"), "must be in (0, 180] degrees (got " + format_number(light.cutoff) + ")");
      if (auto x = v.find("falloff")) light.falloff = non_negative(*x, join(path, "falloff"));
    }
    if (light.type == LightType::area) {
      light.corner = vec3(require(v, path, "corner"), join(path, "corner"));
      const Value eu = require(v, path, "edge_u");
      light.edge_u = vec3(eu, join(path, "edge_u"));
      light.edge_v = vec3(require(v, path, "edge_v"), join(path, "edge_v"));
      if (!(length(cross(light.edge_u, light.edge_v)) > 0))
        fail(eu, join(path, "edge_u"), "edge_u and edge_v must span a parallelogram of non-zero area");
      if (auto x = v.find("samples")) light.samples = integer(*x, join(path, "samples"), 1, kMaxAreaLightSamples);
    }
    if (auto x = v.find("attenuation")) {
      const Path p = join(path, "attenuation");
      const Vec3 a = vec3(*x, p);
      if (a.x < 0 || a.y < 0 || a.z < 0) fail(*x, p, "coefficients must be >= 0");
      if (!(a.x > 0 || a.y > 0 || a.z > 0)) fail(*x, p, "at least one coefficient must be > 0");
      light.attenuation = a;
    }
    scene_.lights.push_back(std::move(light));
  }

  std::optional<Transform> read_transform(const Value& v, const Path& path) const {
    expect_object(v, path);
    check_keys(v, path, {"scale", "rotate", "translate", "matrix"});
    Transform t;
    if (auto m = v.find("matrix")) {
      if (v.size() != 1)
        fail(v, path, "\"matrix\" cannot be combined with \"scale\", \"rotate\" or \"translate\"");
      const Path p = join(path, "matrix");
      if (!m->is_array() || m->size() != 16) fail(*m, p, "expected 16 numbers (a 4x4 matrix, row by row)");
      double e[16];
      for (size_t i = 0; i < 16; ++i) e[i] = number((*m)[i], index(p, i));
      if (e[12] != 0 || e[13] != 0 || e[14] != 0 || e[15] != 1) fail(*m, p, "the last row must be 0 0 0 1");
      Affine a;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) a[r][c] = e[4 * r + c];
      auto xf = Transform::from_affine(a);
      if (!xf) fail(*m, p, "the matrix is singular (or too badly scaled to invert)");
      return xf;
    }
    if (auto s = v.find("scale")) {
      const Path p = join(path, "scale");
      const Vec3 f = s->is_number() ? Vec3(number(*s, p)) : vec3(*s, p);
      if (f.x == 0 || f.y == 0 || f.z == 0) fail(*s, p, "a zero scale makes the transform singular");
      t = Transform::scale(f);
    }
    if (auto r = v.find("rotate")) {
      const Path p = join(path, "rotate");
      expect_object(*r, p);
      check_keys(*r, p, {"axis", "angle"});
      const Vec3 axis = direction(require(*r, p, "axis"), join(p, "axis"));
      const double angle = number(require(*r, p, "angle"), join(p, "angle"));
      t = compose(Transform::rotate(axis, angle), t);
    }
    if (auto tr = v.find("translate")) t = compose(Transform::translate(vec3(*tr, join(path, "translate"))), t);
    // Recheck: extreme scales can still make the composition numerically singular.
    if (!Transform::from_affine(t.m)) fail(v, path, "the transform is singular (or too badly scaled to invert)");
    return t;
  }

  void read_objects(const Value& list) {
    expect_array(list, "objects");
    // Vertex normals are computed only for mesh files some object shades
    // smoothly (the default); a malformed entry is reported by read_object.
    for (size_t i = 0; i < list.size(); ++i) {
      const Value o = list[i];
      if (!o.is_object()) continue;
      const auto type = o.find("type"), file = o.find("file"), smooth = o.find("smooth");
      if (!type || !type->is_string() || type->as_string() != "mesh" || !file || !file->is_string()) continue;
      if (smooth && smooth->is_bool() && !smooth->as_bool()) continue;
      smooth_mesh_files_.insert(file_key(beside_scene(file->as_string())));
    }
    scene_.objects.reserve(list.size());
    for (size_t i = 0; i < list.size(); ++i) {
      collect([&] { read_object(list[i], index("objects", i)); });
      object_json_index_.resize(scene_.objects.size(), i);  // for the animation's names
    }
  }

  // Each mesh file is read once, however many objects use it (instances).
  uint32_t load_mesh(const Value& v, const Path& path) {
    const std::string name = string(v, path);
    if (name.empty()) fail(v, path, "must name a mesh file");
    const std::filesystem::path file = beside_scene(name);
    std::error_code ec;
    const std::string cache_key = file_key(file);
    if (auto it = mesh_index_.find(cache_key); it != mesh_index_.end()) return it->second;
    if (!std::filesystem::exists(file, ec)) fail(v, path, "mesh file " + quote_text(file.string()) + " not found");
    if (std::filesystem::is_directory(file, ec))
      fail(v, path, "mesh file " + quote_text(file.string()) + " is a directory");
    if (!std::filesystem::is_regular_file(file, ec))
      fail(v, path, "mesh file " + quote_text(file.string()) + " is not a regular file (a device or a pipe)");
    // A format this build leaves out (GLINT_ASSIMP=OFF) is refused at the key that names it.
    if (const std::string missing = missing_mesh_support(file); !missing.empty())
      fail(v, path, quote_text(file.string()) + ": " + missing);
    const bool vertex_normals = smooth_mesh_files_.count(cache_key) > 0;
    MeshFile loaded = files_ ? *files_->mesh(file, memory_budget_, vertex_normals)
                             : load_mesh_file(file, memory_budget_, vertex_normals);
    for (std::string& w : loaded.warnings) scene_.warnings.push_back(std::move(w));
    // The file's textures join the scene's; one that cannot be read is a
    // warning and its material keeps its color (the contract: defaults used).
    std::vector<uint32_t> texture_of(loaded.textures.size(), kNoTexture);
    for (size_t i = 0; i < loaded.textures.size(); ++i) {
      const MeshTexture& mt = loaded.textures[i];
      try {
        Texture t;
        t.image = texture_image(mt.file);
        t.wrap = mt.wrap;
        t.scale_u = mt.scale_u;
        t.scale_v = mt.scale_v;
        t.offset_u = mt.offset_u;
        t.offset_v = mt.offset_v;
        scene_.textures.push_back(t);
        texture_of[i] = static_cast<uint32_t>(scene_.textures.size() - 1);
      } catch (const Error& e) {
        scene_.warnings.push_back(mt.named_by + ": texture '" + mt.name + "' not used (defaults used): " + e.what());
      }
    }
    auto remap_texture = [&](uint32_t& t) { t = t < texture_of.size() ? texture_of[t] : kNoTexture; };
    // The file's materials join the scene's; triangles without one use the default.
    std::vector<uint32_t> material_of(loaded.materials.size());
    for (size_t i = 0; i < loaded.materials.size(); ++i) {
      Material m = loaded.materials[i];
      remap_texture(m.ambient_texture);
      remap_texture(m.diffuse_texture);
      remap_texture(m.specular_texture);
      material_of[i] = add_material(scene_, std::move(m));
    }
    Mesh mesh;
    mesh.file = file.string();
    mesh.positions = std::move(loaded.positions);
    mesh.indices = std::move(loaded.indices);
    mesh.corner_normals = std::move(loaded.corner_normals);
    mesh.corner_uvs = std::move(loaded.corner_uvs);
    mesh.triangle_material.resize(mesh.triangle_count(), 0);
    for (size_t t = 0; t < loaded.triangle_material.size() && t < mesh.triangle_count(); ++t) {
      const int32_t m = loaded.triangle_material[t];
      if (m >= 0 && static_cast<size_t>(m) < material_of.size()) mesh.triangle_material[t] = material_of[m];
    }
    // Each file fits on its own (load_mesh_file checks); all of them, with
    // their BVHs, must fit too. Instances share their mesh and cost little.
    mesh_vertices_ += mesh.positions.size();
    mesh_triangles_ += mesh.triangle_count();
    const std::string excess = exceeds_budget(
        kBytesPerVertex * double(mesh_vertices_) + kBytesPerTriangle * double(mesh_triangles_), memory_budget_);
    if (!excess.empty())
      fail(v, path, "with this mesh the scene's " + std::to_string(mesh_index_.size() + 1) + " mesh files hold " +
                        std::to_string(mesh_triangles_) + " triangles: that " + excess);
    const uint32_t index = add_mesh(scene_, std::move(mesh));
    mesh_index_[cache_key] = index;
    return index;
  }

  // --- inline meshes (a glint addition, docs/scene-format.md) -----------
  // "vertices" [[x,y,z]...], "triangles" [[i,j,k]...] (0-based), optional
  // per-vertex "normals" [[x,y,z]...] and "uvs" [[u,v]...]: a mesh that
  // lives in the scene document itself (what glint.Scene.add_mesh writes),
  // with the rules of a mesh file (mesh_from_arrays) and every problem named
  // by its path in the document.
  uint32_t inline_mesh(const Value& v, const Path& path, bool smooth) {
    for (size_t k = 0; k < v.size(); ++k)
      if (v.key(k) == "file")
        throw Error(v.key_location(k), join(path, "file").str(),
                    "give either \"file\" or inline \"vertices\" and \"triangles\", not both");
    const Value verts = require(v, path, "vertices");
    const Path vp = join(path, "vertices");
    expect_array(verts, vp);
    const Value tris = require(v, path, "triangles");
    const Path tp = join(path, "triangles");
    expect_array(tris, tp);
    if (verts.size() > UINT32_MAX) fail(verts, vp, "more than 2^32 - 1 vertices");
    count_inline_mesh(v, path, verts.size(), tris.size());
    std::vector<Vec3f> positions(verts.size());
    for (size_t i = 0; i < verts.size(); ++i) positions[i] = float_vec3(verts[i], index(vp, i));
    std::vector<uint32_t> indices(3 * tris.size());
    for (size_t t = 0; t < tris.size(); ++t) {
      const Value tri = tris[t];
      const Path p = index(tp, t);
      if (!tri.is_array() || tri.size() != 3)
        fail(tri, p, std::string("expected [i, j, k] (three vertex indices), got ") +
                         (tri.is_array() ? "an array of " + std::to_string(tri.size()) : std::string(tri.kind_name())));
      for (size_t k = 0; k < 3; ++k) {
        const Path ip = index(p, k);
        const double x = number(tri[k], ip);
        if (!tri[k].is_integer() || x != std::floor(x)) fail(tri[k], ip, "expected a whole number, got " + format_number(x));
        if (!(x >= 0 && x < double(verts.size())))
          fail(tri[k], ip, "vertex index " + format_number(x) + " out of range (" + std::to_string(verts.size()) +
                               (verts.size() == 1 ? " vertex)" : " vertices)"));
        indices[3 * t + k] = static_cast<uint32_t>(x);
      }
    }
    auto per_vertex = [&](std::string_view key) -> std::optional<Value> {
      const auto a = v.find(key);
      if (!a) return std::nullopt;
      const Path ap = join(path, key);
      expect_array(*a, ap);
      if (a->size() != verts.size())
        fail(*a, ap, "expected one per vertex (" + std::to_string(verts.size()) + "), got " + std::to_string(a->size()));
      return a;
    };
    std::vector<Vec3f> normals;
    if (auto n = per_vertex("normals")) {
      normals.resize(n->size());
      for (size_t i = 0; i < n->size(); ++i) normals[i] = float_vec3((*n)[i], index(join(path, "normals"), i));
    }
    std::vector<UVf> uvs;
    if (auto u = per_vertex("uvs")) {
      uvs.resize(u->size());
      for (size_t i = 0; i < u->size(); ++i) {
        const Path up = index(join(path, "uvs"), i);
        const std::array<double, 2> c = pair((*u)[i], up);
        uvs[i] = {static_cast<float>(c[0]), static_cast<float>(c[1])};
        if (!std::isfinite(uvs[i].u) || !std::isfinite(uvs[i].v)) fail((*u)[i], up, "does not fit in a 32-bit float");
      }
    }
    return add_mesh_from_arrays(v, path, std::move(positions), std::move(indices), normals, uvs, smooth);
  }

  // Counted with the mesh files: all of them, with their BVHs, must fit.
  void count_inline_mesh(const Value& v, const Path& path, size_t vertices, size_t triangles) {
    mesh_vertices_ += vertices;
    mesh_triangles_ += triangles;
    const std::string excess = exceeds_budget(
        kBytesPerVertex * double(mesh_vertices_) + kBytesPerTriangle * double(mesh_triangles_), memory_budget_);
    if (!excess.empty())
      fail(v, path, "with this mesh the scene's meshes hold " + std::to_string(mesh_triangles_) + " triangles: that " +
                        excess);
  }

  // The rules of a mesh file (mesh_from_arrays) applied to an inline or
  // attached mesh, which becomes one of the scene's meshes.
  uint32_t add_mesh_from_arrays(const Value& v, const Path& path, std::vector<Vec3f> positions,
                                std::vector<uint32_t> indices, const std::vector<Vec3f>& normals,
                                const std::vector<UVf>& uvs, bool smooth) {
    MeshFile built;
    try {
      built = mesh_from_arrays(std::move(positions), std::move(indices), normals, uvs, path.str(), smooth);
    } catch (const Error& e) {
      fail(v, path, e.message());  // "no triangles (all 2 are degenerate)"
    }
    for (std::string& w : built.warnings) scene_.warnings.push_back(std::move(w));
    Mesh mesh;
    mesh.file = path.str();  // no file: the object's path names it (geometry keys, messages)
    mesh.positions = std::move(built.positions);
    mesh.indices = std::move(built.indices);
    mesh.corner_normals = std::move(built.corner_normals);
    mesh.corner_uvs = std::move(built.corner_uvs);
    mesh.triangle_material.assign(mesh.triangle_count(), 0);  // the default material, as a file without one
    return add_mesh(scene_, std::move(mesh));
  }

  // A mesh whose arrays the API holds in memory (AttachedMeshes): read
  // straight from them, with no JSON between. They were checked when added
  // (sizes, index range, finite floats); mesh_from_arrays checks again.
  uint32_t attached_mesh(const Value& v, const Path& path, bool smooth) {
    for (size_t k = 0; k < v.size(); ++k)
      for (std::string_view other : {"file", "vertices", "triangles", "normals", "uvs"})
        if (v.key(k) == other)
          throw Error(v.key_location(k), join(path, other).str(),
                      other == "file" ? "give either \"file\" or inline \"vertices\" and \"triangles\", not both"
                                      : "this mesh's arrays are set as a whole (they are held in memory)");
    const Value id = *v.find(kAttachedMeshKey);
    const Path ip = join(path, kAttachedMeshKey);
    const double x = number(id, ip);
    const auto it = id.is_integer() && x >= 0 ? attached_->find(static_cast<uint64_t>(x)) : attached_->end();
    if (it == attached_->end()) fail(id, ip, "no mesh arrays with this id");
    const api::MeshArrays& a = *it->second;
    const size_t n = a.positions.size() / 3;
    count_inline_mesh(v, path, n, a.triangles.size() / 3);
    std::vector<Vec3f> positions(n);
    for (size_t i = 0; i < n; ++i) positions[i] = {a.positions[3 * i], a.positions[3 * i + 1], a.positions[3 * i + 2]};
    std::vector<Vec3f> normals(a.normals.size() / 3);
    for (size_t i = 0; i < normals.size(); ++i) normals[i] = {a.normals[3 * i], a.normals[3 * i + 1], a.normals[3 * i + 2]};
    std::vector<UVf> uvs(a.uvs.size() / 2);
    for (size_t i = 0; i < uvs.size(); ++i) uvs[i] = {a.uvs[2 * i], a.uvs[2 * i + 1]};
    return add_mesh_from_arrays(v, path, std::move(positions), a.triangles, normals, uvs, smooth);
  }

  // [x, y, z] stored as floats (meshes are): each component must fit.
  Vec3f float_vec3(const Value& v, const Path& path) const {
    const Vec3f f = to_vec3f(vec3(v, path));
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z))
      fail(v, path, "does not fit in a 32-bit float");
    return f;
  }

  uint32_t material_ref(const Value& v, const Path& path) const {
    const std::string name = string(v, path);
    auto it = material_index_.find(name);
    if (it != material_index_.end()) return it->second;
    Keys names;
    for (const auto& [n, _] : material_index_) names.push_back(n);
    std::string msg = "unknown material " + quote_text(name);
    const std::string hint = closest_match(name, names);
    if (!hint.empty()) msg += " (did you mean \"" + hint + "\"?)";
    else if (names.empty()) msg += " (the scene defines no materials)";
    fail(v, path, msg);
  }

  void read_object(const Value& v, const Path& path) {
    expect_object(v, path);
    static const Keys types = {"sphere", "plane", "triangle", "box", "mesh", "cylinder", "cone", "disk", "polygon"};
    const Value type_value = require(v, path, "type");
    const size_t type = choice(type_value, join(path, "type"), types, "object type");
    Keys allowed = {"type", "material", "transform", "name"};
    switch (type) {
      case 0: allowed.insert(allowed.end(), {"center", "radius"}); break;
      case 1: allowed.insert(allowed.end(), {"point", "normal"}); break;
      case 2: allowed.insert(allowed.end(), {"vertices", "uv"}); break;
      case 3: allowed.insert(allowed.end(), {"min", "max"}); break;
      case 4:
        allowed.insert(allowed.end(), {"file", "smooth", "vertices", "triangles", "normals", "uvs"});
        if (attached_) allowed.push_back(kAttachedMeshKey);
        break;
      case 5: allowed.insert(allowed.end(), {"base", "apex", "radius", "caps"}); break;
      case 6: allowed.insert(allowed.end(), {"base", "apex", "base_radius", "apex_radius", "caps"}); break;
      case 7: allowed.insert(allowed.end(), {"center", "normal", "radius", "inner_radius"}); break;
      case 8: allowed.insert(allowed.end(), {"vertices", "normals"}); break;
    }
    check_keys(v, path, allowed);
    uint32_t material = 0;
    if (auto m = v.find("material")) material = material_ref(*m, join(path, "material"));
    std::optional<Transform> transform;
    if (auto t = v.find("transform")) transform = read_transform(*t, join(path, "transform"));

    uint32_t object = 0;
    switch (type) {
      case 0: {
        Sphere s;
        s.center = vec3(require(v, path, "center"), join(path, "center"));
        s.radius = positive(require(v, path, "radius"), join(path, "radius"));
        object = add_sphere(scene_, s, material, transform);
        break;
      }
      case 1: {
        Plane p;
        p.point = vec3(require(v, path, "point"), join(path, "point"));
        p.normal = direction(require(v, path, "normal"), join(path, "normal"));
        object = add_plane(scene_, p, material, transform);
        break;
      }
      case 2: {
        const Value verts = require(v, path, "vertices");
        const Path p = join(path, "vertices");
        if (!verts.is_array() || verts.size() != 3) fail(verts, p, "expected three vertices [[x,y,z], [x,y,z], [x,y,z]]");
        Triangle t{vec3(verts[0], index(p, 0)), vec3(verts[1], index(p, 1)), vec3(verts[2], index(p, 2))};
        if (!(length(cross(t.v1 - t.v0, t.v2 - t.v0)) > 0)) fail(verts, p, "degenerate triangle (zero area)");
        object = add_triangle(scene_, t, material, transform);
        const Triangle& w = scene_.triangles.back();
        if (!(length(cross(w.v1 - w.v0, w.v2 - w.v0)) > 0)) fail(verts, p, "degenerate triangle after its transform");
        if (auto uv = v.find("uv")) {
          const Path up = join(path, "uv");
          if (!uv->is_array() || uv->size() != 3) fail(*uv, up, "expected three [u, v] pairs, one per vertex");
          std::array<UV, 3> uvs;
          for (size_t k = 0; k < 3; ++k) {
            const std::array<double, 2> c = pair((*uv)[k], index(up, k));
            uvs[k] = {c[0], c[1]};
          }
          scene_.triangle_uvs[scene_.objects[object].shape] = uvs;
        }
        break;
      }
      case 3: {
        Box b;
        b.lo = vec3(require(v, path, "min"), join(path, "min"));
        const Value max_value = require(v, path, "max");
        b.hi = vec3(max_value, join(path, "max"));
        if (!(b.hi.x > b.lo.x && b.hi.y > b.lo.y && b.hi.z > b.lo.z))
          fail(max_value, join(path, "max"), "must be greater than \"min\" on every axis (a box needs a positive size)");
        object = add_box(scene_, b, material, transform);
        break;
      }
      case 4: {
        bool smooth = true;
        if (auto x = v.find("smooth")) smooth = boolean(*x, join(path, "smooth"));
        uint32_t mesh = 0;
        if (attached_ && v.find(kAttachedMeshKey)) {
          mesh = attached_mesh(v, path, smooth);
        } else if (v.find("vertices") || v.find("triangles")) {
          mesh = inline_mesh(v, path, smooth);
        } else {
          const Value file = require(v, path, "file");
          mesh = load_mesh(file, join(path, "file"));
        }
        object = add_mesh_object(scene_, mesh, v.find("material") ? material : kMeshMaterials, smooth, transform);
        break;
      }
      case 5:
      case 6:
        object = read_cone(v, path, type == 5, material, transform);
        break;
      case 7: {
        Disk d;
        d.center = vec3(require(v, path, "center"), join(path, "center"));
        d.normal = direction(require(v, path, "normal"), join(path, "normal"));
        d.radius = positive(require(v, path, "radius"), join(path, "radius"));
        if (auto x = v.find("inner_radius")) {
          d.inner_radius = non_negative(*x, join(path, "inner_radius"));
          if (!(d.inner_radius < d.radius))
            fail(*x, join(path, "inner_radius"),
                 "must be less than \"radius\" (" + format_number(d.radius) + "; got " + format_number(d.inner_radius) + ")");
        }
        object = add_disk(scene_, d, material, transform);
        break;
      }
      case 8:
        object = read_polygon(v, path, material, transform);
        break;
    }
    if (auto n = v.find("name")) scene_.object_names[object] = string(*n, join(path, "name"));
  }

  // A cylinder (base, apex, radius) or a cone (base, apex, base_radius, apex_radius).
  uint32_t read_cone(const Value& v, const Path& path, bool cylinder, uint32_t material,
                     const std::optional<Transform>& transform) {
    const Vec3 base = vec3(require(v, path, "base"), join(path, "base"));
    const Value apex_value = require(v, path, "apex");
    const Vec3 apex = vec3(apex_value, join(path, "apex"));
    if (apex == base) fail(apex_value, join(path, "apex"), "must differ from \"base\" (the axis needs a length)");
    if (!std::isfinite(length(apex - base)))
      fail(apex_value, join(path, "apex"), "too far from \"base\" (the axis length overflows)");
    double r0 = 0, r1 = 0;
    if (cylinder) {
      r0 = r1 = positive(require(v, path, "radius"), join(path, "radius"));
    } else {
      r0 = non_negative(require(v, path, "base_radius"), join(path, "base_radius"));
      const Value r1_value = require(v, path, "apex_radius");
      r1 = non_negative(r1_value, join(path, "apex_radius"));
      if (r0 == 0 && r1 == 0)
        fail(r1_value, join(path, "apex_radius"), "\"base_radius\" and \"apex_radius\" cannot both be 0");
    }
    bool caps = true;
    if (auto x = v.find("caps")) caps = boolean(*x, join(path, "caps"));
    return add_cone(scene_, make_cone(base, apex, r0, r1, caps), material, transform, cylinder);
  }

  // A polygon: checked and triangulated by make_polygon (geometry/polygon.h).
  uint32_t read_polygon(const Value& v, const Path& path, uint32_t material, const std::optional<Transform>& transform) {
    const Value verts = require(v, path, "vertices");
    const Path vp = join(path, "vertices");
    if (!verts.is_array()) fail(verts, vp, std::string("expected an array of [x, y, z] vertices, got ") + verts.kind_name());
    std::vector<Vec3> vertices;
    vertices.reserve(verts.size());
    for (size_t i = 0; i < verts.size(); ++i) vertices.push_back(vec3(verts[i], index(vp, i)));
    std::vector<Vec3> normals;
    const auto normals_value = v.find("normals");
    const Path np = join(path, "normals");
    if (normals_value) {
      if (!normals_value->is_array())
        fail(*normals_value, np, std::string("expected an array of [x, y, z] normals, got ") + normals_value->kind_name());
      if (normals_value->size() != verts.size())
        fail(*normals_value, np, "expected one normal per vertex (" + std::to_string(verts.size()) + "), got " +
                                     std::to_string(normals_value->size()));
      normals.reserve(normals_value->size());
      for (size_t i = 0; i < normals_value->size(); ++i) normals.push_back(direction((*normals_value)[i], index(np, i)));
    }
    PolygonBuild built = make_polygon(std::move(vertices), std::move(normals));
    if (!built.error.empty()) {
      if (built.error_at_normals) fail(*normals_value, np, built.error);
      fail(verts, vp, built.error);
    }
    return add_polygon(scene_, std::move(built.polygon), material, transform);
  }

  // --- animation (a glint addition, docs/scene-format.md) ----------------
  void read_animation(const Value& a, const std::optional<Value>& objects) {
    const Path path("animation");
    expect_object(a, path);
    check_keys(a, path, {"frames", "fps", "keys"});
    Animation anim;
    anim.frames = integer(require(a, path, "frames"), join(path, "frames"), 1, kMaxFrames);
    if (auto f = a.find("fps")) anim.fps = positive(*f, join(path, "fps"));
    const Value keys = require(a, path, "keys");
    const Path keys_path = join(path, "keys");
    expect_array(keys, keys_path);
    if (keys.size() == 0) fail(keys, keys_path, "needs at least one key");
    std::map<std::string, size_t, std::less<>> tracks_of;  // object name -> anim.objects
    double previous = 0;
    for (size_t i = 0; i < keys.size(); ++i) {
      const Path kp = index(keys_path, i);
      const Value k = keys[i];
      expect_object(k, kp);
      check_keys(k, kp, {"time", "camera", "objects"});
      const Value tv = require(k, kp, "time");
      const double time = non_negative(tv, join(kp, "time"));
      if (i > 0 && !(time > previous))
        fail(tv, join(kp, "time"), "key times must increase (the previous key is at " + format_number(previous) + ")");
      previous = time;
      if (auto c = k.find("camera")) read_camera_key(*c, join(kp, "camera"), time, anim.camera);
      if (auto o = k.find("objects")) {
        const Path op = join(kp, "objects");
        expect_object(*o, op);
        for (size_t m = 0; m < o->size(); ++m) {
          const std::string_view name = o->key(m);
          auto it = tracks_of.find(name);
          if (it == tracks_of.end()) {
            ObjectTracks tracks;
            if (!find_animated_object(*o, m, op, objects, tracks)) continue;  // that object failed to load
            anim.objects.push_back(std::move(tracks));
            it = tracks_of.emplace(std::string(name), anim.objects.size() - 1).first;
          }
          read_object_key(o->member(m), Path(op, name), time, anim.objects[it->second]);
        }
      }
    }
    scene_.animation = std::move(anim);
    if (const std::string what = check_animation(scene_); !what.empty()) fail(a, path, what);
  }

  void read_camera_key(const Value& c, const Path& path, double time, CameraTracks& tracks) const {
    expect_object(c, path);
    check_keys(c, path, {"position", "look_at", "up", "fov_y"});
    if (auto v = c.find("position")) tracks.position.push_back({time, vec3(*v, join(path, "position"))});
    if (auto v = c.find("look_at")) tracks.look_at.push_back({time, vec3(*v, join(path, "look_at"))});
    if (auto v = c.find("up")) tracks.up.push_back({time, direction(*v, join(path, "up"))});
    if (auto v = c.find("fov_y")) {
      const double fov = number(*v, join(path, "fov_y"));
      if (!(fov > 0 && fov < 180))
        fail(*v, join(path, "fov_y"), "must be between 0 and 180 degrees, exclusive (got " + format_number(fov) + ")");
      tracks.fov_y.push_back({time, fov});
    }
  }

  Vec3 scale_factors(const Value& s, const Path& p) const {
    const Vec3 f = s.is_number() ? Vec3(number(s, p)) : vec3(s, p);
    if (f.x == 0 || f.y == 0 || f.z == 0) fail(s, p, "a zero scale makes the transform singular");
    return f;
  }
  Rotation rotation(const Value& r, const Path& p) const {
    expect_object(r, p);
    check_keys(r, p, {"axis", "angle"});
    Rotation rot;
    rot.axis = direction(require(r, p, "axis"), join(p, "axis"));
    rot.degrees = number(require(r, p, "angle"), join(p, "angle"));
    rot.q = quat_from_axis_angle(rot.axis, rot.degrees);
    return rot;
  }

  void read_object_key(const Value& v, const Path& path, double time, ObjectTracks& tracks) const {
    expect_object(v, path);
    check_keys(v, path, {"scale", "rotate", "translate"});
    if (auto s = v.find("scale")) tracks.scale.push_back({time, scale_factors(*s, join(path, "scale"))});
    if (auto r = v.find("rotate")) tracks.rotate.push_back({time, rotation(*r, join(path, "rotate"))});
    if (auto t = v.find("translate")) tracks.translate.push_back({time, vec3(*t, join(path, "translate"))});
  }

  // The object named by member m of a key's "objects": its index, static
  // transform and object-space geometry. False when that object did not load
  // (validate goes on without it).
  bool find_animated_object(const Value& keyed, size_t m, const Path& path, const std::optional<Value>& objects,
                            ObjectTracks& tracks) const {
    const std::string_view name = keyed.key(m);
    std::vector<size_t> named;
    Keys all_names;
    for (size_t j = 0; objects && objects->is_array() && j < objects->size(); ++j) {
      const Value o = (*objects)[j];
      const auto n = o.is_object() ? o.find("name") : std::nullopt;
      if (!n || !n->is_string()) continue;
      all_names.push_back(n->as_string());
      if (n->as_string() == name) named.push_back(j);
    }
    auto fail_name = [&](const std::string& what) {
      throw Error(keyed.key_location(m), Path(path, name).str(), what);
    };
    if (named.empty()) {
      std::string what = "unknown object " + quote_text(name);
      const std::string hint = closest_match(name, all_names);
      fail_name(what + (hint.empty() ? " (no object has this \"name\")" : " (did you mean \"" + hint + "\"?)"));
    }
    if (named.size() > 1)
      fail_name(std::to_string(named.size()) + " objects are named " + quote_text(name) +
                "; an animated object needs a name of its own");
    const auto it = std::find(object_json_index_.begin(), object_json_index_.end(), named[0]);
    if (it == object_json_index_.end()) return false;
    tracks.object = static_cast<uint32_t>(it - object_json_index_.begin());
    const Value o = (*objects)[named[0]];
    const Path op = index("objects", named[0]);
    if (auto t = o.find("transform")) {
      if (t->find("matrix"))
        fail_name("object " + quote_text(name) + " has a \"matrix\" transform, which cannot be animated "
                  "(write it as scale, rotate and translate)");
      const Path tp = join(op, "transform");
      if (auto s = t->find("scale")) {
        tracks.has_scale = true;
        tracks.scale0 = scale_factors(*s, join(tp, "scale"));
      }
      if (auto r = t->find("rotate")) {
        tracks.has_rotate = true;
        tracks.rotate0 = rotation(*r, join(tp, "rotate"));
      }
      if (auto tr = t->find("translate")) {
        tracks.has_translate = true;
        tracks.translate0 = vec3(*tr, join(tp, "translate"));
      }
    }
    const ShapeType type = scene_.objects[tracks.object].type;
    if (type == ShapeType::plane) {
      tracks.object_space[0] = vec3(require(o, op, "point"), join(op, "point"));
      tracks.object_space[1] = direction(require(o, op, "normal"), join(op, "normal"));
    } else if (type == ShapeType::triangle) {
      const Value verts = require(o, op, "vertices");
      for (size_t i = 0; i < 3; ++i) tracks.object_space[i] = vec3(verts[i], index(join(op, "vertices"), i));
    }
    return true;
  }

  const json::Document& doc_;
  std::filesystem::path base_dir_;
  const AttachedMeshes* attached_ = nullptr;
  std::vector<Error>* errors_ = nullptr;
  std::map<std::string, uint32_t> mesh_index_;  // canonical path -> Scene::meshes
  std::set<std::string> smooth_mesh_files_;      // canonical paths some object shades smoothly
  std::map<std::string, uint32_t> texture_image_index_;  // canonical path -> Scene::texture_images
  size_t memory_budget_;
  FileCache* files_;  // or nullptr: read every file
  size_t mesh_vertices_ = 0, mesh_triangles_ = 0;  // of every mesh file loaded
  Scene scene_;
  std::map<std::string, uint32_t, std::less<>> material_index_;
  std::vector<size_t> object_json_index_;  // Scene::objects -> index in the "objects" array
};

}  // namespace

std::string closest_match(std::string_view word, const std::vector<std::string_view>& candidates) {
  std::string best;
  // A plausible typo: at most one edit per three letters (two for short
  // words), and fewer edits than the word has letters ("zz" is no "a").
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (std::string_view c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_distance && d < word.size()) {
      best_distance = d;
      best = std::string(c);
    }
  }
  return best;
}

void check_image_size(int width, int height, const SourceLocation& where) {
  // The film holds 3 floats per pixel; refuse what this machine cannot hold
  // rather than let the allocation fail (or the OOM killer strike) mid-render.
  const std::string excess = exceeds_budget(12.0 * width * height, default_memory_budget());
  if (!excess.empty())
    throw Error(where, "image of " + std::to_string(width) + "x" + std::to_string(height) + " pixels " + excess);
}

Scene parse_scene(std::string text, const std::string& filename, const std::filesystem::path& base_dir,
                  size_t memory_budget, const AttachedMeshes* attached, FileCache* files) {
  const json::Document doc = json::parse(std::move(text), filename);
  try {
    return SceneReader(doc, base_dir, memory_budget, attached, files).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{filename, 0, 0}, "out of memory while loading the scene");
  }
}

Scene read_scene_document(const json::Document& doc, const std::filesystem::path& base_dir, size_t memory_budget) {
  try {
    return SceneReader(doc, base_dir, memory_budget).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{doc.filename(), 0, 0}, "out of memory while loading the scene");
  }
}

std::vector<Error> validate_scene_document(const json::Document& doc, const std::filesystem::path& base_dir) {
  std::vector<Error> errors;
  try {
    SceneReader(doc, base_dir).read(&errors);
  } catch (const Error& e) {
    errors.push_back(e);
  } catch (const std::bad_alloc&) {
    errors.push_back(Error(SourceLocation{doc.filename(), 0, 0}, "out of memory while loading the scene"));
  }
  return errors;
}

std::vector<Error> validate_scene(const std::filesystem::path& path) {
  if (is_nff_path(path)) return validate_nff_scene(path);
  std::vector<Error> errors;
  try {
    const json::Document doc = json::parse_file(path.string());
    SceneReader(doc, path.parent_path()).read(&errors);
  } catch (const Error& e) {
    errors.push_back(e);  // unreadable or not JSON: nothing more can be checked
  } catch (const std::bad_alloc&) {
    errors.push_back(Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene"));
  }
  return errors;
}

Scene load_scene(const std::filesystem::path& path, FileCache* files) {
  if (is_nff_path(path)) return load_nff_scene(path);  // an NFF names no other file
  // A bare mesh file is framed by a fixed rig (io/mesh_scene.h).
  if (is_mesh_file(path))
    return parse_scene(mesh_scene_json(path), path.string(), path.parent_path(), default_memory_budget(), nullptr, files);
  const json::Document doc = json::parse_file(path.string());
  try {
    return SceneReader(doc, path.parent_path(), default_memory_budget(), nullptr, files).read();
  } catch (const std::bad_alloc&) {
    throw Error(SourceLocation{path.string(), 0, 0}, "out of memory while loading the scene");
  }
}

}  // namespace glint
