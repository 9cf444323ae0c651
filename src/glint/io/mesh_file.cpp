// Mesh files into MeshFile: the libraries parse, this file applies the contract.
// - .obj (+ .mtl): tinyobjloader (fastest measured; keeps the file's vertex
//   indices). Its gaps are covered here: it reads "nan"/"inf" as 0 and "Kd 0.5"
//   as red, and cannot say which MTL keys were given, so short scans of the
//   text find those (and file:line for errors, on the error path only).
// - .ply, .gltf, .glb: assimp. Its PLY reader crashes, aborts or hangs on
//   truncated or inconsistent files, so every PLY is checked first against its
//   own header (counts against the file size, every record present, indices
//   in range) by a structural walk that stores nothing. Its glTF reader trusts
//   the JSON: glint's JSON reader checks it first (what it claims in memory,
//   accessors within their views, sparse parts), and assimp gets it reduced
//   to what glint uses (no skins, animations, morph targets, cameras or
//   embedded images).
// - Every format: what the file claims or implies in memory is checked
//   against a budget (memory_limit.h) before it is allocated.
// Then, for every format: polygons triangulated (quads on the shorter
// diagonal, larger polygons as fans), NaN/Inf vertices used by a triangle are
// errors, zero-area triangles dropped with one counted warning, corner normals
// from the file or angle-weighted per vertex index, unused vertices removed.
#include "glint/io/mesh_file.h"

#include <tiny_obj_loader.h>

#include <nlohmann/json.hpp>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/DefaultIOSystem.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <optional>
#include <charconv>
#include <cmath>
#include <cfloat>
#include <cstdio>
#include <cstring>
#include <functional>
#include <istream>
#include <map>
#include <mutex>
#include <new>
#include <set>
#include <streambuf>
#include <string_view>
#include <system_error>
#include <thread>

#include "glint/error.h"
#include "glint/io/file_io.h"
#include "glint/io/json.h"

namespace glint {
namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------
// Shared helpers
// ---------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& file, const std::string& message, int line = 0, int column = 0) {
  throw Error(SourceLocation{file, line, column}, message);
}

std::string plural(size_t n, const char* singular, const char* plural_form) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural_form);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string with_line(const std::string& file, int line) {
  return line > 0 ? file + ":" + std::to_string(line) : file;
}

// Lists up to three names, then "and N more".
std::string name_list(const std::vector<std::string>& names) {
  std::string out;
  for (size_t i = 0; i < names.size() && i < 3; ++i) out += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > 3) out += " and " + std::to_string(names.size() - 3) + " more";
  return out;
}

// A count as a whole number, also beyond 64 bits ("4000000000", "1e+300").
std::string format_count(double n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, n < 1e15 ? "%.0f" : "%.3g", n);
  return buf;
}

bool is_finite(const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Lines as tinyobjloader splits them: "\n", "\r\n" or a lone "\r" ends one.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const size_t start = pos_;
    // memchr (vectorized) for the '\n', then for a '\r' before it.
    const char* begin = text_.data() + start;
    const char* nl = static_cast<const char*>(std::memchr(begin, '\n', text_.size() - start));
    const char* end = nl ? nl : text_.data() + text_.size();
    if (const void* cr = std::memchr(begin, '\r', static_cast<size_t>(end - begin))) end = static_cast<const char*>(cr);
    pos_ = static_cast<size_t>(end - text_.data());
    line = text_.substr(start, pos_ - start);
    if (pos_ < text_.size()) {
      if (text_[pos_] == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') ++pos_;
      ++pos_;
    }
    ++number_;
    return true;
  }
  int number() const { return number_; }  // of the line `next` returned, 1-based

 private:
  std::string_view text_;
  size_t pos_ = 0;
  int number_ = 0;
};

bool is_blank(char c) { return c == ' ' || c == '\t'; }

std::string_view skip_blanks(std::string_view s) {
  size_t i = 0;
  while (i < s.size() && is_blank(s[i])) ++i;
  return s.substr(i);
}

