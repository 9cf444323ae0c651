#include "glint/io/mesh/obj_reader.h"

#include <fast_float/fast_float.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "glint/io/mesh/common.h"
#include "glint/io/mesh/obj_checks.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {
namespace {

// The separators of the statements' numbers, as find_obj_bad_statement splits them.
inline bool is_separator(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
inline bool is_digit(char c) { return static_cast<unsigned>(c) - '0' < 10u; }

// The next token of a line from `p` (empty at the line's end).
inline std::string_view next_token(const char*& p, const char* end) {
  while (p < end && is_separator(*p)) ++p;
  const char* start = p;
  while (p < end && !is_separator(*p)) ++p;
  return {start, static_cast<size_t>(p - start)};
}

// What tinyobjloader's own number parser (tryParseDouble) makes of a token:
// it takes the longest prefix of [+-](digits[.digits]|.digits)[(e|E)[+-]digits]
// it can, gives up on an exponent without digits or above 214748364x, and the
// caller then uses a default. The value of the prefix is computed here by
// fast_float (tinyobjloader sums digits in double; both round to the same
// float on every file the equivalence test reads, and on 40 million random
// decimals of 6 to 17 digits tried while writing this).
std::optional<double> tinyobj_number(std::string_view s) {
  size_t i = 0;
  const size_t n = s.size();
  bool negative = false;
  if (i < n && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  const size_t mantissa_start = i;
  size_t digits = 0;
  if (!(i < n && s[i] == '.')) {
    while (i < n && is_digit(s[i])) ++i, ++digits;
    if (digits == 0) return std::nullopt;
  }
  if (i < n && s[i] == '.')
    for (++i; i < n && is_digit(s[i]); ++i) ++digits;
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < n && (s[i] == '+' || s[i] == '-')) {
      ++i;
    } else if (!(i < n && is_digit(s[i]))) {
      return std::nullopt;
    }
    const size_t exponent_start = i;
    int exponent = 0;
    for (; i < n && is_digit(s[i]); ++i) {
      if (exponent > 214748364) return std::nullopt;
      exponent = exponent * 10 + (s[i] - '0');
    }
    if (i == exponent_start) return std::nullopt;
  }
  if (digits == 0) return negative ? -0.0 : 0.0;  // ".", "-.e5"
  // fast_float takes no '+' and no mantissa without digits; both are gone here.
  const std::string_view prefix = s.substr(mantissa_start, i - mantissa_start);
  double value = 0;
  const auto r = fast_float::from_chars(prefix.data(), prefix.data() + prefix.size(), value);
  if (r.ptr != prefix.data() + prefix.size()) {
    const std::string copy(prefix);
    value = std::strtod(copy.c_str(), nullptr);
  }
  return negative ? -value : value;
}

// A number find_obj_bad_statement accepts that read_plain_number (below)
// does not take ('+', "nan", exponents), as tinyobjloader reads it
// (`fallback` where it reads none: "nan", "inf"). False: not a number.
// `nonfinite_text` tells a "nan"/"inf" text (read as `fallback`).
inline bool read_number(std::string_view tok, double fallback, float& out, bool& nonfinite_text) {
  if (!is_decimal_number(tok) && !parse_number(tok)) return false;
  const std::optional<double> value = tinyobj_number(tok);
  out = static_cast<float>(value ? *value : fallback);
  std::string_view s = tok;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
  const std::string l = lower(s.substr(0, 3));
  nonfinite_text = l == "nan" || l == "inf";
  return true;
}

// The common number of a v, vt or vn statement, read at `p` (blanks before
// it skipped) straight to the separator after it, `p` then moved there,
// without finding the token's end first (a number never runs on into a
// separator, so fast_float stops where the token ends). False, `p` unmoved,
// for anything else ('+', "nan", a zero or infinity written with an
// exponent, which may be tinyobjloader's fallback instead; text after the
// digits): read_number decides.
inline bool read_plain_number(const char*& p, const char* end, float& out) {
  const char* body = p < end && *p == '-' ? p + 1 : p;
  if (!(body < end && (is_digit(*body) || *body == '.'))) return false;
  double value = 0;
  const auto r = fast_float::from_chars(p, end, value);
  if (r.ec != std::errc() || (r.ptr < end && !is_separator(*r.ptr))) return false;
  if ((value == 0 || std::isinf(value)) &&
      std::string_view(p, static_cast<size_t>(r.ptr - p)).find_first_of("eE") != std::string_view::npos)
    return false;
  out = static_cast<float>(value);
  p = r.ptr;
  return true;
}

// What tinyobjloader reads of a token it does not check (the v of "vt u v"):
// the number at its start, else `fallback`. It splits at blanks only.
inline float lenient_number(std::string_view tok, double fallback) {
  const std::optional<double> value = tinyobj_number(tok);
  return static_cast<float>(value ? *value : fallback);
}

// An OBJ index as find_obj_bad_statement's parse_index takes it:
// [+-]digits, at most 18 digits, not 0.
inline bool read_index(std::string_view s, int64_t& value) {
  size_t i = 0;
  const bool negative = !s.empty() && s[0] == '-';
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) i = 1;
  if (i == s.size() || s.size() - i > 18) return false;
  int64_t v = 0;
  for (; i < s.size(); ++i) {
    const unsigned digit = static_cast<unsigned>(s[i]) - '0';
    if (digit > 9) return false;
    v = v * 10 + digit;
  }
  value = negative ? -v : v;
  return value != 0;
}

