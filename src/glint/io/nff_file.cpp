#include "glint/io/nff_file.h"

// GCC 12 warns falsely about std::string concatenation at -O3 (GCC bug 105329).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic ignored "-Wrestrict"
#endif

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <optional>

#include "glint/io/file_io.h"
#include "glint/io/json.h"
#include "glint/io/scene_loader.h"
#include "glint/math/vec3.h"
#include "glint/scene/scene.h"

namespace glint {

namespace {

// The most vertices one `p` or `pp` may announce; a count beyond it is an
// error before anything is read (the file would need gigabytes anyway).
constexpr long long kMaxPolygonVertices = 1 << 24;
// render.width / height: the JSON loader's range.
constexpr long long kMaxResolution = 1 << 20;

struct Token {
  std::string_view text;
  int line = 0, column = 0;
};

int clamp_to_int(size_t n) { return n > static_cast<size_t>(INT_MAX) ? INT_MAX : static_cast<int>(n); }

// Text from the file as it appears in a message: one line, short, ASCII.
std::string printable(std::string_view s) {
  constexpr size_t kMaxShown = 40;
  std::string out;
  for (size_t i = 0; i < s.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  if (s.size() > kMaxShown) out += "...";
  return out;
}
std::string quoted(std::string_view s) { return "\"" + printable(s) + "\""; }

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// A token that is meant as a number (so a malformed one is reported as a
// bad number, not as an unknown entity).
bool looks_numeric(std::string_view s) {
  return !s.empty() && (std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '-' || s[0] == '+' || s[0] == '.');
}

// Splits the text into white-space separated tokens, remembering where each
// starts. Line breaks are white space like any other (an entity's numbers
// may go on over several lines); '#' at the start of a token comments out
// the rest of its line. Lines and columns count as in glint's JSON reader:
// 1-based, columns in bytes, a leading UTF-8 byte-order mark not counted.
class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = line_start_ = 3;
  }

  const std::optional<Token>& peek() {
    if (!peeked_) peeked_ = scan();
    return *peeked_;
  }
  std::optional<Token> next() {
    std::optional<Token> t = peek();
    peeked_.reset();
    return t;
  }
  // Where the file ends (after the last token: call when next() gave nothing).
  Token end() const { return {{}, clamp_to_int(line_), clamp_to_int(pos_ - line_start_ + 1)}; }

 private:
  std::optional<Token> scan() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++pos_;
        ++line_;
        line_start_ = pos_;
      } else if (is_space(c)) {
        ++pos_;
      } else if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        const size_t start = pos_;
        while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
        return Token{text_.substr(start, pos_ - start), clamp_to_int(line_), clamp_to_int(start - line_start_ + 1)};
      }
    }
    return std::nullopt;
  }

  std::string_view text_;
  size_t pos_ = 0, line_start_ = 0, line_ = 1;
  std::optional<std::optional<Token>> peeked_;
};

// d / |d| without overflow or underflow of the length, or nullopt for a zero
// or non-finite d (the JSON loader's rule).
std::optional<Vec3> unit(const Vec3& d) {
  const double big = max_abs_component(d);
  if (!(big > 0) || !std::isfinite(big)) return std::nullopt;
  const Vec3 s = d / big;
  return s / length(s);
}

// --- the file as read: plain parts, before any JSON ----------------------------
// Both documents (nlohmann's for convert and the API, the loader's built in
// memory) are written from these, so they cannot differ.

struct Where {
  int line = 0, column = 0;
};
Where where(const Token& t) { return {t.line, t.column}; }

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
  bool normals = false;      // polygon: `pp`
  uint32_t material = 0;     // 0: none (before the first `f`), else materials[material - 1]
  uint32_t first = 0;        // its numbers start at Parts::numbers[first]:
  uint32_t vertices = 0;     //   sphere: center, radius; cylinder: base, apex, radius;
  Where at;                  //   cone: base, apex, base radius, apex radius;
};                           //   polygon: `vertices` points, then as many normals for `pp`

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

const char* entity_of(const Object& o) {
  switch (o.shape) {
    case Shape::sphere: return "s";
    case Shape::cylinder:
    case Shape::cone: return "c";
    case Shape::polygon: return o.normals ? "pp" : "p";
  }
  return "";
}

// One NFF file, read entity by entity into Parts.
class NffReader {
 public:
  NffReader(std::string_view text, std::string filename) : lex_(text) {
    parts_.filename = std::move(filename);
    // About one object per 40 bytes (an SPD sphere line is 40-50).
    parts_.objects.reserve(text.size() / 40);
    parts_.numbers.reserve(text.size() / 10);
  }

