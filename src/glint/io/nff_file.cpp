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
#include "glint/math/vec3.h"
#include "glint/scene/scene.h"

namespace glint {

namespace {

using Json = nlohmann::ordered_json;

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

// d / |d| without overflow or underflow of the length, or nullopt for a zero
// or non-finite d (the JSON loader's rule).
std::optional<Vec3> unit(const Vec3& d) {
  const double big = max_abs_component(d);
  if (!(big > 0) || !std::isfinite(big)) return std::nullopt;
  const Vec3 s = d / big;
  return s / length(s);
}

struct Light {
  Vec3 position;
  std::optional<Vec3> color;
  Token at;
};

// One NFF file, read entity by entity into the parts of a glint scene.
class NffReader {
 public:
  NffReader(std::string_view text, std::string filename) : lex_(text) {
    scene_.filename = std::move(filename);
    // About one object per 40 bytes (an SPD sphere line is 40-50): the
    // origins table and the object array grow without rehashing or copying.
    const size_t objects = text.size() / 40;
    scene_.origins.reserve(objects);
    objects_.get_ref<Json::array_t&>().reserve(objects);
  }

  NffScene read() {
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
    if (!view_) fail(lex_.end(), "no view: an NFF file needs a \"v\" entity (the camera)");
    assemble();
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const Token& at, const std::string& what) const {
    throw Error(SourceLocation{scene_.filename, at.line, at.column}, what);
  }

  // The next token of `entity` (its keyword token), which must exist.
  Token operand(const Token& entity, const std::string& what) {
    std::optional<Token> t = lex_.next();
    if (!t) fail(entity, std::string(entity.text) + ": the file ends before its " + what);
    return *t;
  }

  // The next token as a finite number; `what` names it for messages.
  double number(const Token& entity, const std::string& what, Token* where = nullptr) {
    const Token t = operand(entity, what);
    if (where) *where = t;
    const std::string prefix = std::string(entity.text) + ": ";
    std::string_view s = t.text;
    // C's %g never writes a leading '+', but a person might; from_chars takes none.
    if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
    double value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec == std::errc::result_out_of_range)
      fail(t, prefix + what + ": the number " + quoted(t.text) + " is out of range");
    if (ec != std::errc() || end != s.data() + s.size())
      fail(t, prefix + "expected a number (" + what + "), got " + quoted(t.text));
    if (!std::isfinite(value)) fail(t, prefix + what + " must be a finite number, got " + quoted(t.text));
    return value;
  }

  Vec3 vec3(const Token& entity, const std::string& what) {
    Vec3 v;
    v.x = number(entity, what + " x");
    v.y = number(entity, what + " y");
    v.z = number(entity, what + " z");
    return v;
  }
  Vec3 color(const Token& entity, const std::string& what) {
    Vec3 c;
    c.x = number(entity, what + " red");
    c.y = number(entity, what + " green");
    c.z = number(entity, what + " blue");
    return c;
  }

  // The next token as a whole number in [lo, hi].
  long long whole(const Token& entity, const std::string& what, long long lo, long long hi) {
    const Token t = operand(entity, what);
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
    const Token t = operand(v, "\"" + std::string(name) + "\" line");
    if (t.text != name) fail(t, "v: expected \"" + std::string(name) + "\", got " + quoted(t.text));
    return t;
  }

  void origin(const std::string& path, const std::string& entity, const Token& where) {
    scene_.origins.insert_or_assign(path, NffOrigin{entity, SourceLocation{scene_.filename, where.line, where.column}});
  }

  // --- entities ----------------------------------------------------------
  void read_view(const Token& v) {
    if (view_) fail(v, "v: a second view (an NFF file has one \"v\")");
    view_ = v;
    const Token from_t = view_word(v, "from");
    const Vec3 from = vec3(v, "from");
    const Token at_t = view_word(v, "at");
    const Vec3 at = vec3(v, "at");
    const Token up_t = view_word(v, "up");
    const Vec3 up = vec3(v, "up");
    const Token angle_t = view_word(v, "angle");
    Token angle_value;
    const double angle = number(v, "angle", &angle_value);
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
    const Vec3 up_ortho = normalize(*up_unit - dot(*up_unit, *forward) * *forward);

    scene_.angle = angle;
    Json& render = scene_.document["render"];
    render["width"] = width;
    render["height"] = height;
    render["samples_per_pixel"] = 1;
    render["max_depth"] = 5;
    origin("render.width", "v: resolution", resolution_t);
    origin("render.height", "v: resolution", resolution_t);
    origin("render.samples_per_pixel", "v", v);
    origin("render.max_depth", "v", v);
    Json& camera = scene_.document["camera"];
    camera["position"] = vec(from);
    camera["look_at"] = vec(at);
    camera["up"] = vec(up_ortho);
    camera["fov_y"] = fov_y_for_row_center_angle(angle, height);
    origin("camera.position", "v: from", from_t);
    origin("camera.look_at", "v: at", at_t);
    origin("camera.up", "v: up", up_t);
    origin("camera.fov_y", "v: angle", angle_t);
  }

  void read_background(const Token& b) {
    if (background_) fail(b, "b: a second background (an NFF file has at most one \"b\")");
    background_ = b;
    background_color_ = color(b, "background");
  }

  void read_light(const Token& l) {
    Light light;
    light.at = l;
    light.position = vec3(l, "position");
    // The color is optional: numbers next mean it is there (an entity
    // starts with its keyword).
    if (const auto& next = lex_.peek(); next && looks_numeric(next->text)) light.color = color(l, "color");
    lights_.push_back(light);
  }