// Statements the join replays in file order (few in large files).
struct Event {
  enum Kind : uint8_t { usemtl, mtllib, group, object, line, points, small_face } kind;
  size_t face;            // faces (>= 3 corners) of the file before it
  std::string_view text;  // usemtl: the name; mtllib: the rest of the line
  size_t count = 0;       // line, points: the number of indices
};

// A statement tinyobjloader rejects that find_obj_bad_statement lets pass
// ("f 1//", "f 1/2/3/4", "vw 1 -1 0.5"): the load fails at its line unless
// the check finds something anywhere in the file.
struct LibraryError {
  int line = 0;  // in the chunk; 0: none
  enum Kind : uint8_t { face, line_or_point, vw } kind = face;
  int column = 0;  // of the first corner it rejects (faces, lines, points); 0: the statement's
};

// What a chunk holds, or what comes before it: v, vt, vn statements,
// faces of 3 corners or more and their corners, lines of text.
struct Counts {
  size_t of[3] = {0, 0, 0};
  size_t faces = 0, corners = 0;
  int lines = 0;
};

// One chunk's results beside the arrays it fills in place.
struct Chunk {
  Counts count;  // the first pass's
  std::vector<Event> events;
  std::vector<BadVertexText> bad_vertex_text;
  bool check_problem = false;  // find_obj_bad_statement would report something here
  LibraryError library_error;  // its line counted in the chunk
};

// v/vt/vn statements: 0, 1, 2.
constexpr int kVertex = 0, kTexcoord = 1, kNormal = 2;

// One corner "v", "v/t", "v//n", "v/t/n" of a face, line or points
// statement into `index` (0-based, -1: absent), against the counts of v, vt
// and vn before it. Returns false for what the check rejects (not a whole
// number, 0, out of range); sets `library_error` for what tinyobjloader rejects.
inline bool read_corner(std::string_view tok, const size_t counts[3], int32_t index[3], bool& library_error) {
  index[1] = index[2] = -1;
  std::string_view part = tok;
  for (int k = 0; k < 3; ++k) {
    const size_t slash = part.find('/');
    const std::string_view text = part.substr(0, slash);
    if (k == 0 || !text.empty()) {
      int64_t i = 0;
      if (!read_index(text, i)) return false;
      const auto count = static_cast<int64_t>(counts[k]);
      const int64_t resolved = i > 0 ? i - 1 : count + i;
      if (resolved < 0 || resolved >= count) return false;
      index[k] = static_cast<int32_t>(resolved);
    } else if (k == 1 ? slash == std::string_view::npos : true) {
      // "1/" and "1//", "1/2/": tinyobjloader reads the next thing as the
      // index (0 at the line's end) and fails or misreads.
      library_error = true;
    }
    if (slash == std::string_view::npos) break;
    part = part.substr(slash + 1);
    if (k == 2) library_error = true;  // a fourth part: tinyobjloader fails on it
  }
  return true;
}