  Parts read() {
    while (const std::optional<Token> t = lex_.next()) {
      const std::string_view kw = t->text;
      if (kw == "v") read_view(*t);
      else if (kw == "b") read_background(*t);
      else if (kw == "l") read_light(*t);
      else if (kw == "f") read_material(*t);
      else if (kw == "s") read_sphere(*t);
      else if (kw == "c") read_cone(*t);
      else if (kw == "p" || kw == "pp") read_polygon(*t, kw == "pp");
      else if (looks_numeric(kw))
        fail(*t, "expected an entity (v, b, l, f, c, s, p or pp), got the number " + quoted(kw) +
                     " (more numbers than the entity before it takes?)");
      else
        fail(*t, "unknown entity " + quoted(kw) + " (expected v, b, l, f, c, s, p or pp)");
    }
    if (!has_view_) fail(lex_.end(), "no view: an NFF file needs a \"v\" entity (the camera)");
    return std::move(parts_);
  }

 private:
  [[noreturn]] void fail(const Token& at, const std::string& what) const {
    throw Error(SourceLocation{parts_.filename, at.line, at.column}, what);
  }

  // The next token of `entity` (its keyword token), which must exist.
  Token operand(const Token& entity, const char* what) {
    std::optional<Token> t = lex_.next();
    if (!t) fail(entity, std::string(entity.text) + ": the file ends before its " + what);
    return *t;
  }

