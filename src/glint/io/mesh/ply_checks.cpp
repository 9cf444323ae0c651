#include "glint/io/mesh/ply_checks.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <optional>

#include "glint/io/memory_limit.h"
#include "glint/io/mesh/common.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {
namespace {

std::optional<PlyType> ply_type(std::string_view name) {
  static const std::pair<std::string_view, PlyType> kTypes[] = {
      {"char", PlyType::i8},   {"int8", PlyType::i8},     {"uchar", PlyType::u8},   {"uint8", PlyType::u8},
      {"short", PlyType::i16}, {"int16", PlyType::i16},   {"ushort", PlyType::u16}, {"uint16", PlyType::u16},
      {"int", PlyType::i32},   {"int32", PlyType::i32},   {"uint", PlyType::u32},   {"uint32", PlyType::u32},
      {"float", PlyType::f32}, {"float32", PlyType::f32}, {"double", PlyType::f64}, {"float64", PlyType::f64}};
  for (const auto& [n, t] : kTypes)
    if (n == name) return t;
  return std::nullopt;
}
size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8:
    case PlyType::u8: return 1;
    case PlyType::i16:
    case PlyType::u16: return 2;
    case PlyType::i32:
    case PlyType::u32:
    case PlyType::f32: return 4;
    case PlyType::f64: return 8;
  }
  return 1;
}
bool ply_is_float(PlyType t) { return t == PlyType::f32 || t == PlyType::f64; }

// A binary integer of this type as a signed 64-bit value.
int64_t read_binary_int(const unsigned char* p, PlyType t, bool big_endian) {
  const size_t size = ply_size(t);
  const uint64_t u = read_binary_uint(p, size, big_endian);
  switch (t) {
    case PlyType::i8: return static_cast<int8_t>(u);
    case PlyType::i16: return static_cast<int16_t>(u);
    case PlyType::i32: return static_cast<int32_t>(u);
    case PlyType::f32:
    case PlyType::f64: return 0;
    default: return static_cast<int64_t>(u);
  }
}

// 'text', appended rather than "'" + text + "'": GCC 12 warns falsely
// (-Wrestrict) on that operator+ when it inlines it without link-time
// optimization.
std::string quoted(std::string_view text) {
  std::string out = "'";
  out.append(text).push_back('\'');
  return out;
}

std::string ply_face_problem(uint64_t face, int64_t index, uint64_t vertices) {
  return "face " + std::to_string(face) + ": vertex index " + std::to_string(index) + " out of range (" +
         plural(vertices, "vertex", "vertices") + ")";
}

}  // namespace

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
    // A carriage return inside a line (not before its '\n'): this reader
    // ends the line there, assimp reads on, and the two saw different
    // headers (assimp then crashed in its binary reader: fuzz_mesh_ply).
    const size_t line_end = static_cast<size_t>(line.data() - data.data()) + line.size();
    if (line_end < data.size() && data[line_end] == '\r' && (line_end + 1 >= data.size() || data[line_end + 1] != '\n'))
      fail(file, "PLY header line has a carriage return inside it", n);
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
            if (!x) fail(file, quoted(v.text) + " is not a number", n, v.column);
            // A float property beyond float range reads as infinity.
            const bool finite = type == PlyType::f32 ? std::abs(*x) <= FLT_MAX : std::isfinite(*x);
            if (!finite && static_cast<int>(e) == l.vertex &&
                (static_cast<int>(k) == l.xyz[0] || static_cast<int>(k) == l.xyz[1] || static_cast<int>(k) == l.xyz[2]))
              bad.push_back({static_cast<uint32_t>(r), n, v.column, std::string(v.text)});
            return 0;
          }
          const auto i = parse_integer(v.text);
          if (!i) fail(file, quoted(v.text) + " is not an integer", n, v.column);
          return *i;
        };
        if (!prop.list) {
          check_value(need(prop.name.c_str()), prop.type);
          continue;
        }
        const Token& count_token = need("a list length");
        const int64_t count = check_value(count_token, prop.count_type);
        if (count < 0 || static_cast<uint64_t>(count) > tok.size() - t)
          fail(file,
               el.name + " " + std::to_string(r) + ": list length " + std::to_string(count) +
                   " does not match the values on the line",
               n, count_token.column);
        const bool indices = static_cast<int>(e) == l.face && static_cast<int>(k) == l.face_list;
        for (int64_t i = 0; i < count; ++i) {
          const Token& v = tok[t++];
          const int64_t index = check_value(v, prop.type);
          if (indices && (ply_is_float(prop.type) || index < 0 || static_cast<uint64_t>(index) >= vertices))
            fail(file,
                 "vertex index " + std::string(v.text) + " out of range (" + plural(vertices, "vertex", "vertices") +
                     ")",
                 n, v.column);
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

}  // namespace glint::mesh_io