// Whitespace-separated tokens of a line, with their 1-based columns.
struct Token {
  std::string_view text;
  int column;
};
std::vector<Token> tokens_of(std::string_view line, size_t max_tokens = SIZE_MAX) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < line.size() && out.size() < max_tokens) {
    while (i < line.size() && (is_blank(line[i]) || line[i] == '\r' || line[i] == '\v' || line[i] == '\f')) ++i;
    if (i >= line.size()) break;
    const size_t start = i;
    while (i < line.size() && !(is_blank(line[i]) || line[i] == '\r' || line[i] == '\v' || line[i] == '\f')) ++i;
    out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

// A number as strtod reads it (leading '+' allowed); nullopt if it is not one.
// Out-of-range values come back as +-inf, so callers see them as non-finite.
std::optional<double> parse_number(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double value = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (end != s.data() + s.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    // Underflow reads as zero, overflow as infinity.
    const std::string digits(s);
    const double approx = std::strtod(digits.c_str(), nullptr);
    return std::isinf(approx) ? approx : 0.0;
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

std::optional<int64_t> parse_integer(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  int64_t value = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return value;
}

// True when `text` holds `word` in any letter case (word given in lower case).
bool contains_word_ci(std::string_view text, std::string_view word) {
  const char first_lower = word[0];
  const char first_upper = static_cast<char>(std::toupper(static_cast<unsigned char>(first_lower)));
  for (char first : {first_lower, first_upper}) {
    size_t pos = 0;
    while ((pos = text.find(first, pos)) != std::string_view::npos) {
      if (pos + word.size() <= text.size()) {
        bool match = true;
        for (size_t k = 1; k < word.size() && match; ++k)
          match = std::tolower(static_cast<unsigned char>(text[pos + k])) == word[k];
        if (match) return true;
      }
      ++pos;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------
// The common back end: triangles as the libraries gave them -> MeshFile
// ---------------------------------------------------------------------------

// A vertex whose text was "nan"/"inf" (or overflowed) where the library read a
// finite number; an error only if a triangle uses it.
struct BadVertexText {
  uint32_t vertex;
  int line, column;
  std::string text;
};

struct RawMesh {
  std::vector<Vec3f> positions;
  std::vector<uint32_t> indices;        // 3 per triangle
  std::vector<Vec3f> normals;           // 3 per triangle when has_normals; (0,0,0): none for that corner
  bool has_normals = false;
  std::vector<UVf> uvs;                 // 3 per triangle when has_uvs; (0,0) for a corner without one
  bool has_uvs = false;
  std::vector<int32_t> triangle_material;  // per triangle
  std::vector<Material> materials;
  std::vector<MeshTexture> textures;
  std::vector<std::string> warnings;
  std::vector<BadVertexText> bad_vertex_text;
  // The error for a used vertex that is NaN/Inf in memory (file:line where known).
  std::function<Error(uint32_t vertex)> nonfinite_vertex_error;
  size_t small_faces = 0;   // faces with fewer than 3 vertices (skipped)
  size_t non_faces = 0;     // points and lines
};

// Splits a polygon of n corners into triangles of corner numbers: quads along
// the shorter diagonal (as tinyobjloader does), larger polygons as a fan.
template <typename Position, typename Emit>
void triangulate(size_t n, Position position, Emit emit) {
  if (n < 3) return;
  if (n == 3) {
    emit(0, 1, 2);
  } else if (n == 4) {
    auto dist2 = [](const Vec3f& a, const Vec3f& b) {
      const double dx = double(a.x) - b.x, dy = double(a.y) - b.y, dz = double(a.z) - b.z;
      return dx * dx + dy * dy + dz * dz;
    };
    if (dist2(position(0), position(2)) < dist2(position(1), position(3))) {
      emit(0, 1, 2);
      emit(0, 2, 3);
    } else {
      emit(0, 1, 3);
      emit(1, 2, 3);
    }
  } else {
    for (size_t k = 1; k + 1 < n; ++k) emit(0, k, k + 1);
  }
}

struct Vec3d {
  double x, y, z;
};
inline Vec3d to_d(const Vec3f& v) { return {v.x, v.y, v.z}; }
inline Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double length(const Vec3d& a) { return std::sqrt(dot(a, a)); }

MeshFile finish(RawMesh raw, const std::string& file, bool vertex_normals) {
  const size_t vertex_count = raw.positions.size();
  size_t triangle_count = raw.indices.size() / 3;
  if (triangle_count == 0) {
    if (raw.non_faces > 0 || raw.small_faces > 0) fail(file, "no triangles (only points or lines)");
    if (vertex_count > 0) fail(file, "no triangles (vertices only)");
    fail(file, "no triangles (no meshes in the file)");
  }
  for (uint32_t i : raw.indices)
    if (i >= vertex_count)
      fail(file, "vertex index " + std::to_string(i) + " out of range (" + plural(vertex_count, "vertex", "vertices") +
                     ")");

  // NaN/Inf vertices used by a triangle (degenerate or not) are errors.
  std::vector<uint8_t> used(vertex_count, 0);
  for (uint32_t i : raw.indices) used[i] = 1;
  for (const BadVertexText& bad : raw.bad_vertex_text)
    if (bad.vertex < vertex_count && used[bad.vertex])
      fail(file, "vertex coordinate '" + bad.text + "' is not a finite number", bad.line, bad.column);
  for (size_t v = 0; v < vertex_count; ++v) {
    if (used[v] && !is_finite(raw.positions[v])) {
      if (raw.nonfinite_vertex_error) throw raw.nonfinite_vertex_error(static_cast<uint32_t>(v));
      fail(file, "vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }

  // Drop zero-area triangles; face normals and corner angles of the others.
  MeshFile out;
  std::vector<uint8_t> keep(triangle_count, 1);
  size_t dropped = 0;
  std::vector<Vec3d> face_normal(triangle_count);
  for (size_t t = 0; t < triangle_count; ++t) {
    const Vec3d p0 = to_d(raw.positions[raw.indices[3 * t]]);
    const Vec3d p1 = to_d(raw.positions[raw.indices[3 * t + 1]]);
    const Vec3d p2 = to_d(raw.positions[raw.indices[3 * t + 2]]);
    const Vec3d n = cross(sub(p1, p0), sub(p2, p0));
    const double len = length(n);
    if (!(len > 0) || !std::isfinite(len)) {
      keep[t] = 0;
      ++dropped;
      continue;
    }
    face_normal[t] = {n.x / len, n.y / len, n.z / len};
  }
  if (dropped > 0)
    raw.warnings.push_back(file + ": dropped " + plural(dropped, "degenerate triangle", "degenerate triangles"));
  if (dropped == triangle_count)
    fail(file, triangle_count == 1 ? std::string("no triangles (the only one is degenerate)")
                                   : "no triangles (all " + std::to_string(triangle_count) + " are degenerate)");

  // Which corners need a computed normal (no file normal, or a zero/non-finite one).
  auto file_normal = [&](size_t corner, Vec3d& n) {
    if (!raw.has_normals) return false;
    n = to_d(raw.normals[corner]);
    const double len = length(n);
    if (!(len > 0) || !std::isfinite(len)) return false;
    n = {n.x / len, n.y / len, n.z / len};
    return true;
  };
  bool need_computed = vertex_normals && !raw.has_normals;
  if (vertex_normals && !need_computed) {
    Vec3d n;
    for (size_t t = 0; t < triangle_count && !need_computed; ++t)
      if (keep[t])
        for (int k = 0; k < 3; ++k)
          if (!file_normal(3 * t + k, n)) need_computed = true;
  }

  // Angle-weighted vertex normals per vertex index: each face adds its unit
  // normal times its interior angle at the vertex. All three cross products
  // of a triangle's edges have the same length, so angle = atan2(|n|, dot).
  std::vector<Vec3d> vertex_normal;
  if (need_computed) {
    vertex_normal.assign(vertex_count, Vec3d{0, 0, 0});
    for (size_t t = 0; t < triangle_count; ++t) {
      if (!keep[t]) continue;
      const uint32_t i[3] = {raw.indices[3 * t], raw.indices[3 * t + 1], raw.indices[3 * t + 2]};
      const Vec3d p[3] = {to_d(raw.positions[i[0]]), to_d(raw.positions[i[1]]), to_d(raw.positions[i[2]])};
      const double twice_area = length(cross(sub(p[1], p[0]), sub(p[2], p[0])));
      for (int k = 0; k < 3; ++k) {
        const Vec3d a = sub(p[(k + 1) % 3], p[k]);
        const Vec3d b = sub(p[(k + 2) % 3], p[k]);
        const double angle = std::atan2(twice_area, dot(a, b));
        Vec3d& acc = vertex_normal[i[k]];
        acc.x += face_normal[t].x * angle;
        acc.y += face_normal[t].y * angle;
        acc.z += face_normal[t].z * angle;
      }
    }
  }

  // Remove vertices no kept triangle uses.
  std::vector<uint32_t> remap(vertex_count, UINT32_MAX);
  uint32_t next = 0;
  for (size_t t = 0; t < triangle_count; ++t)
    if (keep[t])
      for (int k = 0; k < 3; ++k) {
        uint32_t& r = remap[raw.indices[3 * t + k]];
        if (r == UINT32_MAX) r = next++;
      }
  // Keep the file's order of vertices.
  {
    uint32_t ordinal = 0;
    for (size_t v = 0; v < vertex_count; ++v)
      if (remap[v] != UINT32_MAX) remap[v] = ordinal++;
  }
  out.positions.resize(next);
  for (size_t v = 0; v < vertex_count; ++v)
    if (remap[v] != UINT32_MAX) out.positions[remap[v]] = raw.positions[v];

  const size_t kept = triangle_count - dropped;
  out.indices.reserve(3 * kept);
  if (vertex_normals) out.corner_normals.reserve(3 * kept);
  out.triangle_material.reserve(kept);
  for (size_t t = 0; t < triangle_count; ++t) {
    if (!keep[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = raw.indices[3 * t + k];
      out.indices.push_back(remap[v]);
      if (raw.has_uvs) out.corner_uvs.push_back(raw.uvs[3 * t + k]);
      if (!vertex_normals) continue;
      Vec3d n;
      if (!file_normal(3 * t + k, n)) {
        n = vertex_normal[v];
        const double len = length(n);
        // Opposite faces can cancel at a vertex: the face's own normal then.
        n = len > 0 && std::isfinite(len) ? Vec3d{n.x / len, n.y / len, n.z / len} : face_normal[t];
      }
      out.corner_normals.push_back({static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
    }
    out.triangle_material.push_back(t < raw.triangle_material.size() ? raw.triangle_material[t] : -1);
  }

  // Materials no triangle uses and that have no name are noise (tinyobjloader
  // adds one for an empty .mtl): drop those, keep the rest in file order.
  std::vector<int32_t> material_map(raw.materials.size(), -1);
  std::vector<uint8_t> material_used(raw.materials.size(), 0);
  for (int32_t m : out.triangle_material)
    if (m >= 0 && static_cast<size_t>(m) < raw.materials.size()) material_used[m] = 1;
  for (size_t m = 0; m < raw.materials.size(); ++m) {
    if (raw.materials[m].name.empty() && !material_used[m]) continue;
    material_map[m] = static_cast<int32_t>(out.materials.size());
    out.materials.push_back(std::move(raw.materials[m]));
  }
  for (int32_t& m : out.triangle_material)
    m = (m >= 0 && static_cast<size_t>(m) < material_map.size()) ? material_map[m] : -1;

  if (raw.small_faces > 0)
    raw.warnings.push_back(file + ": skipped " + plural(raw.small_faces, "face", "faces") +
                           " with fewer than 3 vertices");
  out.textures = std::move(raw.textures);
  out.warnings = std::move(raw.warnings);
  return out;
}

}  // namespace

MeshFile mesh_from_arrays(std::vector<Vec3f> positions, std::vector<uint32_t> indices,
                          const std::vector<Vec3f>& normals, const std::vector<UVf>& uvs, const std::string& name,
                          bool vertex_normals) {
  RawMesh raw;
  raw.positions = std::move(positions);
  raw.indices = std::move(indices);
  // Per-vertex values become per-corner ones, as a file's would be.
  auto corners = [&](const auto& per_vertex, auto& out) {
    out.reserve(raw.indices.size());
    using T = std::decay_t<decltype(per_vertex[0])>;
    for (uint32_t i : raw.indices) out.push_back(i < per_vertex.size() ? per_vertex[i] : T{});
  };
  if (!normals.empty()) {
    corners(normals, raw.normals);
    raw.has_normals = true;
  }
  if (!uvs.empty()) {
    corners(uvs, raw.uvs);
    raw.has_uvs = true;
  }
  return finish(std::move(raw), name, vertex_normals);
}

namespace {

// ---------------------------------------------------------------------------
// Wavefront OBJ and MTL (tinyobjloader)
// ---------------------------------------------------------------------------

// An istream over bytes in memory, without copying them.
class MemoryStreambuf : public std::streambuf {
 public:
  MemoryStreambuf(const char* data, size_t size) {
    char* p = const_cast<char*>(data);
    setg(p, p, p + size);
  }
};

// Where a text file goes wrong: 1-based line and column (line 0: nowhere).
struct TextProblem {
  int line = 0, column = 0;
  std::string message;
};

// What tinyobjloader's material_t cannot tell: which keys a newmtl block gave,
// whether a color had one value (the MTL spec: g = b = r), and where.
struct MtlBlock {
  std::string name;
  int line = 0;
  std::set<std::string> keys;    // "Ka", "Kd", "Ks", "Tf", "Ns", "Ni", "d", "Tr", "illum"
  std::set<std::string> single;  // colors given as one number
  int illum_line = 0, ns_line = 0;
};

// The numbers of an MTL statement glint uses ("Kd 0.5 0.5 0.5"), checked:
// tinyobjloader reads what is not a number as 0 ("Kd nan 0 0" is black,
// "illum x" unlit). Colors take 1 or 3 numbers, finite and >= 0; Ns, Ni, d,
// Tr one finite number; illum a whole number. Sets `problem` on the first.
void check_mtl_numbers(std::string_view t, std::string_view key, int line, int offset, TextProblem& problem) {
  if (problem.line > 0) return;
  const bool color = key == "Ka" || key == "Kd" || key == "Ks" || key == "Tf" || key == "Kt";
  const std::vector<Token> tokens = tokens_of(t.substr(key.size()), color ? 3 : 1);
  auto report = [&](int column, std::string message) {
    problem = {line, offset + static_cast<int>(key.size()) + column - 1, std::move(message)};
  };
  if (tokens.empty()) {
    problem = {line, offset, std::string(key) + " without a value"};
    return;
  }
  if (color && tokens.size() == 2) return report(tokens[1].column, std::string(key) + ": 1 or 3 numbers, not 2");
  for (const Token& tok : tokens) {
    // Appended, not "'" + text + "'": GCC 12 warns falsely (-Wrestrict) on
    // that operator+ when it inlines it without link-time optimization.
    std::string value = "'";
    value.append(tok.text).push_back('\'');
    if (key == "illum") {
      if (!parse_integer(tok.text)) report(tok.column, "illum " + value + " is not a whole number");
      return;
    }
    const auto x = parse_number(tok.text);
    if (!x) return report(tok.column, std::string(key) + " " + value + " is not a number" +
                                          (color ? " (only r g b colors are read)" : ""));
    if (!std::isfinite(*x)) return report(tok.column, std::string(key) + " " + value + " is not a finite number");
    if (color && *x < 0) return report(tok.column, std::string(key) + " " + value + ": color components must be >= 0");
  }
}

// Mirrors tinyobj::LoadMtl's blocks: a newmtl flushes the block before it if
// that one has a name; the last block is always flushed. Sets `problem` on
// the first number it cannot take (check_mtl_numbers).
std::vector<MtlBlock> scan_mtl(std::string_view text, TextProblem& problem) {
  std::vector<MtlBlock> blocks;
  MtlBlock current;
  LineCursor lines(text);
  std::string_view line;
  auto key_is = [](std::string_view t, std::string_view key) {
    return t.size() > key.size() && t.substr(0, key.size()) == key && is_blank(t[key.size()]);
  };
  while (lines.next(line)) {
    while (!line.empty() && is_blank(line.back())) line.remove_suffix(1);
    const std::string_view t = skip_blanks(line);
    if (t.empty() || t[0] == '#') continue;
    if (key_is(t, "newmtl")) {
      if (!current.name.empty()) blocks.push_back(std::move(current));
      current = MtlBlock{};
      current.name = std::string(t.substr(7));
      current.line = lines.number();
      continue;
    }
    const int offset = static_cast<int>(t.data() - line.data()) + 1;
    for (const char* key : {"Ka", "Kd", "Ks", "Tf", "Kt", "Ns", "Ni", "d", "Tr", "illum"})
      if (key_is(t, key)) check_mtl_numbers(t, key, lines.number(), offset, problem);
    for (const char* color : {"Ka", "Kd", "Ks", "Tf", "Kt"}) {
      if (key_is(t, color)) {
        const std::string key = std::string(color) == "Kt" ? "Tf" : color;
        current.keys.insert(key);
        if (tokens_of(t.substr(2)).size() == 1) current.single.insert(key);
        else current.single.erase(key);
      }
    }
    for (const char* scalar : {"Ns", "Ni", "d", "Tr"})
      if (key_is(t, scalar)) current.keys.insert(scalar);
    if (key_is(t, "Ns")) current.ns_line = lines.number();
    if (key_is(t, "illum")) {
      current.keys.insert("illum");
      current.illum_line = lines.number();
    }
  }
  blocks.push_back(std::move(current));
  return blocks;
}

// Per-file findings while mapping materials, reported once each.
struct MtlReport {
  size_t ns_below_one = 0;
  int ns_line = 0;
  size_t illum_8_to_10 = 0;
  int illum_line = 0;
  size_t illum_unknown = 0;
  int illum_unknown_line = 0;
  std::vector<std::string> missing_textures;
};

Color mtl_color(const tinyobj::real_t c[3], bool single) {
  return single ? Color(c[0], c[0], c[0]) : Color(c[0], c[1], c[2]);
}

// The contract's MTL table: Ka/Kd/Ks/Ns and illum 0..10 onto glint::Material.
Material map_mtl(const tinyobj::material_t& t, const MtlBlock& b, MtlReport& report) {
  Material m;  // the contract's defaults for every key the block leaves out
  m.name = t.name;
  auto has = [&](const char* key) { return b.keys.count(key) > 0; };
  auto single = [&](const char* key) { return b.single.count(key) > 0; };
  if (has("Ka")) m.ambient = mtl_color(t.ambient, single("Ka"));
  if (has("Kd")) m.diffuse = mtl_color(t.diffuse, single("Kd"));
  if (has("Ks")) m.specular = mtl_color(t.specular, single("Ks"));
  if (has("Ns")) {
    double ns = t.shininess;
    if (!(ns >= 1)) {
      if (report.ns_below_one++ == 0) report.ns_line = b.ns_line;
      ns = 1;
    }
    m.shininess = ns;
  }
  int illum = has("illum") ? t.illum : 2;
  if (illum >= 8 && illum <= 10) {
    if (report.illum_8_to_10++ == 0) report.illum_line = b.illum_line;
    illum = illum == 8 ? 2 : illum == 9 ? 4 : 1;
  } else if (illum < 0 || illum > 10) {
    if (report.illum_unknown++ == 0) report.illum_unknown_line = b.illum_line;
    illum = 2;
  }
  const double dissolve = (has("d") || has("Tr")) ? double(t.dissolve) : 1.0;
  const Color filter = has("Tf") ? mtl_color(t.transmittance, single("Tf")) : Color(1.0);
  switch (illum) {
    case 0: m.unlit = true; break;
    case 1: m.specular = Color(0.0); break;
    case 2: break;
    case 3: m.reflectivity = m.specular; break;
    case 4:
      m.reflectivity = m.specular;
      m.transparency = 1.0 - dissolve;
      m.ior = 1.0;
      break;
    case 5:
      m.reflectivity = m.specular;
      m.fresnel = true;
      break;
    case 6:
    case 7: {
      m.reflectivity = m.specular;
      // Material::transparency is one number: the mean of (1 - Ks) * Tf.
      const Color c = (Color(1.0) - m.specular) * filter;
      m.transparency = (c.x + c.y + c.z) / 3.0;
      if (has("Ni")) m.ior = t.ior;
      m.fresnel = illum == 7;
      break;
    }
    default: break;
  }
  m.transparency = std::clamp(m.transparency, 0.0, 1.0);
  return m;
}

// Reads each mtllib file next to the OBJ, remembers which were missing, and
// scans each one's text alongside tinyobj::LoadMtl.
class MtlReader : public tinyobj::MaterialReader {
 public:
  explicit MtlReader(fs::path folder) : folder_(std::move(folder)) {}

  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* map, std::string* warn, std::string* err) override {
    const fs::path path = (folder_ / name).lexically_normal();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      missing.push_back(name);
      return false;
    }
    std::vector<unsigned char> bytes;
    try {
      bytes = read_file(path);
    } catch (const Error&) {
      missing.push_back(name);
      return false;
    }
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    TextProblem problem;
    std::vector<MtlBlock> blocks = scan_mtl(text, problem);
    if (problem.line > 0 && !error)
      error = Error(SourceLocation{path.string(), problem.line, problem.column}, problem.message);
    const size_t before = materials->size();
    MemoryStreambuf buffer(text.data(), text.size());
    std::istream in(&buffer);
    tinyobj::LoadMtl(map, materials, &in, warn, err);
    // The scan mirrors LoadMtl's blocks; if it ever disagrees, fall back to
    // "every key given" for the extra materials rather than misattribute.
    for (size_t i = before; i < materials->size(); ++i) {
      const size_t b = i - before;
      MtlBlock block;
      if (b < blocks.size() && blocks[b].name == (*materials)[i].name) {
        block = blocks[b];
      } else {
        block.name = (*materials)[i].name;
        block.keys = {"Ka", "Kd", "Ks", "Ns", "illum"};
      }
      origin.push_back({path, std::move(block)});
    }
    return true;
  }

  struct Origin {
    fs::path mtl;
    MtlBlock block;
  };
  std::vector<Origin> origin;  // per material, as tinyobjloader numbers them
  std::vector<std::string> missing;
  std::optional<Error> error;  // the first bad number in a material library (thrown once LoadObj returns)

 private:
  fs::path folder_;
};

// The 1-based line of the n-th (0-based) statement with this keyword.
int find_obj_statement(std::string_view text, std::string_view keyword, size_t ordinal) {
  LineCursor lines(text);
  std::string_view line;
  size_t seen = 0;
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() > keyword.size() && t.substr(0, keyword.size()) == keyword && is_blank(t[keyword.size()])) {
      if (seen++ == ordinal) return lines.number();
    }
  }
  return 0;
}

// Literal "nan"/"inf" coordinates on 'v' lines (tinyobjloader reads them as 0).
std::vector<BadVertexText> scan_obj_nonfinite_text(std::string_view text) {
  std::vector<BadVertexText> bad;
  if (!contains_word_ci(text, "nan") && !contains_word_ci(text, "inf")) return bad;
  LineCursor lines(text);
  std::string_view line;
  uint32_t vertex = 0;
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() < 2 || t[0] != 'v' || !is_blank(t[1])) continue;
    const size_t offset = static_cast<size_t>(t.data() - line.data()) + 1;
    for (const Token& tok : tokens_of(t.substr(1), 3)) {
      std::string_view s = tok.text;
      if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
      const std::string l = lower(s.substr(0, 3));
      if (l == "nan" || l == "inf")
        bad.push_back({vertex, lines.number(), static_cast<int>(offset) + tok.column, std::string(tok.text)});
    }
    ++vertex;
  }
  return bad;
}

// The first statement whose numbers tinyobjloader would read wrongly or not
// at all: line, column and message. tinyobjloader reads a coordinate that is
// not a number ("v a b c", "v 1" without y and z) as 0, and an index with
// atoi, so "1.5" is 1 and "99999999999999999999" wraps to -1, a valid index
// counted back from the end. Checked here, in one pass over the text, before
// it parses: every v/vn has 3 numbers and every vt 1 (the rest of a line is
// not read); every index of a face, line or point is a whole number that
// names an existing vertex, texture coordinate or normal (negative ones count
// back from the current end). "nan" and "inf" are numbers here: a vertex
// holding one is an error only if a triangle uses it.
// [+-]digits[.digits][(e|E)[+-]digits] with a digit before or after the
// point: what parse_number reads, without converting (most of the cost).
bool is_decimal_number(std::string_view s) {
  size_t i = 0, digits = 0;
  auto is_digit = [&](size_t k) { return k < s.size() && s[k] >= '0' && s[k] <= '9'; };
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  for (; is_digit(i); ++i) ++digits;
  if (i < s.size() && s[i] == '.')
    for (++i; is_digit(i); ++i) ++digits;
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (!is_digit(i)) return false;
    while (is_digit(i)) ++i;
  }
  return i == s.size();
}

// An OBJ index: [+-]digits, at most 18 of them (so it fits in 64 bits).
// parse_integer's result, faster (a large file has millions).
std::optional<int64_t> parse_index(std::string_view s) {
  size_t i = 0;
  const bool negative = !s.empty() && s[0] == '-';
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) i = 1;
  if (i == s.size() || s.size() - i > 18) return std::nullopt;
  int64_t value = 0;
  for (; i < s.size(); ++i) {
    const unsigned digit = static_cast<unsigned>(s[i]) - '0';
    if (digit > 9) return std::nullopt;
    value = value * 10 + digit;
  }
  return negative ? -value : value;
}

TextProblem find_obj_bad_statement(std::string_view text) {
  LineCursor lines(text);
  std::string_view line;
  int64_t counts[3] = {0, 0, 0};  // v, vt, vn so far
  static constexpr const char* kIndexNames[3] = {"vertex", "texture coordinate", "normal"};
  static constexpr const char* kPlural[3] = {"vertices", "texture coordinates", "normals"};
  auto key_is = [](std::string_view t, std::string_view key) {
    return t.size() > key.size() && t.substr(0, key.size()) == key && is_blank(t[key.size()]);
  };
  // The next token of `t` from `pos` (blanks and \v \f separate), or empty.
  auto next_token = [](std::string_view t, size_t& pos) {
    auto blank = [](char c) { return is_blank(c) || c == '\r' || c == '\v' || c == '\f'; };
    while (pos < t.size() && blank(t[pos])) ++pos;
    const size_t start = pos;
    while (pos < t.size() && !blank(t[pos])) ++pos;
    return t.substr(start, pos - start);
  };
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() < 2 || (t[0] != 'v' && t[0] != 'f' && t[0] != 'l' && t[0] != 'p')) continue;
    const int offset = static_cast<int>(t.data() - line.data()) + 1;  // column of t[0]
    const int kind = key_is(t, "v") ? 0 : key_is(t, "vt") ? 1 : key_is(t, "vn") ? 2 : -1;
    if (kind >= 0) {
      const size_t needed = kind == 1 ? 1 : 3;
      size_t pos = kind == 0 ? 1 : 2;
      for (size_t k = 0; k < needed; ++k) {
        const std::string_view tok = next_token(t, pos);
        const int column = offset + static_cast<int>(pos - tok.size());
        const char* what = kind == 0 ? "vertex" : kind == 1 ? "texture coordinate" : "normal";
        if (tok.empty())
          return {lines.number(), offset + static_cast<int>(pos),
                  std::string(what) + " with " + plural(k, "number", "numbers") + " (" +
                      (kind == 1 ? "u [v] needed)" : "x y z needed)")};
        if (!is_decimal_number(tok) && !parse_number(tok))
          return {lines.number(), column,
                  std::string(what) + (kind == 1 ? " '" : " coordinate '") + std::string(tok) + "' is not a number"};
      }
      ++counts[kind];
      continue;
    }
    if (!key_is(t, "f") && !key_is(t, "l") && !key_is(t, "p")) continue;
    size_t pos = 1;
    for (std::string_view tok = next_token(t, pos); !tok.empty(); tok = next_token(t, pos)) {
      const int column = offset + static_cast<int>(pos - tok.size());
      // v, v/vt, v//vn, v/vt/vn: empty parts are absent (the vertex is not).
      std::string_view part = tok;
      for (int k = 0; k < 3; ++k) {
        const size_t slash = part.find('/');
        const std::string_view index_text = part.substr(0, slash);
        if (k == 0 || !index_text.empty()) {
          const auto i = parse_index(index_text);
          if (!i) {
            const std::string_view digits = index_text.substr(index_text.starts_with('-') ? 1 : 0);
            const bool too_long = !digits.empty() && digits.find_first_not_of("0123456789") == std::string_view::npos;
            return {lines.number(), column,
                    std::string(kIndexNames[k]) + " index '" + std::string(index_text) + "'" +
                        (too_long ? " out of range" : " is not a whole number")};
          }
          if (*i == 0)
            return {lines.number(), column,
                    std::string(kIndexNames[k]) + " index of 0 (OBJ counts from 1, or back from -1)"};
          const int64_t resolved = *i > 0 ? *i - 1 : counts[k] + *i;
          if (resolved < 0 || resolved >= counts[k])
            return {lines.number(), column,
                    std::string(kIndexNames[k]) + " index " + std::string(index_text) + " out of range (" +
                        (counts[k] == 1 ? "1 " + std::string(kIndexNames[k]) : std::to_string(counts[k]) + " " + kPlural[k]) +
                        (*i < 0 ? " before it)" : ")")};
        }
        if (slash == std::string_view::npos) break;
        part = part.substr(slash + 1);
        if (k == 2) break;
      }
    }
  }
  return {};
}

// The vertex count of every face with at least 3, in file order (what
// tinyobjloader keeps, before its 8-bit count wraps above 255).
std::vector<size_t> scan_obj_face_sizes(std::string_view text) {
  std::vector<size_t> sizes;
  LineCursor lines(text);
  std::string_view line;
  while (lines.next(line)) {
    const std::string_view t = skip_blanks(line);
    if (t.size() < 2 || t[0] != 'f' || !is_blank(t[1])) continue;
    const size_t n = tokens_of(t.substr(1)).size();
    if (n >= 3) sizes.push_back(n);
  }
  return sizes;
}

// "... line 12.)" in tinyobjloader's messages.
int line_in_message(const std::string& message) {
  const size_t pos = message.rfind("line ");
  if (pos == std::string::npos) return 0;
  int line = 0;
  std::from_chars(message.data() + pos + 5, message.data() + message.size(), line);
  return line;
}

size_t count_occurrences(const std::string& text, std::string_view what) {
  size_t n = 0;
  for (size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + what.size())) ++n;
  return n;
}

// UTF-16 text (with a byte-order mark) to UTF-8, as some exporters write OBJ.
std::string utf16_to_utf8(std::string_view bytes, bool big_endian) {
  std::string out;
  out.reserve(bytes.size() / 2);
  for (size_t i = 2; i + 1 < bytes.size(); i += 2) {
    const auto b0 = static_cast<unsigned char>(bytes[i]), b1 = static_cast<unsigned char>(bytes[i + 1]);
    unsigned c = big_endian ? (b0 << 8 | b1) : (b1 << 8 | b0);
    if (c >= 0xD800 && c <= 0xDFFF) c = '?';  // no astral planes in mesh files
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

MeshFile load_obj(const fs::path& path, const std::string& file, std::vector<unsigned char> bytes, size_t budget,
                  bool vertex_normals) {
  std::string converted;
  std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (text.size() >= 2 && (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF")) {
    converted = utf16_to_utf8(text, text[0] == '\xFE');
    text = converted;
  } else if (text.substr(0, 3) == "\xEF\xBB\xBF") {
    text.remove_prefix(3);
  }
  if (text.find('\0') != std::string_view::npos) fail(file, "not a Wavefront OBJ file (binary content)");
  if (text.find_first_not_of(" \t\r\n\v\f") == std::string_view::npos) fail(file, "empty file");
  // glint's own checks of the text (numbers tinyobjloader would misread,
  // non-finite coordinates) run beside tinyobjloader's parse: both only read
  // the text, and loading is otherwise single-threaded (the checks are about
  // a tenth of a 1M-triangle load). Their verdict comes first.
  TextProblem bad_statement;
  std::vector<BadVertexText> bad_vertex_text;
  std::jthread checks([&] {
    bad_statement = find_obj_bad_statement(text);
    if (bad_statement.line == 0) bad_vertex_text = scan_obj_nonfinite_text(text);
  });

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  MtlReader mtl_reader(path.parent_path());
  {
    MemoryStreambuf buffer(text.data(), text.size());
    std::istream in(&buffer);
    const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, &mtl_reader,
                                     /*triangulate=*/false, /*default_vcols_fallback=*/false);
    checks.join();
    if (bad_statement.line > 0) fail(file, bad_statement.message, bad_statement.line, bad_statement.column);
    if (!ok) {
      const std::string first = err.substr(0, err.find('\n'));
      const int line = line_in_message(first);
      if (first.find("`f'") != std::string::npos)
        fail(file, "face with a vertex index of 0 or not a number", line);
      if (first.find("`l'") != std::string::npos || first.find("`p'") != std::string::npos)
        fail(file, "line or point with a vertex index of 0 or not a number", line);
      fail(file, "cannot read OBJ: " + (first.empty() ? std::string("unknown error") : first), line);
    }
  }
  if (mtl_reader.error)  // at the .mtl's line; the message names the OBJ that uses it
    throw Error(mtl_reader.error->location(), mtl_reader.error->message() + " (material library of " + file + ")");
  // bytes and converted stay alive: error paths below scan the text again.

  RawMesh raw;
  raw.positions.resize(attrib.vertices.size() / 3);
  for (size_t v = 0; v < raw.positions.size(); ++v)
    raw.positions[v] = {attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]};
  const size_t normal_count = attrib.normals.size() / 3;
  const size_t texcoord_count = attrib.texcoords.size() / 2;
  raw.bad_vertex_text = std::move(bad_vertex_text);
  raw.nonfinite_vertex_error = [&](uint32_t v) {
    return Error(SourceLocation{file, find_obj_statement(text, "v", v), 0},
                 "vertex coordinate is not a finite number (out of float range)");
  };

  // tinyobjloader keeps a face's vertex count in 8 bits: recover larger ones
  // from the text when the counts do not add up.
  size_t stored_corners = 0, face_total = 0;
  for (const auto& s : shapes) {
    for (unsigned char n : s.mesh.num_face_vertices) stored_corners += n;
    face_total += s.mesh.num_face_vertices.size();
  }
  size_t index_total = 0;
  for (const auto& s : shapes) index_total += s.mesh.indices.size();
  std::vector<size_t> true_sizes;
  if (stored_corners != index_total) {
    true_sizes = scan_obj_face_sizes(text);
    size_t sum = 0;
    for (size_t n : true_sizes) sum += n;
    if (true_sizes.size() != face_total || sum != index_total)
      fail(file, "cannot match polygons with more than 255 vertices to the faces read");
  }

  {
    // Polygons of n corners make n - 2 triangles (8-bit counts wrap, so at most an estimate).
    size_t estimate = 0;
    for (const auto& s : shapes)
      for (unsigned char n : s.mesh.num_face_vertices) estimate += n >= 3 ? n - 2 : 0;
    // OBJ states no counts, but text is dense: "f 1 2 3 4 ..." makes a
    // triangle per 2 bytes, 50 times that in memory. Checked once the
    // library's compact arrays are read, before the large ones are made.
    const std::string excess = exceeds_budget(
        kBytesPerTriangle * double(estimate) + kBytesPerVertex * double(attrib.vertices.size() / 3), budget);
    if (!excess.empty()) fail(file, plural(estimate, "triangle", "triangles") + " (about): that " + excess);
    raw.indices.reserve(3 * estimate);
    raw.normals.reserve(3 * estimate);
    raw.triangle_material.reserve(estimate);
  }
  size_t face_ordinal = 0;
  bool bad_index = false;
  for (const auto& s : shapes) {
    const auto& m = s.mesh;
    size_t offset = 0;
    for (size_t f = 0; f < m.num_face_vertices.size(); ++f, ++face_ordinal) {
      const size_t n = true_sizes.empty() ? m.num_face_vertices[f] : true_sizes[face_ordinal];
      if (offset + n > m.indices.size()) fail(file, "inconsistent face data from the OBJ reader");
      const tinyobj::index_t* corner = &m.indices[offset];
      offset += n;
      bool corners_ok = true;
      for (size_t k = 0; k < n; ++k) {
        const int vi = corner[k].vertex_index, ni = corner[k].normal_index, ti = corner[k].texcoord_index;
        if (vi < 0 || static_cast<size_t>(vi) >= raw.positions.size()) corners_ok = false;
        if (ni < -1 || (ni >= 0 && static_cast<size_t>(ni) >= normal_count)) corners_ok = false;
        if (ti < -1 || (ti >= 0 && static_cast<size_t>(ti) >= texcoord_count)) corners_ok = false;
      }
      if (!corners_ok) {
        bad_index = true;
        break;
      }
      const int32_t material = f < m.material_ids.size() ? m.material_ids[f] : -1;
      triangulate(
          n, [&](size_t k) { return raw.positions[corner[k].vertex_index]; },
          [&](size_t a, size_t b, size_t c) {
            for (size_t k : {a, b, c}) {
              raw.indices.push_back(static_cast<uint32_t>(corner[k].vertex_index));
              const int ni = corner[k].normal_index;
              raw.normals.push_back(ni >= 0 ? Vec3f{attrib.normals[3 * ni], attrib.normals[3 * ni + 1],
                                                    attrib.normals[3 * ni + 2]}
                                            : Vec3f{});
              if (ni >= 0) raw.has_normals = true;
              const int ti = corner[k].texcoord_index;
              raw.uvs.push_back(ti >= 0 ? UVf{attrib.texcoords[2 * ti], attrib.texcoords[2 * ti + 1]} : UVf{});
              if (ti >= 0) raw.has_uvs = true;
            }
            raw.triangle_material.push_back(material >= 0 && static_cast<size_t>(material) < materials.size()
                                                ? material
                                                : -1);
          });
    }
    if (bad_index) break;
    raw.non_faces += s.lines.num_line_vertices.size() + s.points.indices.size();
  }
  if (bad_index) {
    fail(file, "face index out of range");  // find_obj_bad_statement found none: tinyobjloader disagrees
  }
  if (!raw.has_normals) raw.normals.clear();
  if (!raw.has_uvs) raw.uvs.clear();
  raw.small_faces = count_occurrences(warn, "Degenerated face found");
  if (raw.positions.empty() && raw.indices.empty() && raw.non_faces == 0)
    fail(file, "no vertices or faces: not a Wavefront OBJ file");

  // Materials, and what went wrong with them: one warning per kind per file.
  for (const std::string& name : mtl_reader.missing)
    raw.warnings.push_back(file + ": material library '" + name + "' not found (default materials used)");
  {
    std::vector<std::string> unknown;
    for (size_t pos = warn.find("material [ '"); pos != std::string::npos; pos = warn.find("material [ '", pos + 1)) {
      const size_t start = pos + 12, end = warn.find("' ]", start);
      if (end == std::string::npos) break;
      std::string name = warn.substr(start, end - start);
      if (std::find(unknown.begin(), unknown.end(), name) == unknown.end()) unknown.push_back(name);
    }
    if (!unknown.empty() && mtl_reader.missing.empty())
      raw.warnings.push_back(file + ": usemtl " + name_list(unknown) +
                             " not in the material library (default material used)");
  }
  std::map<fs::path, MtlReport> reports;
  std::vector<fs::path> report_order;
  for (size_t i = 0; i < materials.size(); ++i) {
    const bool known = i < mtl_reader.origin.size();
    const fs::path mtl = known ? mtl_reader.origin[i].mtl : fs::path(file);
    if (!reports.count(mtl)) report_order.push_back(mtl);
    MtlReport& report = reports[mtl];
    MtlBlock block;
    if (known) block = mtl_reader.origin[i].block;
    raw.materials.push_back(map_mtl(materials[i], block, report));
    const auto& t = materials[i];
    // map_Ka / map_Kd / map_Ks that exist become the material's textures (the
    // missing ones are reported below and the colors stay).
    const std::pair<const tinyobj::texture_option_t*, uint32_t*> maps[] = {
        {&t.ambient_texopt, &raw.materials.back().ambient_texture},
        {&t.diffuse_texopt, &raw.materials.back().diffuse_texture},
        {&t.specular_texopt, &raw.materials.back().specular_texture}};
    const std::string* map_names[] = {&t.ambient_texname, &t.diffuse_texname, &t.specular_texname};
    for (size_t k = 0; k < 3; ++k) {
      if (map_names[k]->empty()) continue;
      std::string relative = *map_names[k];
      std::replace(relative.begin(), relative.end(), '\\', '/');
      std::error_code ec;
      const fs::path texture_file = mtl.parent_path() / relative;
      if (!fs::is_regular_file(texture_file, ec)) continue;
      const tinyobj::texture_option_t& o = *maps[k].first;
      MeshTexture mt;
      mt.file = texture_file;
      mt.name = *map_names[k];
      mt.named_by = mtl.string();
      mt.wrap = o.clamp ? TextureWrap::clamp : TextureWrap::repeat;
      mt.scale_u = o.scale[0];
      mt.scale_v = o.scale[1];
      mt.offset_u = o.origin_offset[0];
      mt.offset_v = o.origin_offset[1];
      *maps[k].second = static_cast<uint32_t>(raw.textures.size());
      raw.textures.push_back(std::move(mt));
    }
    for (const std::string* tex :
         {&t.ambient_texname, &t.diffuse_texname, &t.specular_texname, &t.specular_highlight_texname,
          &t.bump_texname, &t.displacement_texname, &t.alpha_texname, &t.reflection_texname,
          &t.roughness_texname, &t.metallic_texname, &t.sheen_texname, &t.emissive_texname,
          &t.normal_texname}) {
      if (tex->empty()) continue;
      std::string relative = *tex;  // Windows exporters write '\\'
      std::replace(relative.begin(), relative.end(), '\\', '/');
      std::error_code ec;
      if (!fs::exists(mtl.parent_path() / relative, ec) &&
          std::find(report.missing_textures.begin(), report.missing_textures.end(), *tex) ==
              report.missing_textures.end())
        report.missing_textures.push_back(*tex);
    }
  }
  for (const fs::path& mtl : report_order) {
    const MtlReport& r = reports[mtl];
    const std::string name = mtl.string();
    if (r.ns_below_one > 0)
      raw.warnings.push_back(with_line(name, r.ns_line) + ": Ns below 1 read as 1 (" +
                             plural(r.ns_below_one, "material", "materials") + ")");
    if (r.illum_8_to_10 > 0)
      raw.warnings.push_back(with_line(name, r.illum_line) +
                             ": illum 8, 9, 10 read as 2, 4, 1: no reflection maps, no shadow matte (" +
                             plural(r.illum_8_to_10, "material", "materials") + ")");
    if (r.illum_unknown > 0)
      raw.warnings.push_back(with_line(name, r.illum_unknown_line) + ": illum outside 0..10 read as 2 (" +
                             plural(r.illum_unknown, "material", "materials") + ")");
    if (!r.missing_textures.empty())
      raw.warnings.push_back(name + ": " +
                             plural(r.missing_textures.size(), "texture file", "texture files") +
                             " not found (defaults used): " + name_list(r.missing_textures));
  }
  return finish(std::move(raw), file, vertex_normals);
}

// ---------------------------------------------------------------------------
// PLY: header and structure checked here, data read by assimp
// ---------------------------------------------------------------------------

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

std::optional<PlyType> ply_type(std::string_view name) {
  static const std::pair<std::string_view, PlyType> kTypes[] = {
      {"char", PlyType::i8},    {"int8", PlyType::i8},     {"uchar", PlyType::u8},   {"uint8", PlyType::u8},
      {"short", PlyType::i16},  {"int16", PlyType::i16},   {"ushort", PlyType::u16}, {"uint16", PlyType::u16},
      {"int", PlyType::i32},    {"int32", PlyType::i32},   {"uint", PlyType::u32},   {"uint32", PlyType::u32},
      {"float", PlyType::f32},  {"float32", PlyType::f32}, {"double", PlyType::f64}, {"float64", PlyType::f64}};
  for (const auto& [n, t] : kTypes)
    if (n == name) return t;
  return std::nullopt;
}
size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
  }
  return 1;
}
bool ply_is_float(PlyType t) { return t == PlyType::f32 || t == PlyType::f64; }