// The common corners "v", "v/t", "v//n" and "v/t/n" of positive indices in
// range, read at `p` straight to the separator after them, `p` then moved
// there: what read_corner makes of them, without finding the token's end
// and its slashes first. False, `p` unmoved, for anything else (signs, "v/",
// a fourth part, an index of 0, out of range or of over 18 digits):
// read_corner decides.
inline bool read_plain_corner(const char*& p, const char* end, const size_t counts[3], int32_t index[3]) {
  const char* q = p;
  auto number = [&](int k) {
    const char* start = q;
    uint64_t value = 0;
    while (q < end && is_digit(*q) && q - start < 18) value = value * 10 + static_cast<unsigned>(*q++ - '0');
    if (q == start || value == 0 || value > counts[k]) return false;
    index[k] = static_cast<int32_t>(value - 1);
    return true;
  };
  index[1] = index[2] = -1;
  if (!number(0)) return false;
  if (q < end && *q == '/') {
    ++q;
    if (q < end && *q != '/' && !number(1)) return false;
    if (q < end && *q == '/') {
      ++q;
      if (!number(2)) return false;
    } else if (index[1] < 0) {
      return false;  // "v/"
    }
  }
  if (q < end && !is_separator(*q)) return false;
  p = q;
  return true;
}

// tinyobjloader's "vw vid joint weight ...": a joint that is negative or not a
// number fails the load (glint ignores the weights).
bool vw_fails(std::string_view rest) {
  const char* p = rest.data();
  const char* end = p + rest.size();
  auto blank = [](char c) { return c == ' ' || c == '\t'; };
  auto token = [&] {
    while (p < end && blank(*p)) ++p;
    const char* start = p;
    while (p < end && !blank(*p)) ++p;
    return std::string_view(start, static_cast<size_t>(p - start));
  };
  token();  // the vertex id
  while (p < end) {
    const float joint = lenient_number(token(), -1.0);
    token();  // the weight
    if (joint < 0) return true;
    while (p < end && blank(*p)) ++p;
  }
  return false;
}

inline bool key_is(std::string_view t, std::string_view key) {
  return t.size() > key.size() && t.substr(0, key.size()) == key && is_blank(t[key.size()]);
}