  // The next token as a finite number; `what` names it for messages. The
  // names are built only for a message: this runs for every number.
  double number(const Token& entity, const char* what, const char* suffix = "", Token* at = nullptr) {
    std::optional<Token> next = lex_.next();
    if (!next) fail(entity, std::string(entity.text) + ": the file ends before its " + what + suffix);
    const Token& t = *next;
    if (at) *at = t;
    std::string_view s = t.text;
    // C's %g never writes a leading '+', but a person might; from_chars takes none.
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec == std::errc() && end == s.data() + s.size() && std::isfinite(value)) return value;
    const std::string prefix = std::string(entity.text) + ": ";
    const std::string name = std::string(what) + suffix;
    if (ec == std::errc::result_out_of_range)
      fail(t, prefix + name + ": the number " + quoted(t.text) + " is out of range");
    if (ec != std::errc() || end != s.data() + s.size())
      fail(t, prefix + "expected a number (" + name + "), got " + quoted(t.text));
    fail(t, prefix + name + " must be a finite number, got " + quoted(t.text));
  }

  // Three numbers named "<what> x", "<what> y", "<what> z".
  Vec3 vec3(const Token& entity, const char* what) {
    Vec3 v;
    v.x = number(entity, what, " x");
    v.y = number(entity, what, " y");
    v.z = number(entity, what, " z");
    return v;
  }
  Vec3 color(const Token& entity, const char* what) {
    Vec3 c;
    c.x = number(entity, what, " red");
    c.y = number(entity, what, " green");
    c.z = number(entity, what, " blue");
    return c;
  }

  // The next token as a whole number in [lo, hi].
  long long whole(const Token& entity, const std::string& what, long long lo, long long hi) {
    const Token t = operand(entity, what.c_str());
    const std::string prefix = std::string(entity.text) + ": ";
    std::string_view s = t.text;
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);  // as number() takes it
    long long value = 0;
    const char* last = s.data() + s.size();
    const auto [end, ec] = std::from_chars(s.data(), last, value);
    if (ec == std::errc::result_out_of_range)
      fail(t, prefix + what + " " + quoted(t.text) + " is out of range (at most " + std::to_string(hi) + ")");
    if (ec != std::errc() || end != last)
      fail(t, prefix + "expected a whole number (" + what + "), got " + quoted(t.text));
    if (value < lo || value > hi)
      fail(t, prefix + what + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " +
                  std::to_string(value) + ")");
    return value;
  }

  // One of the view's named lines ("from 0 0 1"): its keyword.
  Token view_word(const Token& v, std::string_view name) {
    const Token t = operand(v, ("\"" + std::string(name) + "\" line").c_str());
    if (t.text != name) fail(t, "v: expected \"" + std::string(name) + "\", got " + quoted(t.text));
    return t;
  }

  // --- entities ----------------------------------------------------------
  void read_view(const Token& v) {
    if (has_view_) fail(v, "v: a second view (an NFF file has one \"v\")");
    has_view_ = true;
    const Token from_t = view_word(v, "from");
    const Vec3 from = vec3(v, "from");
    const Token at_t = view_word(v, "at");
    const Vec3 at = vec3(v, "at");
    const Token up_t = view_word(v, "up");
    const Vec3 up = vec3(v, "up");
    const Token angle_t = view_word(v, "angle");
    Token angle_value;
    const double angle = number(v, "angle", "", &angle_value);
    view_word(v, "hither");
    number(v, "hither");  // a near plane for scan converters: a ray tracer has none
    const Token resolution_t = view_word(v, "resolution");
    const auto width = static_cast<int>(whole(v, "resolution width", 1, kMaxResolution));
    const auto height = static_cast<int>(whole(v, "resolution height", 1, kMaxResolution));

    if (!(angle > 0 && angle < 180))
      fail(angle_value, "v: angle must be between 0 and 180 degrees, exclusive (got " + printable(angle_value.text) + ")");
    if (at == from) fail(at_t, "v: \"at\" must differ from \"from\" (the view needs a direction)");
    const std::optional<Vec3> forward = unit(at - from);
    if (!forward) fail(at_t, "v: \"at\" is too far from \"from\" (the distance overflows)");
    const std::optional<Vec3> up_unit = unit(up);
    if (!up_unit) fail(up_t, "v: up must be a non-zero vector");
    if (!(length(cross(*forward, *up_unit)) > 1e-9)) fail(up_t, "v: up is parallel to the view direction");
    // Orthogonalized against the view direction, as the contract writes it;
    // the image is the same either way (the camera frame takes up's component
    // across the view only).
    View& view = parts_.view;
    view.from = from;
    view.at = at;
    view.up = normalize(*up_unit - dot(*up_unit, *forward) * *forward);
    view.angle = angle;
    view.fov_y = fov_y_for_row_center_angle(angle, height);
    view.width = width;
    view.height = height;
    view.v = where(v);
    view.from_t = where(from_t);
    view.at_t = where(at_t);
    view.up_t = where(up_t);
    view.angle_t = where(angle_t);
    view.resolution_t = where(resolution_t);
  }

  void read_background(const Token& b) {
    if (parts_.background_at) fail(b, "b: a second background (an NFF file has at most one \"b\")");
    parts_.background_at = where(b);
    parts_.background = color(b, "background");
  }

  void read_light(const Token& l) {
    Light light;
    light.at = where(l);
    light.position = vec3(l, "position");
    // The color is optional: numbers next mean it is there (an entity
    // starts with its keyword).
    if (const auto& next = lex_.peek(); next && looks_numeric(next->text)) light.color = color(l, "color");
    parts_.lights.push_back(light);
  }

  void read_material(const Token& f) {
    const Vec3 rgb = color(f, "color");
    const double kd = number(f, "Kd");
    const double ks = number(f, "Ks");
    const double shine = number(f, "Shine");
    const double t = number(f, "T");
    const double ior = number(f, "index of refraction");
    parts_.materials.push_back(Material{kd * rgb, ks, std::max(shine, 1.0), t, ior, where(f)});
    material_ = static_cast<uint32_t>(parts_.materials.size());
  }

  Object& add_object(Shape shape, const Token& at) {
    Object& o = parts_.objects.emplace_back();
    o.shape = shape;
    o.material = material_;
    o.first = static_cast<uint32_t>(parts_.numbers.size());
    o.at = where(at);
    return o;
  }
  void push(const Vec3& v) {
    parts_.numbers.push_back(v.x);
    parts_.numbers.push_back(v.y);
    parts_.numbers.push_back(v.z);
  }

  void read_sphere(const Token& s) {
    const Vec3 center = vec3(s, "center");
    const double r = number(s, "radius");
    // A negative radius means "seen from inside only"; glint's surfaces are two-sided.
    add_object(Shape::sphere, s);
    push(center);
    parts_.numbers.push_back(std::abs(r));
  }

  void read_cone(const Token& c) {
    const Vec3 base = vec3(c, "base");
    const double base_r = std::abs(number(c, "base radius"));
    const Vec3 apex = vec3(c, "apex");
    const double apex_r = std::abs(number(c, "apex radius"));
    add_object(base_r == apex_r ? Shape::cylinder : Shape::cone, c);
    push(base);
    push(apex);
    parts_.numbers.push_back(base_r);
    if (base_r != apex_r) parts_.numbers.push_back(apex_r);
  }

  void read_polygon(const Token& p, bool with_normals) {
    const long long n = whole(p, "vertex count", 3, kMaxPolygonVertices);
    // Read one by one: a huge count in a short file ends in an error at the
    // end of the file with nothing reserved for it.
    normals_.clear();
    const size_t first = parts_.numbers.size();
    for (long long i = 0; i < n; ++i) {
      const Vec3 v = vec3_of_vertex(p, i, n, "");
      push(v);
      if (with_normals) {
        const Vec3 normal = vec3_of_vertex(p, i, n, " normal");
        normals_.push_back(normal.x);
        normals_.push_back(normal.y);
        normals_.push_back(normal.z);
      }
    }
    parts_.numbers.insert(parts_.numbers.end(), normals_.begin(), normals_.end());
    Object& o = add_object(Shape::polygon, p);
    o.first = static_cast<uint32_t>(first);
    o.normals = with_normals;
    o.vertices = static_cast<uint32_t>(n);
  }

  // Vertex i (0-based) of n, or its normal: the names ("vertex 2 of 3 x")
  // are only built for a message.
  Vec3 vec3_of_vertex(const Token& p, long long i, long long n, const char* what) {
    Vec3 v;
    for (int axis = 0; axis < 3; ++axis) {
      const std::optional<Token>& next = lex_.peek();
      static constexpr const char* kAxis[] = {" x", " y", " z"};
      if (!next || !is_plain_number(next->text, v[axis])) {
        const std::string name =
            "vertex " + std::to_string(i + 1) + " of " + std::to_string(n) + what + kAxis[axis];
        v[axis] = number(p, name.c_str());  // fails with the message
      } else {
        lex_.next();
      }
    }
    return v;
  }

  // A token number() would take without a message: its value in `value`.
  static bool is_plain_number(std::string_view s, double& value) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    return ec == std::errc() && end == s.data() + s.size() && std::isfinite(value);
  }

  Lexer lex_;
  Parts parts_;
  bool has_view_ = false;
  uint32_t material_ = 0;  // the current `f` (1-based), 0 before the first
  std::vector<double> normals_;  // a `pp`'s normals while its vertices are read
};