struct PlyProperty {
  std::string name;
  bool list = false;
  PlyType type = PlyType::f32;        // scalar, or list items
  PlyType count_type = PlyType::u8;   // list
};
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  int line = 0;
  std::vector<PlyProperty> properties;
};
enum class PlyFormat { ascii, binary_le, binary_be };
struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  size_t body = 0;       // byte offset of the data
  int body_line = 0;     // line number of the data's first line
  size_t unknown_lines = 0;
  int unknown_line = 0;  // the first
};

PlyHeader read_ply_header(std::string_view data, const std::string& file) {
  PlyHeader h;
  LineCursor lines(data.substr(0, std::min<size_t>(data.size(), size_t(1) << 20)));
  std::string_view line;
  if (!lines.next(line) || lower(std::string(tokens_of(line).empty() ? "" : tokens_of(line)[0].text)) != "ply")
    fail(file, "not a PLY file (it does not start with 'ply')");
  bool have_format = false;
  for (;;) {
    if (!lines.next(line)) fail(file, "PLY header has no end_header line (in its first MiB)");
    const int n = lines.number();
    const std::vector<Token> tok = tokens_of(line);
    if (tok.empty()) continue;
    const std::string_view key = tok[0].text;
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") {
      // The data starts after this line's terminator.
      const size_t end = static_cast<size_t>(line.data() - data.data()) + line.size();
      size_t body = end;
      if (body < data.size() && data[body] == '\r') ++body;
      if (body < data.size() && data[body] == '\n') ++body;
      h.body = body;
      h.body_line = n + 1;
      break;
    }
    if (key == "format") {
      // A second format line is ambiguous (and trips assimp): refuse it.
      if (have_format) fail(file, "PLY header has more than one format line", n);
      if (tok.size() < 2) fail(file, "PLY format line needs a format name", n);
      if (tok[1].text == "ascii") h.format = PlyFormat::ascii;
      else if (tok[1].text == "binary_little_endian") h.format = PlyFormat::binary_le;
      else if (tok[1].text == "binary_big_endian") h.format = PlyFormat::binary_be;
      else fail(file, "unknown PLY format '" + std::string(tok[1].text) + "'", n, tok[1].column);
      have_format = true;
    } else if (key == "element") {
      if (tok.size() != 3) fail(file, "PLY element line must be 'element <name> <count>'", n);
      const auto count = parse_integer(tok[2].text);
      if (!count || *count < 0)
        fail(file, "bad PLY element count '" + std::string(tok[2].text) + "'", n, tok[2].column);
      // assimp leaks on a repeated element (found by fuzz_mesh_ply), and
      // which of two 'face' lists would be meant is anyone's guess.
      for (const PlyElement& el : h.elements)
        if (el.name == tok[1].text)
          fail(file, "PLY element '" + el.name + "' declared twice (first on line " + std::to_string(el.line) + ")", n,
               tok[1].column);
      h.elements.push_back({std::string(tok[1].text), static_cast<uint64_t>(*count), n, {}});
    } else if (key == "property") {
      if (h.elements.empty()) fail(file, "PLY property before any element", n);
      PlyProperty p;
      if (tok.size() >= 2 && tok[1].text == "list") {
        if (tok.size() != 5) fail(file, "PLY list property must be 'property list <count type> <type> <name>'", n);
        const auto ct = ply_type(tok[2].text), it = ply_type(tok[3].text);
        if (!ct || ply_is_float(*ct))
          fail(file, "bad PLY list count type '" + std::string(tok[2].text) + "'", n, tok[2].column);
        if (!it) fail(file, "unknown PLY type '" + std::string(tok[3].text) + "'", n, tok[3].column);
        p.list = true;
        p.count_type = *ct;
        p.type = *it;
        p.name = std::string(tok[4].text);
      } else {
        if (tok.size() != 3) fail(file, "PLY property must be 'property <type> <name>'", n);
        const auto t = ply_type(tok[1].text);
        if (!t) fail(file, "unknown PLY type '" + std::string(tok[1].text) + "'", n, tok[1].column);
        p.type = *t;
        p.name = std::string(tok[2].text);
      }
      h.elements.back().properties.push_back(std::move(p));
    } else {
      // Some exporters write a comment without the keyword; assimp skips it too.
      ++h.unknown_lines;
      if (h.unknown_line == 0) h.unknown_line = n;
    }
  }
  if (!have_format) fail(file, "PLY header has no format line");
  return h;
}