// LineCursor for text without '\r' (nearly every chunk of a big file): one
// memchr a line instead of two.
class LfLines {
 public:
  explicit LfLines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const char* begin = text_.data() + pos_;
    const void* nl = std::memchr(begin, '\n', text_.size() - pos_);
    const size_t end = nl ? static_cast<size_t>(static_cast<const char*>(nl) - text_.data()) : text_.size();
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  int number() const { return number_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  int number_ = 0;
};

// Calls f(lines) with the cheaper cursor when the text has no '\r'.
template <typename F>
void with_lines(std::string_view text, F f) {
  if (text.find('\r') == std::string_view::npos) f(LfLines(text));
  else f(LineCursor(text));
}

// The first pass: what parse_chunk will store (it stops at errors, which fail the load).
Counts count_chunk(std::string_view text) {
  Counts n;
  with_lines(text, [&](auto lines) {
    std::string_view line;
    while (lines.next(line)) {
      const std::string_view t = skip_blanks(line);
      if (t.size() < 2) continue;
      if (t[0] == 'v') {
        if (is_blank(t[1])) ++n.of[kVertex];
        else if (key_is(t, "vt")) ++n.of[kTexcoord];
        else if (key_is(t, "vn")) ++n.of[kNormal];
      } else if (t[0] == 'f' && is_blank(t[1])) {
        size_t corners = 0;
        bool in_token = false;
        for (size_t i = 1; i < t.size(); ++i) {
          const bool sep = is_separator(t[i]);
          corners += !sep && !in_token;
          in_token = !sep;
        }
        if (corners >= 3) {
          ++n.faces;
          n.corners += corners;
        }
      }
    }
    n.lines = lines.number();
  });
  return n;
}

// The second pass: parses one chunk of whole lines into `out` at the
// chunk's place (`before`: what the chunks before it hold). Stops at the
// first statement the check rejects.
template <typename Lines>
void parse_lines(Lines& lines, const Counts& before, ObjData& out, Chunk& c) {
  std::string_view line;
  size_t counts[3] = {before.of[0], before.of[1], before.of[2]};  // so far, in the file
  size_t face = before.faces, corner = before.corners;
  const bool keep_texcoord = !out.corner_texcoord.empty(), keep_normal = !out.corner_normal.empty();
  std::vector<std::array<int32_t, 3>> corners;  // of the current statement
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.empty() || t[0] == '#') continue;
    const char* end = t.data() + t.size();
    const int line_number = lines.number();
    const char c0 = t[0];
    if (c0 == 'v') {
      const int kind = key_is(t, "v") ? kVertex : key_is(t, "vt") ? kTexcoord : key_is(t, "vn") ? kNormal : -1;
      if (kind < 0) {
        if (key_is(t, "vw") && vw_fails(t.substr(3)) && c.library_error.line == 0)
          c.library_error = {line_number, LibraryError::vw};
        continue;
      }
      const char* p = t.data() + (kind == kVertex ? 1 : 2);
      const size_t needed = kind == kTexcoord ? 1 : 3;
      float value[3] = {0, 0, 0};
      for (size_t k = 0; k < needed; ++k) {
        while (p < end && is_separator(*p)) ++p;
        if (read_plain_number(p, end, value[k])) continue;
        const std::string_view tok = next_token(p, end);
        bool nonfinite = false;
        if (tok.empty() || !read_number(tok, 0.0, value[k], nonfinite)) {
          c.check_problem = true;
          return;
        }
        if (nonfinite && kind == kVertex)
          c.bad_vertex_text.push_back({static_cast<uint32_t>(counts[kVertex]), before.lines + line_number,
                                       static_cast<int>(tok.data() - line.data()) + 1, std::string(tok)});
      }
      if (counts[kind] >= before.of[kind] + c.count.of[kind]) {  // the passes disagree: cannot happen
        c.check_problem = true;
        return;
      }
      if (kind == kVertex) {
        out.positions[counts[kind]] = {value[0], value[1], value[2]};
      } else if (kind == kNormal) {
        out.normals[counts[kind]] = {value[0], value[1], value[2]};
      } else {
        // tinyobjloader splits at blanks only here: the v is the number at
        // the start of the next blank-separated token, else 0.
        const char* q = p;
        while (q < end && (*q == ' ' || *q == '\t')) ++q;
        const char* start = q;
        while (q < end && *q != ' ' && *q != '\t') ++q;
        out.texcoords[counts[kind]] = {value[0], lenient_number({start, static_cast<size_t>(q - start)}, 0.0)};
      }
      ++counts[kind];
      continue;
    }
    if (c0 == 'f' || c0 == 'l' || c0 == 'p') {
      if (t.size() < 2 || !is_blank(t[1])) continue;
      const char* p = t.data() + 1;
      corners.clear();
      bool library_error = false;
      int library_error_column = 0;
      for (;;) {
        while (p < end && is_separator(*p)) ++p;
        if (p == end) break;
        std::array<int32_t, 3> index;
        if (read_plain_corner(p, end, counts, index.data())) {
          corners.push_back(index);
          continue;
        }
        const std::string_view tok = next_token(p, end);
        const bool earlier = library_error;
        if (!read_corner(tok, counts, index.data(), library_error)) {
          c.check_problem = true;
          return;
        }
        if (library_error && !earlier) library_error_column = static_cast<int>(tok.data() - line.data()) + 1;
        corners.push_back(index);
      }
      if (library_error && c.library_error.line == 0)
        c.library_error = {line_number, c0 == 'f' ? LibraryError::face : LibraryError::line_or_point,
                           library_error_column};
      if (c0 != 'f') {
        c.events.push_back({c0 == 'l' ? Event::line : Event::points, face, {}, corners.size()});
      } else if (corners.size() < 3) {
        c.events.push_back({Event::small_face, face, {}, 0});
      } else {
        if (face >= before.faces + c.count.faces || corner + corners.size() > before.corners + c.count.corners) {
          c.check_problem = true;  // the passes disagree: cannot happen
          return;
        }
        for (const auto& index : corners) {
          out.corner_vertex[corner] = static_cast<uint32_t>(index[0]);  // read_corner: 0 or more
          if (keep_texcoord) out.corner_texcoord[corner] = index[1];
          if (keep_normal) out.corner_normal[corner] = index[2];
          ++corner;
        }
        out.face_start[++face] = static_cast<uint32_t>(corner);
      }
      continue;
    }
    if (t.substr(0, 6) == "usemtl") {
      // tinyobjloader: no blank needed after the keyword; the name ends at a blank.
      std::string_view name = t.substr(6);
      name = skip_blanks(name);
      name = name.substr(0, std::min(name.find_first_of(" \t"), name.size()));
      c.events.push_back({Event::usemtl, face, name, 0});
    } else if (key_is(t, "mtllib")) {
      c.events.push_back({Event::mtllib, face, t.substr(7), 0});
    } else if (key_is(t, "g")) {
      c.events.push_back({Event::group, face, {}, 0});
    } else if (key_is(t, "o")) {
      c.events.push_back({Event::object, face, {}, 0});
    }
    // s, t, curves and the rest: ignored, as tinyobjloader does.
  }
}

