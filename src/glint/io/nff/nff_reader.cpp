// The NFF reader: a lexer over the file's text and one function per entity,
// into Parts (nff_parts.h). Every problem is an Error at file:line:col.
#include "glint/io/nff/nff_parts.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <optional>

namespace glint::nff {

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

Where where(const Token& t) { return {t.line, t.column}; }

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
      else fail(*t, "unknown entity " + quoted(kw) + " (expected v, b, l, f, c, s, p or pp)");
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
      fail(angle_value,
           "v: angle must be between 0 and 180 degrees, exclusive (got " + printable(angle_value.text) + ")");
    if (at == from) fail(at_t, "v: \"at\" must differ from \"from\" (the view needs a direction)");
    const std::optional<Vec3> forward = unit_direction(at - from);
    if (!forward) fail(at_t, "v: \"at\" is too far from \"from\" (the distance overflows)");
    const std::optional<Vec3> up_unit = unit_direction(up);
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
        const std::string name = "vertex " + std::to_string(i + 1) + " of " + std::to_string(n) + what + kAxis[axis];
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
  uint32_t material_ = 0;        // the current `f` (1-based), 0 before the first
  std::vector<double> normals_;  // a `pp`'s normals while its vertices are read
};

}  // namespace

Parts read_parts(std::string_view text, std::string filename) { return NffReader(text, std::move(filename)).read(); }

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
      return {"lights[" + std::to_string(index) + "]",
              at("l", parts.lights[index < parts.lights.size() ? index : 0].at)};
    case Section::object:
      return {"objects[" + std::to_string(index) + "]", at(entity_of(parts.objects[index]), parts.objects[index].at)};
    case Section::none: break;
  }
  return {};
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

}  // namespace glint::nff