// Which element is the vertex list and which list property holds face indices.
struct PlyLayout {
  int vertex = -1, face = -1, face_list = -1;
  int xyz[3] = {-1, -1, -1};  // property numbers in the vertex element
};

PlyLayout ply_layout(const PlyHeader& h, const std::string& file) {
  PlyLayout l;
  for (size_t e = 0; e < h.elements.size(); ++e) {
    const PlyElement& el = h.elements[e];
    if (el.name == "vertex" && l.vertex < 0) l.vertex = static_cast<int>(e);
    if (el.name == "face" && l.face < 0) {
      l.face = static_cast<int>(e);
      for (size_t p = 0; p < el.properties.size(); ++p) {
        const PlyProperty& prop = el.properties[p];
        const bool indices = prop.name == "vertex_indices" || prop.name == "vertex_index";
        if (prop.list && indices) l.face_list = static_cast<int>(p);
      }
    }
  }
  if (l.vertex < 0) fail(file, "PLY file has no vertex element");
  const PlyElement& v = h.elements[l.vertex];
  for (size_t p = 0; p < v.properties.size(); ++p)
    for (int a = 0; a < 3; ++a)
      if (v.properties[p].name == std::string(1, char('x' + a)) && !v.properties[p].list)
        l.xyz[a] = static_cast<int>(p);
  if (l.xyz[0] < 0 || l.xyz[1] < 0 || l.xyz[2] < 0) fail(file, "PLY vertex element has no x, y, z properties", v.line);
  if (l.face >= 0 && l.face_list < 0)
    fail(file, "PLY face element has no vertex_indices list", h.elements[l.face].line);
  return l;
}