void parse_chunk(std::string_view text, const Counts& before, ObjData& out, Chunk& c) {
  with_lines(text, [&](auto lines) { parse_lines(lines, before, out, c); });
}

// tinyobjloader's SplitString(s, ' ', '\\'): mtllib file names.
std::vector<std::string> split_names(std::string_view s) {
  std::vector<std::string> names;
  std::string name;
  bool escaping = false;
  for (char ch : s) {
    if (escaping) {
      escaping = false;
    } else if (ch == '\\') {
      escaping = true;
      continue;
    } else if (ch == ' ') {
      if (!name.empty()) names.push_back(name);
      name.clear();
      continue;
    }
    name += ch;
  }
  names.push_back(name);
  return names;
}

// tinyobjloader's shapes, as far as glint sees them: which lines and points
// it keeps (a group without faces loses them) and each face's material.
struct Replay {
  Replay(tinyobj::MaterialReader* reader, ObjData& data) : mtl(reader), out(data) {}
  tinyobj::MaterialReader* mtl;
  ObjData& out;
  std::map<std::string, int> material_map;
  std::set<std::string> loaded;
  int material = -1;
  size_t material_from = 0;  // first face of the current material run
  // tinyobjloader's PrimGroup (since the last flush) and shape_t.
  size_t group_faces_from = 0;
  bool group_small = false;
  size_t group_lines = 0, group_line_indices = 0, group_points = 0, group_point_indices = 0;
  bool shape_mesh = false;
  size_t shape_lines = 0, shape_line_indices = 0, shape_point_indices = 0;

  bool flush(size_t face) {
    const bool faces = face > group_faces_from;
    if (!faces && !group_small && group_lines == 0 && group_points == 0) return false;
    shape_mesh |= faces;
    shape_lines += group_lines;
    shape_line_indices += group_line_indices;
    shape_point_indices += group_point_indices;
    return true;
  }
  void clear_faces(size_t face) {
    group_faces_from = face;
    group_small = false;
  }
  void new_shape(size_t face, bool keep) {
    if (keep) out.non_faces += shape_lines + shape_point_indices;
    shape_mesh = false;
    shape_lines = shape_line_indices = shape_point_indices = 0;
    clear_faces(face);
    group_lines = group_line_indices = group_points = group_point_indices = 0;
  }
  void set_material(size_t face, int id) {
    std::fill(out.face_material.begin() + static_cast<ptrdiff_t>(material_from),
              out.face_material.begin() + static_cast<ptrdiff_t>(face), material);
    material_from = face;
    material = id;
  }
  void load_libraries(std::string_view rest) {
    if (!mtl) return;
    bool found = false;
    for (const std::string& name : split_names(rest)) {
      if (loaded.count(name)) {
        found = true;
        continue;
      }
      std::string warn, err;
      if ((*mtl)(name, &out.materials, &material_map, &warn, &err)) {
        loaded.insert(name);
        break;
      }
    }
    (void)found;  // tinyobjloader only warns, and glint reports missing libraries from MtlReader
  }
  void event(const Event& e, size_t face) {
    switch (e.kind) {
      case Event::usemtl: {
        const std::string name(e.text);
        const auto it = material_map.find(name);
        const int id = it != material_map.end() ? it->second : -1;
        if (it == material_map.end()) out.unknown_materials.push_back(name);
        if (id != material) {
          flush(face);
          clear_faces(face);
          set_material(face, id);
        }
        break;
      }
      case Event::mtllib: load_libraries(e.text); break;
      case Event::group:
        flush(face);
        new_shape(face, shape_mesh);
        break;
      case Event::object:
        flush(face);
        new_shape(face, shape_mesh || shape_line_indices > 0 || shape_point_indices > 0);
        break;
      case Event::line:
        ++group_lines;
        group_line_indices += e.count;
        break;
      case Event::points:
        ++group_points;
        group_point_indices += e.count;
        break;
      case Event::small_face:
        group_small = true;
        ++out.small_faces;
        break;
    }
  }
  void finish(size_t faces) {
    const bool flushed = flush(faces);
    if (flushed || shape_mesh) out.non_faces += shape_lines + shape_point_indices;
    set_material(faces, -1);
  }
};

size_t default_threads(const ObjReadOptions& options) {
  if (options.threads > 0) return options.threads;
  return std::max<size_t>(1, std::thread::hardware_concurrency());
}

