#include "glint/io/mesh/mtl.h"

#include <algorithm>
#include <istream>
#include <string_view>
#include <system_error>
#include <utility>

#include "glint/io/file_io.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {
namespace fs = std::filesystem;
namespace {

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
    if (!x)
      return report(tok.column, std::string(key) + " " + value + " is not a number" +
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

Color mtl_color(const tinyobj::real_t c[3], bool single) {
  return single ? Color(c[0], c[0], c[0]) : Color(c[0], c[1], c[2]);
}

}  // namespace

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

bool MtlReader::operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                           std::map<std::string, int>* map, std::string* warn, std::string* err) {
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

}  // namespace glint::mesh_io