// --- where each part of the document came from ----------------------------------

// The document's parts, in its order: render's and camera's members, the
// materials, the lights (the ambient one last), the objects.
enum class Section : uint8_t { none, render, camera, material, light, object };

constexpr const char* kRenderKeys[] = {"width", "height", "samples_per_pixel", "max_depth", "background"};
constexpr const char* kCameraKeys[] = {"position", "look_at", "up", "fov_y"};

std::string material_name(uint32_t k) { return "f" + std::to_string(k); }

// The document path of part `index` of `section` ("render.width",
// "materials.f2", "lights[0]", "objects[7]") and the NFF entity behind it.
std::pair<std::string, NffOrigin> origin_of(const Parts& parts, Section section, size_t index) {
  const View& v = parts.view;
  auto at = [&](const char* entity, Where w) {
    return NffOrigin{entity, SourceLocation{parts.filename, w.line, w.column}};
  };
  switch (section) {
    case Section::render: {
      const std::string path = std::string("render.") + kRenderKeys[index];
      if (index < 2) return {path, at("v: resolution", v.resolution_t)};
      if (index < 4) return {path, at("v", v.v)};
      return {path, parts.background_at ? at("b", *parts.background_at) : at("v", v.v)};
    }
    case Section::camera: {
      const std::string path = std::string("camera.") + kCameraKeys[index];
      const Where w[] = {v.from_t, v.at_t, v.up_t, v.angle_t};
      const char* entity[] = {"v: from", "v: at", "v: up", "v: angle"};
      return {path, at(entity[index], w[index])};
    }
    case Section::material:
      return {"materials." + material_name(static_cast<uint32_t>(index + 1)), at("f", parts.materials[index].at)};
    case Section::light:  // the ambient light, last, comes from the first `l`
      return {"lights[" + std::to_string(index) + "]", at("l", parts.lights[index < parts.lights.size() ? index : 0].at)};
    case Section::object:
      return {"objects[" + std::to_string(index) + "]", at(entity_of(parts.objects[index]), parts.objects[index].at)};
    case Section::none: break;
  }
  return {};
}

// The SPD's suggestion for lights of unstated intensity: sqrt(n)/(2n) each,
// and as much again for the ambient term.
double light_gray(const Parts& parts) {
  const double n = static_cast<double>(parts.lights.size());
  return std::sqrt(n) / (2.0 * n);
}

// `e`, an error of the JSON loader about the part at `path`, as the same
// problem at the NFF entity: "objects[3].radius: must be > 0" -> "s: radius: must be > 0".
Error at_entity(const std::string& path, const NffOrigin& origin, const Error& e) {
  std::string rest = e.message();
  if (rest.starts_with(path) && (rest.size() == path.size() || rest[path.size()] == '.' || rest[path.size()] == ':')) {
    rest.erase(0, path.size());
    if (rest.starts_with(": ")) rest.erase(0, 2);
    else if (rest.starts_with(".")) rest.erase(0, 1);
  }
  return Error(origin.where, origin.entity + ": " + rest);
}

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

Json object_json(const Parts& parts, const Object& o) {
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

Json material_json(const Material& m) {
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
      const Light& l = parts.lights[i];
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
    const Material& m = parts_.materials[i];
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
    const Light& l = parts_.lights[i];
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
    const Object& o = parts_.objects[i];
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
  Parts parts = NffReader(text, filename).read();
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
  return to_nff_scene(NffReader(text, filename).read());
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