  void read_material(const Token& f) {
    const Vec3 rgb = color(f, "color");
    const double kd = number(f, "Kd");
    const double ks = number(f, "Ks");
    const double shine = number(f, "Shine");
    const double t = number(f, "T");
    const double ior = number(f, "index of refraction");
    material_ = "f" + std::to_string(++material_count_);
    Json m;
    m["ambient"] = vec(kd * rgb);
    m["diffuse"] = vec(kd * rgb);
    m["specular"] = ks;
    m["shininess"] = std::max(shine, 1.0);
    m["reflectivity"] = ks;
    m["transparency"] = t;
    if (t > 0) {
      // A transmitting surface bends light and, with fresnel, reflects some:
      // the reflected ray the SPD statistics count for it.
      m["ior"] = ior;
      m["fresnel"] = true;
    }
    materials_[*material_] = std::move(m);
    origin("materials." + *material_, "f", f);
  }

  void add_object(Json object, const Token& at) {
    if (material_) object["material"] = *material_;
    origin("objects[" + std::to_string(objects_.size()) + "]", std::string(at.text), at);
    objects_.push_back(std::move(object));
  }

  void read_sphere(const Token& s) {
    const Vec3 center = vec3(s, "center");
    const double r = number(s, "radius");
    // A negative radius means "seen from inside only"; glint's surfaces are two-sided.
    Json object(Json::value_t::object);
    object["type"] = "sphere";
    object["center"] = vec(center);
    object["radius"] = std::abs(r);
    add_object(std::move(object), s);
  }

  void read_cone(const Token& c) {
    const Vec3 base = vec3(c, "base");
    const double base_r = std::abs(number(c, "base radius"));
    const Vec3 apex = vec3(c, "apex");
    const double apex_r = std::abs(number(c, "apex radius"));
    Json object;
    if (base_r == apex_r) {
      object = Json{{"type", "cylinder"}, {"base", vec(base)}, {"apex", vec(apex)}, {"radius", base_r}};
    } else {
      object = Json{{"type", "cone"}, {"base", vec(base)},           {"apex", vec(apex)},
                    {"base_radius", base_r}, {"apex_radius", apex_r}};
    }
    object["caps"] = false;  // NFF cones and cylinders are open
    add_object(std::move(object), c);
  }

  void read_polygon(const Token& p, bool with_normals) {
    const long long n = whole(p, "vertex count", 3, kMaxPolygonVertices);
    Json vertices = Json::array(), normals = Json::array();
    for (long long i = 0; i < n; ++i) {
      const std::string which = "vertex " + std::to_string(i + 1) + " of " + std::to_string(n);
      vertices.push_back(vec(vec3(p, which)));
      if (with_normals) normals.push_back(vec(vec3(p, which + " normal")));
    }
    Json object{{"type", "polygon"}, {"vertices", std::move(vertices)}};
    if (with_normals) object["normals"] = std::move(normals);
    add_object(std::move(object), p);
  }

  // The document in the contract's section order, once every light is
  // known (their intensity depends on how many there are).
  void assemble() {
    Json& doc = scene_.document;
    Json& render = doc["render"];
    render["background"] = vec(background_color_);
    origin("render.background", background_ ? "b" : "v", background_ ? *background_ : *view_);
    if (!materials_.empty()) doc["materials"] = std::move(materials_);
    if (!lights_.empty()) {
      // The SPD's suggestion for lights of unstated intensity: sqrt(n)/(2n)
      // each, and as much again for the ambient term.
      const double n = static_cast<double>(lights_.size());
      const double gray = std::sqrt(n) / (2.0 * n);
      Json lights = Json::array();
      for (size_t i = 0; i < lights_.size(); ++i) {
        const Light& l = lights_[i];
        const Json c = l.color ? vec(*l.color) : Json(gray);
        lights.push_back(Json{{"type", "point"}, {"position", vec(l.position)}, {"diffuse", c}, {"specular", c}});
        origin("lights[" + std::to_string(i) + "]", "l", l.at);
      }
      lights.push_back(Json{{"type", "ambient"}, {"ambient", gray}});
      origin("lights[" + std::to_string(lights_.size()) + "]", "l", lights_.front().at);
      doc["lights"] = std::move(lights);
    }
    doc["objects"] = std::move(objects_);
  }

  Lexer lex_;
  NffScene scene_;
  std::optional<Token> view_, background_;
  Vec3 background_color_{0.0};
  std::vector<Light> lights_;
  Json materials_ = Json::object();
  std::optional<std::string> material_;  // the current `f`'s name
  int material_count_ = 0;
  Json objects_ = Json::array();
};

}  // namespace

bool is_nff_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".nff";
}

NffScene read_nff(std::string_view text, const std::string& filename) { return NffReader(text, filename).read(); }

NffScene read_nff_file(const std::filesystem::path& path) {
  const std::vector<unsigned char> bytes = read_file(path);
  return read_nff(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
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
    if (const auto it = scene.origins.find(path); it != scene.origins.end()) {
      // "objects[3].radius: must be > 0" -> "s: radius: must be > 0"
      std::string rest = e.message();
      if (rest.starts_with(path) && (rest.size() == path.size() || rest[path.size()] == '.' || rest[path.size()] == ':')) {
        rest.erase(0, path.size());
        if (rest.starts_with(": ")) rest.erase(0, 2);
        else if (rest.starts_with(".")) rest.erase(0, 1);
      }
      return Error(it->second.where, it->second.entity + ": " + rest);
    }
  }
  return Error(SourceLocation{scene.filename, 0, 0}, e.message());
}

}  // namespace glint