// Absurd counts: every record takes at least some bytes, so a count larger
// than the data allows is refused before anything is allocated for it.
void check_ply_counts(const PlyHeader& h, size_t data_bytes, const std::string& file) {
  for (const PlyElement& el : h.elements) {
    size_t min_bytes = 0;
    for (const PlyProperty& p : el.properties) {
      if (h.format == PlyFormat::ascii) min_bytes += 2;  // a digit and a separator
      else min_bytes += p.list ? ply_size(p.count_type) : ply_size(p.type);
    }
    min_bytes = std::max<size_t>(min_bytes, 1);
    if (el.count > (data_bytes + 1) / min_bytes)
      fail(file,
           "truncated or corrupt: the header claims " + std::to_string(el.count) + " '" + el.name +
               "' elements but only " + plural(data_bytes, "byte", "bytes") + " of data follow",
           el.line);
  }
}

// What the header's counts would take in memory once read (at least one
// triangle per face), refused before assimp allocates anything for them.
void check_ply_memory(const PlyHeader& h, const PlyLayout& l, size_t budget, const std::string& file) {
  const PlyElement& vertex = h.elements[l.vertex];
  const uint64_t faces = l.face >= 0 ? h.elements[l.face].count : 0;
  const double vertex_bytes = kBytesPerVertex * static_cast<double>(vertex.count);
  const double face_bytes = kBytesPerTriangle * static_cast<double>(faces);
  const std::string excess = exceeds_budget(vertex_bytes + face_bytes, budget);
  if (excess.empty()) return;
  const int line = face_bytes > vertex_bytes ? h.elements[l.face].line : vertex.line;
  fail(file,
       "the header claims " + plural(vertex.count, "vertex", "vertices") + " and " + plural(faces, "face", "faces") +
           ": that " + excess,
       line);
}

uint64_t read_binary_uint(const unsigned char* p, size_t size, bool big_endian) {
  uint64_t v = 0;
  for (size_t i = 0; i < size; ++i) v |= uint64_t(p[big_endian ? i : size - 1 - i]) << (8 * (size - 1 - i));
  return v;
}
// A binary integer of this type as a signed 64-bit value.
int64_t read_binary_int(const unsigned char* p, PlyType t, bool big_endian) {
  const size_t size = ply_size(t);
  const uint64_t u = read_binary_uint(p, size, big_endian);
  switch (t) {
    case PlyType::i8: return static_cast<int8_t>(u);
    case PlyType::i16: return static_cast<int16_t>(u);
    case PlyType::i32: return static_cast<int32_t>(u);
    case PlyType::f32: case PlyType::f64: return 0;
    default: return static_cast<int64_t>(u);
  }
}

std::string ply_face_problem(uint64_t face, int64_t index, uint64_t vertices) {
  return "face " + std::to_string(face) + ": vertex index " + std::to_string(index) + " out of range (" +
         plural(vertices, "vertex", "vertices") + ")";
}

// Walks the binary data record by record: every record present, list counts
// sane, face indices in range. Nothing is stored.
void walk_binary_ply(const PlyHeader& h, const PlyLayout& l, std::string_view data, const std::string& file) {
  const bool be = h.format == PlyFormat::binary_be;
  const auto* p = reinterpret_cast<const unsigned char*>(data.data()) + h.body;
  const auto* end = reinterpret_cast<const unsigned char*>(data.data()) + data.size();
  const uint64_t vertices = h.elements[l.vertex].count;
  for (size_t e = 0; e < h.elements.size(); ++e) {
    const PlyElement& el = h.elements[e];
    auto truncated = [&](uint64_t r) {
      fail(file, "truncated: the header promises " + std::to_string(el.count) + " '" + el.name +
                     "' elements but the data ends in number " + std::to_string(r));
    };
    size_t fixed = 0;
    bool has_list = false;
    for (const PlyProperty& prop : el.properties) {
      if (prop.list) has_list = true;
      else fixed += ply_size(prop.type);
    }
    if (!has_list) {  // fixed-size records: one check for all
      const uint64_t fit = fixed > 0 ? static_cast<uint64_t>(end - p) / fixed : el.count;
      if (fit < el.count) truncated(fit);
      p += fixed * el.count;
      continue;
    }
    for (uint64_t r = 0; r < el.count; ++r) {
      for (size_t k = 0; k < el.properties.size(); ++k) {
        const PlyProperty& prop = el.properties[k];
        if (!prop.list) {
          if (static_cast<size_t>(end - p) < ply_size(prop.type)) truncated(r);
          p += ply_size(prop.type);
          continue;
        }
        const size_t cs = ply_size(prop.count_type), is = ply_size(prop.type);
        if (static_cast<size_t>(end - p) < cs) truncated(r);
        const int64_t n = read_binary_int(p, prop.count_type, be);
        p += cs;
        if (n < 0) fail(file, el.name + " " + std::to_string(r) + ": negative list length " + std::to_string(n));
        if (static_cast<uint64_t>(end - p) / is < static_cast<uint64_t>(n)) truncated(r);
        if (static_cast<int>(e) == l.face && static_cast<int>(k) == l.face_list) {
          for (int64_t i = 0; i < n; ++i) {
            const int64_t index = ply_is_float(prop.type) ? -1 : read_binary_int(p + i * is, prop.type, be);
            if (index < 0 || static_cast<uint64_t>(index) >= vertices) fail(file, ply_face_problem(r, index, vertices));
          }
        }
        p += static_cast<size_t>(n) * is;
      }
    }
  }
}

// Walks the ASCII data: one record per line (blank lines skipped, as assimp
// does), every value a number of its type, face indices in range. Records
// non-finite x/y/z text with its line for the back end.
void walk_ascii_ply(const PlyHeader& h, const PlyLayout& l, std::string_view data, const std::string& file,
                    std::vector<BadVertexText>& bad) {
  LineCursor lines(data.substr(h.body));
  const int first_line = h.body_line - 1;
  std::string_view line;
  const uint64_t vertices = h.elements[l.vertex].count;
  for (size_t e = 0; e < h.elements.size(); ++e) {
    const PlyElement& el = h.elements[e];
    for (uint64_t r = 0; r < el.count; ++r) {
      std::vector<Token> tok;
      do {
        if (!lines.next(line))
          fail(file, "truncated: the header promises " + std::to_string(el.count) + " '" + el.name +
                         "' elements but the file ends after " + std::to_string(r));
        tok = tokens_of(line);
      } while (tok.empty());
      const int n = first_line + lines.number();
      size_t t = 0;
      auto need = [&](const char* what) -> const Token& {
        if (t >= tok.size())
          fail(file, el.name + " " + std::to_string(r) + ": too few values on the line (missing " + what + ")", n);
        return tok[t++];
      };
      for (size_t k = 0; k < el.properties.size(); ++k) {
        const PlyProperty& prop = el.properties[k];
        auto check_value = [&](const Token& v, PlyType type) -> int64_t {
          if (ply_is_float(type)) {
            const auto x = parse_number(v.text);
            if (!x) fail(file, "'" + std::string(v.text) + "' is not a number", n, v.column);
            // A float property beyond float range reads as infinity.
            const bool finite = type == PlyType::f32 ? std::abs(*x) <= FLT_MAX : std::isfinite(*x);
            if (!finite && static_cast<int>(e) == l.vertex &&
                (static_cast<int>(k) == l.xyz[0] || static_cast<int>(k) == l.xyz[1] || static_cast<int>(k) == l.xyz[2]))
              bad.push_back({static_cast<uint32_t>(r), n, v.column, std::string(v.text)});
            return 0;
          }
          const auto i = parse_integer(v.text);
          if (!i) fail(file, "'" + std::string(v.text) + "' is not an integer", n, v.column);
          return *i;
        };
        if (!prop.list) {
          check_value(need(prop.name.c_str()), prop.type);
          continue;
        }
        const Token& count_token = need("a list length");
        const int64_t count = check_value(count_token, prop.count_type);
        if (count < 0 || static_cast<uint64_t>(count) > tok.size() - t)
          fail(file, el.name + " " + std::to_string(r) + ": list length " + std::to_string(count) +
                         " does not match the values on the line", n, count_token.column);
        const bool indices = static_cast<int>(e) == l.face && static_cast<int>(k) == l.face_list;
        for (int64_t i = 0; i < count; ++i) {
          const Token& v = tok[t++];
          const int64_t index = check_value(v, prop.type);
          if (indices && (ply_is_float(prop.type) || index < 0 || static_cast<uint64_t>(index) >= vertices))
            fail(file, "vertex index " + std::string(v.text) + " out of range (" +
                           plural(vertices, "vertex", "vertices") + ")", n, v.column);
        }
      }
      // One record per line: assimp reads the values as one stream, so
      // anything extra shifts every later value (and made it leak on the
      // garbage it then met: fuzz_mesh_ply).
      if (t < tok.size())
        fail(file, el.name + " " + std::to_string(r) + ": more values on the line than the header declares", n,
             tok[t].column);
    }
  }
}