size_t default_chunks(std::string_view text, const ObjReadOptions& options, size_t threads) {
  if (options.chunks > 0) return options.chunks;
  // About 1 MiB each (a thread's start costs far less), several per thread
  // so that a thread that drew vertex lines (slower per byte) does not hold up the rest.
  return std::clamp<size_t>(text.size() >> 20, 1, 8 * threads);
}

}  // namespace

std::vector<size_t> split_obj_chunks(std::string_view text, size_t chunks) {
  chunks = std::max<size_t>(1, chunks);
  std::vector<size_t> bounds(chunks + 1, text.size());
  bounds[0] = 0;
  for (size_t i = 1; i < chunks; ++i) {
    size_t at = std::max(bounds[i - 1], text.size() / chunks * i);
    const size_t nl = text.find('\n', at);
    bounds[i] = nl == std::string_view::npos ? text.size() : nl + 1;
  }
  return bounds;
}

ObjData read_obj(std::string_view text, const std::string& file, tinyobj::MaterialReader* mtl,
                 const ObjReadOptions& options) {
  const size_t threads = default_threads(options);
  const std::vector<size_t> bounds = split_obj_chunks(text, default_chunks(text, options, threads));
  const size_t n = bounds.size() - 1;
  auto chunk_text = [&](size_t i) { return text.substr(bounds[i], bounds[i + 1] - bounds[i]); };
  std::vector<Chunk> chunks(n);
  // Counted first, so that each chunk parses straight into the arrays at its
  // place and resolves indices that count back as it goes.
  run_parallel(n, threads, [&](size_t i) { chunks[i].count = count_chunk(chunk_text(i)); });
  std::vector<Counts> before(n + 1);
  for (size_t i = 0; i < n; ++i) {
    const Counts& c = chunks[i].count;
    Counts& b = before[i + 1];
    b = before[i];
    for (int k = 0; k < 3; ++k) b.of[k] += c.of[k];
    b.faces += c.faces;
    b.corners += c.corners;
    b.lines += c.lines;
  }
  const Counts& total = before[n];
  if (total.corners > INT32_MAX || total.of[0] > INT32_MAX || total.of[1] > INT32_MAX || total.of[2] > INT32_MAX)
    fail(file, "more than 2^31 vertices or face corners: too many for one mesh");

  ObjData out;
  resize_in_huge_pages(out.positions, total.of[kVertex]);
  resize_in_huge_pages(out.texcoords, total.of[kTexcoord]);
  resize_in_huge_pages(out.normals, total.of[kNormal]);
  resize_in_huge_pages(out.face_start, total.faces + 1);
  resize_in_huge_pages(out.corner_vertex, total.corners);
  if (total.of[kTexcoord] > 0) resize_in_huge_pages(out.corner_texcoord, total.corners);
  if (total.of[kNormal] > 0) resize_in_huge_pages(out.corner_normal, total.corners);
  run_parallel(n, threads, [&](size_t i) { parse_chunk(chunk_text(i), before[i], out, chunks[i]); });

  if (std::any_of(chunks.begin(), chunks.end(), [](const Chunk& c) { return c.check_problem; })) {
    // The check's own message and position (one more pass, on errors only).
    const TextProblem bad = find_obj_bad_statement(text);
    if (bad.line > 0) fail(file, bad.message, bad.line, bad.column);
    fail(file, "cannot read OBJ (the reader and its check disagree)");
  }
  for (size_t i = 0; i < n; ++i) {
    const LibraryError& e = chunks[i].library_error;
    if (e.line == 0) continue;
    const int line = before[i].lines + e.line;
    if (e.kind == LibraryError::face) fail(file, "face with a vertex index of 0 or not a number", line, e.column);
    if (e.kind == LibraryError::line_or_point)
      fail(file, "line or point with a vertex index of 0 or not a number", line, e.column);
    fail(file, "cannot read OBJ: Failed parse `vw' line. joint_id is negative. line " + std::to_string(line) + ".)",
         line);
  }

  // usemtl, mtllib, groups, lines and points in file order.
  resize_in_huge_pages(out.face_material, total.faces);
  Replay replay(mtl, out);
  for (size_t i = 0; i < n; ++i) {
    for (const Event& e : chunks[i].events) replay.event(e, e.face);
    for (BadVertexText& bad : chunks[i].bad_vertex_text) out.bad_vertex_text.push_back(std::move(bad));
  }
  replay.finish(total.faces);
  return out;
}

}  // namespace glint::mesh_io