// ---------------------------------------------------------------------------
// assimp scenes (PLY, glTF) -> RawMesh
// ---------------------------------------------------------------------------

constexpr size_t kMaxTriangles = size_t(1) << 28;  // after glTF instancing: ~14 GiB of MeshFile

Material map_assimp_material(const aiMaterial& a) {
  Material m;
  aiString name;
  if (a.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
  aiColor4D c;
  if (aiGetMaterialColor(&a, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS) m.diffuse = Color(c.r, c.g, c.b);
  return m;
}

// PLY faces with fewer than 3 vertices are skipped with a warning; glTF
// point and line primitives are simply not surfaces.
void from_assimp(const aiScene& scene, const std::string& file, const fs::path& folder, bool is_ply,
                 size_t budget, RawMesh& raw) {
  const bool use_materials = !is_ply;
  // Mesh instances with their node transforms (glTF scenes place and reuse meshes).
  struct Instance {
    unsigned mesh;
    aiMatrix4x4 transform;
  };
  std::vector<Instance> instances;
  size_t triangles = 0;
  double vertices = 0;
  if (scene.mRootNode) {
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{scene.mRootNode, scene.mRootNode->mTransformation}};
    size_t visits = 0;
    while (!stack.empty()) {
      auto [node, m] = stack.back();
      stack.pop_back();
      if (++visits > 1'000'000) fail(file, "scene graph too large (more than a million nodes)");
      for (unsigned i = 0; i < node->mNumMeshes; ++i) {
        const unsigned mi = node->mMeshes[i];
        if (mi >= scene.mNumMeshes || !scene.mMeshes[mi]) continue;
        triangles += scene.mMeshes[mi]->mNumFaces;
        vertices += scene.mMeshes[mi]->mNumVertices;
        if (triangles > kMaxTriangles) fail(file, "too many triangles after instancing");
        instances.push_back({mi, m});
      }
      for (unsigned i = 0; i < node->mNumChildren; ++i)
        if (node->mChildren[i]) stack.push_back({node->mChildren[i], m * node->mChildren[i]->mTransformation});
    }
  }
  if (instances.empty())
    for (unsigned i = 0; i < scene.mNumMeshes; ++i)
      if (scene.mMeshes[i]) {
        instances.push_back({i, aiMatrix4x4()});
        triangles += scene.mMeshes[i]->mNumFaces;
        vertices += scene.mMeshes[i]->mNumVertices;
      }
  // Every instance gets its own copy of the mesh: a few nodes can multiply a
  // small mesh beyond memory.
  const std::string excess =
      exceeds_budget(kBytesPerTriangle * static_cast<double>(triangles) + kBytesPerVertex * vertices, budget);
  if (!excess.empty())
    fail(file, plural(triangles, "triangle", "triangles") + " after instancing: that " + excess);
  raw.indices.reserve(3 * triangles);  // exact for triangle meshes
  raw.normals.reserve(3 * triangles);
  raw.triangle_material.reserve(triangles);

  if (use_materials) {
    for (unsigned i = 0; i < scene.mNumMaterials; ++i) {
      const aiMaterial* a = scene.mMaterials[i];
      raw.materials.push_back(a ? map_assimp_material(*a) : Material{});
      if (!a) continue;
      std::vector<std::string> missing;
      for (aiTextureType type : {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR, aiTextureType_SPECULAR,
                                 aiTextureType_NORMALS, aiTextureType_EMISSIVE}) {
        for (unsigned k = 0; k < a->GetTextureCount(type); ++k) {
          aiString tex;
          if (a->GetTexture(type, k, &tex) != AI_SUCCESS) continue;
          const std::string t = tex.C_Str();
          if (t.empty() || t[0] == '*' || t.rfind("data:", 0) == 0) continue;  // embedded
          std::error_code ec;
          if (!fs::exists(folder / t, ec) && std::find(missing.begin(), missing.end(), t) == missing.end())
            missing.push_back(t);
        }
      }
      if (!missing.empty())
        raw.warnings.push_back(file + ": " + plural(missing.size(), "texture file", "texture files") +
                               " not found (defaults used): " + name_list(missing));
      // The base color texture, when it is a file beside the mesh, becomes the diffuse texture.
      for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
        aiString tex;
        aiTextureMapMode mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
        if (a->GetTextureCount(type) == 0 || a->GetTexture(type, 0, &tex) != AI_SUCCESS) continue;
        const std::string t = tex.C_Str();
        std::error_code ec;
        if (t.empty() || t[0] == '*' || t.rfind("data:", 0) == 0 || !fs::is_regular_file(folder / t, ec)) break;
        a->Get(AI_MATKEY_MAPPINGMODE_U(type, 0), mode[0]);
        MeshTexture mt;
        mt.file = folder / t;
        mt.name = t;
        mt.named_by = file;
        // One wrap mode for both directions: u's (glTF samplers rarely differ).
        mt.wrap = mode[0] == aiTextureMapMode_Clamp    ? TextureWrap::clamp
                  : mode[0] == aiTextureMapMode_Mirror ? TextureWrap::mirror
                                                       : TextureWrap::repeat;
        raw.materials.back().diffuse_texture = static_cast<uint32_t>(raw.textures.size());
        raw.textures.push_back(std::move(mt));
        break;
      }
    }
  }

  struct Range {
    size_t first;
    unsigned mesh;
  };
  std::vector<Range> ranges;
  for (const Instance& inst : instances) {
    const aiMesh& mesh = *scene.mMeshes[inst.mesh];
    const size_t base = raw.positions.size();
    if (base + mesh.mNumVertices > UINT32_MAX) fail(file, "too many vertices (more than 2^32)");
    if (!mesh.mVertices && mesh.mNumVertices > 0) continue;
    ranges.push_back({base, inst.mesh});
    const bool identity = inst.transform.IsIdentity();
    aiMatrix3x3 normal_matrix(inst.transform);
    normal_matrix.Inverse().Transpose();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      aiVector3D p = mesh.mVertices[v];
      if (!identity) p = inst.transform * p;
      raw.positions.push_back({p.x, p.y, p.z});
    }
    const bool normals = mesh.mNormals != nullptr;
    const aiVector3D* uvs = mesh.HasTextureCoords(0) ? mesh.mTextureCoords[0] : nullptr;
    const int32_t material =
        use_materials && mesh.mMaterialIndex < raw.materials.size() ? static_cast<int32_t>(mesh.mMaterialIndex) : -1;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices < 3) {
        ++(is_ply ? raw.small_faces : raw.non_faces);
        continue;
      }
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= mesh.mNumVertices)
          fail(file, "mesh " + std::to_string(inst.mesh) + ", face " + std::to_string(f) + ": vertex index " +
                         std::to_string(face.mIndices[k]) + " out of range (" +
                         plural(mesh.mNumVertices, "vertex", "vertices") + ")");
      triangulate(
          face.mNumIndices, [&](size_t k) { return raw.positions[base + face.mIndices[k]]; },
          [&](size_t a, size_t b, size_t c) {
            for (size_t k : {a, b, c}) {
              const unsigned v = face.mIndices[k];
              raw.indices.push_back(static_cast<uint32_t>(base + v));
              if (normals) {
                aiVector3D n = mesh.mNormals[v];
                if (!identity) n = normal_matrix * n;
                raw.normals.push_back({n.x, n.y, n.z});
              } else {
                raw.normals.push_back({});
              }
              raw.uvs.push_back(uvs ? UVf{uvs[v].x, uvs[v].y} : UVf{});
            }
            raw.triangle_material.push_back(material);
          });
      if (normals) raw.has_normals = true;
      if (uvs) raw.has_uvs = true;
    }
  }
  if (!raw.has_normals) raw.normals.clear();
  if (!raw.has_uvs) raw.uvs.clear();
  raw.nonfinite_vertex_error = [file, ranges, &scene](uint32_t v) {
    auto it = std::upper_bound(ranges.begin(), ranges.end(), size_t(v),
                               [](size_t x, const Range& r) { return x < r.first; });
    std::string where = "vertex " + std::to_string(v);
    if (it != ranges.begin()) {
      --it;
      const aiMesh* mesh = scene.mMeshes[it->mesh];
      where = "vertex " + std::to_string(v - it->first);
      if (scene.mNumMeshes > 1)
        where = "mesh " + std::to_string(it->mesh) + " ('" + std::string(mesh->mName.C_Str()) + "'), " + where;
    }
    return Error(SourceLocation{file, 0, 0}, where + " has a non-finite coordinate");
  };
}

// assimp reports some repairs only in its log (e.g. glTF faces with
// out-of-range indices are dropped): capture its warnings while it reads.
// Its logger is global, so assimp reads are serialized.
class AssimpLogCapture {
 public:
  AssimpLogCapture() : lock_(mutex()) {
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(new Stream(messages), Assimp::Logger::Warn | Assimp::Logger::Err);
  }
  ~AssimpLogCapture() { Assimp::DefaultLogger::kill(); }
  AssimpLogCapture(const AssimpLogCapture&) = delete;
  AssimpLogCapture& operator=(const AssimpLogCapture&) = delete;

  bool contains(std::string_view text) const {
    for (const std::string& m : messages)
      if (m.find(text) != std::string::npos) return true;
    return false;
  }
  std::vector<std::string> messages;

 private:
  struct Stream : Assimp::LogStream {
    explicit Stream(std::vector<std::string>& out) : out_(out) {}
    void write(const char* message) override {
      std::string m = message ? message : "";
      while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
      out_.push_back(std::move(m));
    }
    std::vector<std::string>& out_;
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
};

std::string assimp_error(const Assimp::Importer& importer) {
  std::string e = importer.GetErrorString();
  while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
  return e.empty() ? "unknown error" : e;
}

MeshFile load_ply(const std::string& file, std::vector<unsigned char> bytes, size_t budget, bool vertex_normals) {
  const std::string_view data(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const PlyHeader header = read_ply_header(data, file);
  const PlyLayout layout = ply_layout(header, file);
  check_ply_memory(header, layout, budget, file);
  check_ply_counts(header, data.size() - header.body, file);
  RawMesh raw;
  if (header.unknown_lines > 0)
    raw.warnings.push_back(file + ":" + std::to_string(header.unknown_line) + ": ignored " +
                           plural(header.unknown_lines, "unknown PLY header line", "unknown PLY header lines"));
  if (header.format == PlyFormat::ascii) walk_ascii_ply(header, layout, data, file, raw.bad_vertex_text);
  else walk_binary_ply(header, layout, data, file);
  if (layout.face < 0 || header.elements[layout.face].count == 0)
    fail(file, "no triangles (vertices only)");

  AssimpLogCapture log;
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, "ply");
  if (!scene) fail(file, "cannot read PLY: " + assimp_error(importer));
  from_assimp(*scene, file, {}, /*is_ply=*/true, budget, raw);
  // assimp keeps the file's vertex order, so PLY vertex numbers are the file's.
  if (raw.positions.size() != header.elements[layout.vertex].count)
    raw.bad_vertex_text.clear();  // numbering differs: report by position instead
  if (header.format != PlyFormat::ascii) {
    raw.nonfinite_vertex_error = [file](uint32_t v) {
      return Error(SourceLocation{file, 0, 0}, "vertex " + std::to_string(v) + " has a non-finite coordinate");
    };
  }
  return finish(std::move(raw), file, vertex_normals);
}

// The glTF's JSON: all of a .gltf, or a .glb's first chunk, which must be JSON.
// Only glTF content goes to assimp: it would otherwise guess another format.
std::string gltf_json_text(const std::vector<unsigned char>& bytes, bool binary, const std::string& file) {
  if (!binary) {
    size_t i = 0;
    if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xEF\xBB\xBF", 3) == 0) i = 3;
    while (i < bytes.size() && std::isspace(bytes[i])) ++i;
    if (i >= bytes.size() || bytes[i] != '{') fail(file, "not a glTF file (no JSON object)");
    return std::string(bytes.begin(), bytes.end());
  }
  if (bytes.size() < 12 || std::memcmp(bytes.data(), "glTF", 4) != 0)
    fail(file, "not a binary glTF file (no 'glTF' magic)");
  const uint64_t declared = read_binary_uint(bytes.data() + 8, 4, false);
  if (declared > bytes.size())
    fail(file, "truncated: the header declares " + std::to_string(declared) + " bytes, the file has " +
                   std::to_string(bytes.size()));
  if (bytes.size() < 20) fail(file, "truncated: no JSON chunk after the header");
  const uint64_t length = read_binary_uint(bytes.data() + 12, 4, false);
  if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0) fail(file, "the first chunk is not the JSON chunk");
  if (length > bytes.size() - 20)
    fail(file, "truncated: the JSON chunk claims " + std::to_string(length) + " bytes, " +
                   std::to_string(bytes.size() - 20) + " follow");
  std::string text(bytes.begin() + 20, bytes.begin() + 20 + static_cast<ptrdiff_t>(length));
  while (!text.empty() && text.back() == '\0') text.pop_back();  // padding some exporters write
  return text;
}

// Bytes of one element of a glTF accessor (0 for types assimp will refuse).
double gltf_element_bytes(const json::Value& accessor) {
  const auto type = accessor.find("type");
  const auto component = accessor.find("componentType");
  if (!type || !type->is_string() || !component || !component->is_number()) return 0;
  static const std::pair<std::string_view, int> kComponents[] = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3},
                                                                  {"VEC4", 4},   {"MAT2", 4}, {"MAT3", 9},
                                                                  {"MAT4", 16}};
  int components = 0;
  for (const auto& [name, n] : kComponents)
    if (type->as_string() == name) components = n;
  const double c = component->as_number();
  const int size = c == 5120 || c == 5121 ? 1 : c == 5122 || c == 5123 ? 2 : c == 5125 || c == 5126 ? 4 : 0;
  return double(components) * size;
}

// An accessor's count as the file claims it (0 when it is no count at all,
// which assimp reports itself).
double gltf_count(const json::Value& accessor) {
  const auto count = accessor.find("count");
  return count && count->is_number() && count->as_number() > 0 ? count->as_number() : 0;
}

// A non-negative integer member, or nullopt.
std::optional<double> gltf_index(const json::Value& object, std::string_view key) {
  const auto v = object.find(key);
  if (!v || !v->is_integer() || v->as_number() < 0) return std::nullopt;
  return v->as_number();
}

// False for a "data:...;base64,..." URI whose payload is not base64 (the
// alphabet, a length of whole 4-character groups, '=' only as padding);
// true for anything else (other URIs are assimp's to judge).
bool is_valid_data_uri(std::string_view uri) {
  if (uri.substr(0, 5) != "data:") return true;
  const size_t comma = uri.find(',');
  if (comma == std::string_view::npos) return true;
  const std::string_view header = uri.substr(0, comma);
  if (header.size() < 7 || header.substr(header.size() - 7) != ";base64") return true;
  std::string_view payload = uri.substr(comma + 1);
  if (payload.size() % 4 != 0) return false;
  for (int pad = 0; pad < 2 && !payload.empty() && payload.back() == '='; ++pad) payload.remove_suffix(1);
  for (char c : payload)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '/') return false;
  return true;
}

// assimp 5.2's data URI parser (glTFCommon ParseDataURI) keeps the offsets of
// the parts it found in the string's first bytes, each as a char: a header
// (the part before the first ',') of 127 bytes or more wraps an offset
// negative, and the payload is then read from before the string (a leak);
// a string starting with byte 0x10 counts as already parsed, its next four
// bytes as those offsets (a length near 2^64). Both found by hand next to a
// fuzz_mesh_gltf finding; buffers are checked for both, and images never
// reach the parser (see reduce_gltf_json).
constexpr size_t kMaxDataUriHeader = 126;
bool assimp_reads_as_data_uri(std::string_view uri) {
  return uri.substr(0, 5) == "data:" || (!uri.empty() && uri[0] == '\x10');
}

// One primitive's indices: unsigned integer scalars (assimp leaked on a VEC3
// index accessor), and at least as many corners (indices, or positions
// without them) as its mode needs for one point, line or triangle: with fewer,
// assimp leaked (lines, fans) or wrapped a count to 2^64 (strips, fans).
template <class Where>
void check_gltf_primitive(const json::Value& primitive, const std::optional<json::Value>& accessors, Where where,
                          const std::string& name) {
  auto accessor = [&](const std::optional<double>& index) -> std::optional<json::Value> {
    if (!index || !accessors || !accessors->is_array() || *index >= double(accessors->size())) return std::nullopt;
    return (*accessors)[static_cast<size_t>(*index)];  // else assimp reports it
  };
  const auto indices = accessor(gltf_index(primitive, "indices"));
  if (indices) {
    const auto type = indices->find("type");
    const auto component = indices->find("componentType");
    const double c = component && component->is_number() ? component->as_number() : 0;
    if (!type || !type->is_string() || type->as_string() != "SCALAR" || (c != 5121 && c != 5123 && c != 5125))
      throw Error(where(*primitive.find("indices")),
                  name + ".indices: must be a SCALAR accessor of 5121, 5123 or 5125 (unsigned integers)");
  }
  const auto attributes = primitive.find("attributes");
  const auto positions = attributes ? accessor(gltf_index(*attributes, "POSITION")) : std::nullopt;
  // No positions at all count as none (a strip of none wrapped too).
  const double corners = indices ? gltf_count(*indices) : positions ? gltf_count(*positions) : 0;
  const double mode = gltf_index(primitive, "mode").value_or(4);
  const double needed = mode == 0 ? 1 : mode <= 3 ? 2 : 3;
  if (corners < needed)
    throw Error(where(primitive), name + ": " + format_count(corners) + (indices ? " indices" : " vertices") +
                                      " are too few for mode " + format_count(mode) + " (at least " +
                                      format_count(needed) + ")");
}

// What the glTF specification requires and assimp 5.2 relies on without
// checking, for what reaches it (see reduce_gltf_json): it leaks on an
// accessor without a valid componentType or type (fuzz_mesh_glb) and on
// indices that are not scalar integers; for sparse accessors it dereferences
// null for a missing part and reads past the buffer for a count the buffer
// views cannot hold (fuzz_mesh_gltf).
void check_gltf_structure(const json::Document& doc, bool binary, const std::string& file) {
  const json::Value root = doc.root();
  auto where = [&](const json::Value& v) { return binary ? SourceLocation{file, 0, 0} : v.location(); };
  // glTF 1.0 (objects where 2.0 has arrays) would go to assimp's glTF 1
  // reader, unchecked by anything here.
  const auto asset = root.find("asset");
  const auto version = asset ? asset->find("version") : std::nullopt;
  if (!version || !version->is_string()) throw Error(where(root), "no asset.version: not a glTF 2.0 file");
  if (version->as_string().substr(0, 2) != "2.")
    throw Error(where(*version), "asset.version: glTF " + std::string(version->as_string()) +
                                     " is not supported (only glTF 2.0)");
  const auto accessors = root.find("accessors");
  const auto views = root.find("bufferViews");
  const size_t view_count = views && views->is_array() ? views->size() : 0;
  // byteLength of a buffer view by index; nullopt when there is no such view.
  auto view_length = [&](const std::optional<double>& index) -> std::optional<double> {
    if (!index || *index >= double(view_count)) return std::nullopt;
    const auto length = gltf_index((*views)[static_cast<size_t>(*index)], "byteLength");
    return length ? length : std::optional<double>(0.0);
  };
  for (size_t i = 0; accessors && accessors->is_array() && i < accessors->size(); ++i) {
    const json::Value a = (*accessors)[i];
    const std::string name = "accessors[" + std::to_string(i) + "]";
    if (!a.is_object()) continue;  // assimp reports that one
    const double element = gltf_element_bytes(a);
    if (element == 0)
      throw Error(where(a), name + ": needs a componentType of 5120, 5121, 5122, 5123, 5125 or 5126 and a type of "
                                   "SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4");
    // The specification's bound on an accessor within its view, stride
    // included: assimp checks count x element size only, then reads strided
    // elements past the view, throws half-way and leaks (fuzz_mesh_glb).
    const auto view_index = gltf_index(a, "bufferView");
    if (const auto length = view_length(view_index); length && gltf_count(a) > 0) {
      const json::Value view = (*views)[static_cast<size_t>(*view_index)];
      const double stride = gltf_index(view, "byteStride").value_or(0) > 0 ? *gltf_index(view, "byteStride") : element;
      const double end = gltf_index(a, "byteOffset").value_or(0) + stride * (gltf_count(a) - 1) + element;
      if (end > *length)
        throw Error(where(a), name + ": " + format_count(gltf_count(a)) + " elements need " + format_count(end) +
                                  " bytes of buffer view " + format_count(*view_index) + ", which has " +
                                  format_count(*length));
    }
    const auto sparse = a.find("sparse");
    if (!sparse) continue;
    auto bad_sparse = [&](const std::string& what) { throw Error(where(*sparse), name + ".sparse: " + what); };
    const auto count = sparse->is_object() ? gltf_index(*sparse, "count") : std::nullopt;
    if (!count || *count < 1 || *count > gltf_count(a))
      bad_sparse("needs a count from 1 to the accessor's count");
    const auto indices = sparse->find("indices"), values = sparse->find("values");
    if (!indices || !indices->is_object() || !values || !values->is_object())
      bad_sparse("needs 'indices' and 'values' objects");
    const auto index_type = indices->find("componentType");
    const double t = index_type && index_type->is_number() ? index_type->as_number() : 0;
    const double index_bytes = t == 5121 ? 1 : t == 5123 ? 2 : t == 5125 ? 4 : 0;
    if (index_bytes == 0) bad_sparse("indices need a componentType of 5121, 5123 or 5125");
    const auto index_view = view_length(gltf_index(*indices, "bufferView"));
    const auto value_view = view_length(gltf_index(*values, "bufferView"));
    if (!index_view || !value_view) bad_sparse("indices and values each need a bufferView that exists");
    if (gltf_index(*indices, "byteOffset").value_or(0) + *count * index_bytes > *index_view ||
        gltf_index(*values, "byteOffset").value_or(0) + *count * element > *value_view)
      bad_sparse(format_count(*count) + " entries do not fit in their buffer views");
  }
  // assimp 5.2's base64 decoder leaks its buffer when it throws on a bad
  // character (fuzz_mesh_gltf). Images are not read at all (see
  // reduce_gltf_json); buffers must decode.
  const auto buffers = root.find("buffers");
  for (size_t i = 0; buffers && buffers->is_array() && i < buffers->size(); ++i) {
    const auto uri = (*buffers)[i].find("uri");
    if (!uri || !uri->is_string()) continue;
    const std::string_view u = uri->as_string();
    const std::string name = "buffers[" + std::to_string(i) + "].uri: ";
    if (!u.empty() && static_cast<unsigned char>(u[0]) < 0x20)
      throw Error(where(*uri), name + "starts with a control character (not a URI)");
    if (assimp_reads_as_data_uri(u) && std::min(u.find(','), u.size()) > kMaxDataUriHeader)
      throw Error(where(*uri), name + "a data URI whose header (before the first ',') is longer than " +
                                   std::to_string(kMaxDataUriHeader) + " bytes");
    if (!is_valid_data_uri(u)) throw Error(where(*uri), name + "a data URI whose base64 does not decode");
    // assimp 5.2 leaks the stream of an external buffer file shorter than
    // its byteLength when it throws (adversarial review): checked here.
    const auto length = (*buffers)[i].find("byteLength");
    if (u.substr(0, 5) != "data:" && length && length->is_number()) {
      const fs::path bin = fs::path(file).parent_path() / std::string(u);
      std::error_code ec;
      if (fs::is_regular_file(bin, ec)) {
        const auto size = fs::file_size(bin, ec);
        if (!ec && double(size) < length->as_number())
          throw Error(where(*length), "buffers[" + std::to_string(i) + "].byteLength: " +
                                          format_count(length->as_number()) + " bytes, but '" + std::string(u) +
                                          "' holds " + std::to_string(size));
      }
    }
  }
  const auto meshes = root.find("meshes");
  for (size_t m = 0; meshes && meshes->is_array() && m < meshes->size(); ++m) {
    const auto primitives = (*meshes)[m].find("primitives");
    for (size_t p = 0; primitives && primitives->is_array() && p < primitives->size(); ++p)
      check_gltf_primitive((*primitives)[p], accessors, where,
                           "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]");
  }
}

// What glint reads from a glTF is the node tree, the meshes' positions,
// normals, first UV set and indices, and the materials (with their base color
// textures). Skins, animations, morph targets, cameras and other vertex
// attributes are dropped before assimp sees the file: glint would ignore
// them, and assimp 5.2 crashes or leaks on many
// malformed ones (a skin without inverseBindMatrices, an animation channel
// without a target, float joints: fuzz_mesh_gltf). LINE_LOOPs become
// LINE_STRIPs (see below). `text` is valid JSON.
std::string reduce_gltf_json(const std::string& text) {
  using NJson = nlohmann::json;
  NJson j = NJson::parse(text);
  if (!j.is_object()) return text;
  for (const char* key : {"animations", "skins", "cameras"}) j.erase(key);
  // Embedded images (data URIs, or bytes in a buffer view) are never read by
  // glint, and assimp 5.2 fails on their details: it leaked decoding bad
  // base64, called strcmp on strchr(type, '/') + 1 (address 1) for a media
  // type without '/' ("data:png;...", a fuzz_mesh_gltf finding, or
  // "mimeType": "png"), misread a long data URI header. Each reaches it as
  // the same 3 zero bytes of PNG. Image files keep their uri.
  if (auto images = j.find("images"); images != j.end() && images->is_array())
    for (NJson& image : *images) {
      if (!image.is_object()) continue;
      // assimp reads a bufferView when there is no string uri.
      const auto uri = image.find("uri");
      const bool embedded = uri != image.end() && uri->is_string()
                                ? assimp_reads_as_data_uri(uri->get<std::string>())
                                : image.contains("bufferView");
      if (!embedded) continue;
      image.erase("bufferView");
      image.erase("mimeType");
      image["uri"] = "data:image/png;base64,AAAA";
    }
  if (auto nodes = j.find("nodes"); nodes != j.end() && nodes->is_array())
    for (NJson& node : *nodes)
      if (node.is_object())
        for (const char* key : {"skin", "camera", "weights"}) node.erase(key);
  if (auto meshes = j.find("meshes"); meshes != j.end() && meshes->is_array())
    for (NJson& mesh : *meshes) {
      if (!mesh.is_object()) continue;
      mesh.erase("weights");
      auto primitives = mesh.find("primitives");
      if (primitives == mesh.end() || !primitives->is_array()) continue;
      for (NJson& primitive : *primitives) {
        if (!primitive.is_object()) continue;
        primitive.erase("targets");
        // Lines are no surfaces to glint, but assimp 5.2 dereferences null
        // closing a LINE_LOOP whose indices are out of range (fuzz_mesh_glb):
        // a LINE_STRIP is read the same way, without the closing segment.
        if (auto mode = primitive.find("mode"); mode != primitive.end() && *mode == 2) *mode = 3;
        auto attributes = primitive.find("attributes");
        if (attributes == primitive.end() || !attributes->is_object()) continue;
        for (auto it = attributes->begin(); it != attributes->end();)
          it = it.key() == "POSITION" || it.key() == "NORMAL" || it.key() == "TEXCOORD_0" ? std::next(it)
                                                                                         : attributes->erase(it);
      }
    }
  return j.dump(-1, ' ', false, NJson::error_handler_t::replace);
}

// The file as assimp gets it: the reduced JSON, in a GLB with the file's
// other chunks (its binary buffer) when the file is one.
std::string reduced_gltf_file(const std::vector<unsigned char>& bytes, bool binary, const std::string& json_text) {
  std::string json = reduce_gltf_json(json_text);
  if (!binary) return json;
  while (json.size() % 4) json += ' ';  // chunks stay 4-byte aligned
  const uint64_t declared = read_binary_uint(bytes.data() + 8, 4, false);
  const uint64_t rest = 20 + read_binary_uint(bytes.data() + 12, 4, false);
  const std::string tail = rest < declared ? std::string(bytes.begin() + static_cast<ptrdiff_t>(rest),
                                                         bytes.begin() + static_cast<ptrdiff_t>(declared))
                                           : std::string();
  auto u32 = [](uint64_t v) {
    const char b[4] = {char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff), char((v >> 24) & 0xff)};
    return std::string(b, 4);
  };
  return std::string(reinterpret_cast<const char*>(bytes.data()), 8) + u32(20 + json.size() + tail.size()) +
         u32(json.size()) + "JSON" + json + tail;
}

// Serves the glTF file itself from memory (reduced) and every file it names
// (external buffers, images) from disk, relative to it as assimp resolves
// them; only regular files, since opening a FIFO a buffer names would block.
class ReducedGltfIO final : public Assimp::DefaultIOSystem {
 public:
  ReducedGltfIO(std::string path, std::string bytes) : path_(std::move(path)), bytes_(std::move(bytes)) {}
  bool Exists(const char* file) const override { return path_ == file || is_regular(file); }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (path_ == file)
      return new Assimp::MemoryIOStream(reinterpret_cast<const uint8_t*>(bytes_.data()), bytes_.size());
    return is_regular(file) ? DefaultIOSystem::Open(file, mode) : nullptr;
  }

 private:
  static bool is_regular(const char* file) {
    std::error_code ec;
    return fs::is_regular_file(file, ec);
  }
  std::string path_, bytes_;
};

// What the glTF claims before assimp allocates for it: every accessor's data
// (assimp allocates count x element size even for an accessor without a
// buffer, e.g. a sparse one, so a 300-byte file can claim gigabytes), and the
// meshes' vertices and triangles times the nodes that instance each mesh.
void check_gltf_memory(const json::Document& doc, bool binary, size_t budget, const std::string& file) {
  const json::Value root = doc.root();
  // A .glb's JSON positions mean little to people: name the file only.
  auto where = [&](const json::Value& v) { return binary ? SourceLocation{file, 0, 0} : v.location(); };
  const auto accessors = root.find("accessors");
  std::vector<double> counts;
  double accessor_bytes = 0;
  if (accessors && accessors->is_array()) {
    for (size_t i = 0; i < accessors->size(); ++i) {
      const json::Value a = (*accessors)[i];
      counts.push_back(gltf_count(a));
      const double bytes = counts.back() * gltf_element_bytes(a);
      const std::string excess = exceeds_budget(bytes, budget);
      if (!excess.empty())
        throw Error(where(*a.find("count")), "accessors[" + std::to_string(i) + "].count: " +
                                                 format_count(counts.back()) + " elements: that " + excess);
      accessor_bytes += bytes;
    }
  }
  // assimp holds every buffer whole (an external .bin may be any size).
  const auto buffers = root.find("buffers");
  for (size_t i = 0; buffers && buffers->is_array() && i < buffers->size(); ++i) {
    const auto length = (*buffers)[i].find("byteLength");
    if (!length || !length->is_number() || length->as_number() <= 0) continue;
    const std::string excess = exceeds_budget(length->as_number(), budget);
    if (!excess.empty())
      throw Error(where(*length), "buffers[" + std::to_string(i) + "].byteLength: " + format_count(length->as_number()) +
                                      " bytes: that " + excess);
    accessor_bytes += length->as_number();
  }
  auto count_of = [&](const std::optional<json::Value>& index) {
    if (!index || !index->is_integer() || index->as_number() < 0 || index->as_number() >= double(counts.size()))
      return 0.0;
    return counts[static_cast<size_t>(index->as_number())];
  };
  const auto meshes = root.find("meshes");
  const auto nodes = root.find("nodes");
  double vertices = 0, triangles = 0;
  for (size_t m = 0; meshes && meshes->is_array() && m < meshes->size(); ++m) {
    double instances = 0;
    for (size_t n = 0; nodes && nodes->is_array() && n < nodes->size(); ++n) {
      const auto mesh = (*nodes)[n].find("mesh");
      instances += mesh && mesh->is_number() && mesh->as_number() == double(m);
    }
    const auto primitives = (*meshes)[m].find("primitives");
    for (size_t p = 0; primitives && primitives->is_array() && p < primitives->size(); ++p) {
      const json::Value primitive = (*primitives)[p];
      const auto attributes = primitive.find("attributes");
      const double positions = attributes ? count_of(attributes->find("POSITION")) : 0;
      const auto indices = primitive.find("indices");
      const double corners = indices ? count_of(indices) : positions;
      const auto mode = primitive.find("mode");
      const bool strip_or_fan = mode && mode->is_number() && (mode->as_number() == 5 || mode->as_number() == 6);
      vertices += std::max(instances, 1.0) * positions;
      triangles += std::max(instances, 1.0) * (strip_or_fan ? corners : corners / 3);
    }
  }
  const std::string excess =
      exceeds_budget(accessor_bytes + kBytesPerVertex * vertices + kBytesPerTriangle * triangles, budget);
  if (!excess.empty())
    fail(file, "the accessors claim " + format_count(vertices) + " vertices and " + format_count(triangles) +
                   " triangles (instances counted): that " + excess);
}

json::Document parse_gltf_json(std::string text, bool binary, const std::string& file) {
  try {
    return json::parse(std::move(text), file);
  } catch (const Error& e) {
    if (!binary) throw;
    fail(file, "JSON chunk: " + e.message());
  }
}

MeshFile load_gltf(const fs::path& path, const std::string& file, const std::vector<unsigned char>& bytes,
                   bool binary, size_t budget, bool vertex_normals) {
  const std::string json_text = gltf_json_text(bytes, binary, file);
  {
    const json::Document doc = parse_gltf_json(json_text, binary, file);
    // Memory first: a claim of billions is the news, not the buffer it overruns.
    check_gltf_memory(doc, binary, budget, file);
    check_gltf_structure(doc, binary, file);
  }
  AssimpLogCapture log;
  Assimp::Importer importer;
  importer.SetIOHandler(new ReducedGltfIO(path.string(), reduced_gltf_file(bytes, binary, json_text)));
  const aiScene* scene = importer.ReadFile(path.string(), 0);
  // assimp drops faces with out-of-range indices (with a log line), and then
  // may fail for a mesh left without faces: the cause is the better message.
  if (log.contains("out-of-range indices")) fail(file, "face with a vertex index out of range");
  if (!scene) fail(file, "cannot read glTF: " + assimp_error(importer));
  RawMesh raw;
  from_assimp(*scene, file, path.parent_path(), /*is_ply=*/false, budget, raw);
  // assimp adds a default material for primitives without one: not the file's.
  for (int32_t& m : raw.triangle_material)
    if (m >= 0 && raw.materials[m].name == AI_DEFAULT_MATERIAL_NAME) m = -1;
  for (Material& m : raw.materials)
    if (m.name == AI_DEFAULT_MATERIAL_NAME) m.name.clear();  // dropped when unused
  return finish(std::move(raw), file, vertex_normals);
}

}  // namespace

MeshFile load_mesh_file(const fs::path& path, size_t memory_budget, bool vertex_normals) {
  const std::string file = path.string();
  try {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (!fs::exists(status)) fail(file, "mesh file not found");
    if (fs::is_directory(status)) fail(file, "is a directory, not a mesh file");
    const std::string ext = lower(path.extension().string());
    if (ext != ".obj" && ext != ".ply" && ext != ".gltf" && ext != ".glb")
      fail(file, "unsupported mesh format '" + path.extension().string() + "' (supported: .obj, .ply, .gltf, .glb)");
    // Not a device or a pipe: /dev/zero would be read until memory runs out.
    if (!fs::is_regular_file(status)) fail(file, "not a regular file");
    // The readers hold the whole file and more, so a file beyond the budget is refused unread.
    const uintmax_t size = fs::file_size(path, ec);
    if (!ec) {
      const std::string excess = exceeds_budget(static_cast<double>(size), memory_budget);
      if (!excess.empty()) fail(file, "file of " + format_bytes(static_cast<double>(size)) + ": reading it " + excess);
    }
    std::vector<unsigned char> bytes = read_file(path);
    if (bytes.empty()) fail(file, "empty file");
    if (ext == ".obj") return load_obj(path, file, std::move(bytes), memory_budget, vertex_normals);
    if (ext == ".ply") return load_ply(file, std::move(bytes), memory_budget, vertex_normals);
    return load_gltf(path, file, bytes, ext == ".glb", memory_budget, vertex_normals);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(file, "out of memory reading the mesh");
  } catch (const std::exception& e) {
    fail(file, std::string("cannot read mesh: ") + e.what());
  } catch (...) {
    fail(file, "cannot read mesh: unknown error");
  }
}

}  // namespace glint
