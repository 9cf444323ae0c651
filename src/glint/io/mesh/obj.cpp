#include "glint/io/mesh/obj.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <istream>
#include <map>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>

#include "glint/io/mesh/common.h"
#include "glint/io/mesh/mesh_builder.h"
#include "glint/io/mesh/mtl.h"
#include "glint/io/mesh/obj_checks.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {
namespace fs = std::filesystem;
namespace {

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

// The file's text as UTF-8 (`converted` holds it when the file was UTF-16),
// without a byte-order mark; binary content and blank files are errors.
std::string_view obj_text(const std::vector<unsigned char>& bytes, std::string& converted, const std::string& file) {
  std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (text.size() >= 2 && (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF")) {
    converted = utf16_to_utf8(text, text[0] == '\xFE');
    text = converted;
  } else if (text.substr(0, 3) == "\xEF\xBB\xBF") {
    text.remove_prefix(3);
  }
  if (text.find('\0') != std::string_view::npos) fail(file, "not a Wavefront OBJ file (binary content)");
  if (text.find_first_not_of(" \t\r\n\v\f") == std::string_view::npos) fail(file, "empty file");
  return text;
}

// What tinyobjloader read.
struct ObjParse {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
};

// tinyobjloader's parse, with glint's checks of the text beside it; returns
// the non-finite vertex texts found (an error only if a triangle uses one).
std::vector<BadVertexText> parse_obj(std::string_view text, const std::string& file, MtlReader& mtl_reader,
                                     ObjParse& obj) {
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

  {
    MemoryStreambuf buffer(text.data(), text.size());
    std::istream in(&buffer);
    const bool ok = tinyobj::LoadObj(&obj.attrib, &obj.shapes, &obj.materials, &obj.warn, &obj.err, &in, &mtl_reader,
                                     /*triangulate=*/false, /*default_vcols_fallback=*/false);
    checks.join();
    if (bad_statement.line > 0) fail(file, bad_statement.message, bad_statement.line, bad_statement.column);
    if (!ok) {
      const std::string first = obj.err.substr(0, obj.err.find('\n'));
      const int line = line_in_message(first);
      if (first.find("`f'") != std::string::npos) fail(file, "face with a vertex index of 0 or not a number", line);
      if (first.find("`l'") != std::string::npos || first.find("`p'") != std::string::npos)
        fail(file, "line or point with a vertex index of 0 or not a number", line);
      fail(file, "cannot read OBJ: " + (first.empty() ? std::string("unknown error") : first), line);
    }
  }
  if (mtl_reader.error)  // at the .mtl's line; the message names the OBJ that uses it
    throw Error(mtl_reader.error->location(), mtl_reader.error->message() + " (material library of " + file + ")");
  return bad_vertex_text;
}

// tinyobjloader keeps a face's vertex count in 8 bits: recover larger ones
// from the text when the counts do not add up (empty: the stored ones hold).
std::vector<size_t> true_face_sizes(const std::vector<tinyobj::shape_t>& shapes, std::string_view text,
                                    const std::string& file) {
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
  return true_sizes;
}

// Checks the triangles' memory against the budget and reserves for them.
void reserve_triangles(const ObjParse& obj, size_t budget, const std::string& file, RawMesh& raw) {
  // Polygons of n corners make n - 2 triangles (8-bit counts wrap, so at most an estimate).
  size_t estimate = 0;
  for (const auto& s : obj.shapes)
    for (unsigned char n : s.mesh.num_face_vertices) estimate += n >= 3 ? n - 2 : 0;
  // OBJ states no counts, but text is dense: "f 1 2 3 4 ..." makes a
  // triangle per 2 bytes, 50 times that in memory. Checked once the
  // library's compact arrays are read, before the large ones are made.
  const std::string excess = exceeds_budget(
      kBytesPerTriangle * double(estimate) + kBytesPerVertex * double(obj.attrib.vertices.size() / 3), budget);
  if (!excess.empty()) fail(file, plural(estimate, "triangle", "triangles") + " (about): that " + excess);
  raw.indices.reserve(3 * estimate);
  raw.normals.reserve(3 * estimate);
  raw.triangle_material.reserve(estimate);
}

// The faces, triangulated, into `raw` (with their normals, UVs and materials).
void add_obj_faces(const ObjParse& obj, const std::vector<size_t>& true_sizes, const std::string& file, RawMesh& raw) {
  const tinyobj::attrib_t& attrib = obj.attrib;
  const size_t normal_count = attrib.normals.size() / 3;
  const size_t texcoord_count = attrib.texcoords.size() / 2;
  size_t face_ordinal = 0;
  bool bad_index = false;
  for (const auto& s : obj.shapes) {
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
              raw.normals.push_back(
                  ni >= 0 ? Vec3f{attrib.normals[3 * ni], attrib.normals[3 * ni + 1], attrib.normals[3 * ni + 2]}
                          : Vec3f{});
              if (ni >= 0) raw.has_normals = true;
              const int ti = corner[k].texcoord_index;
              raw.uvs.push_back(ti >= 0 ? UVf{attrib.texcoords[2 * ti], attrib.texcoords[2 * ti + 1]} : UVf{});
              if (ti >= 0) raw.has_uvs = true;
            }
            raw.triangle_material.push_back(
                material >= 0 && static_cast<size_t>(material) < obj.materials.size() ? material : -1);
          });
    }
    if (bad_index) break;
    raw.non_faces += s.lines.num_line_vertices.size() + s.points.indices.size();
  }
  if (bad_index) {
    fail(file, "face index out of range");  // find_obj_bad_statement found none: tinyobjloader disagrees
  }
}

// Missing material libraries, and usemtl names none of them has: one warning each.
void warn_missing_materials(const ObjParse& obj, const MtlReader& mtl_reader, const std::string& file, RawMesh& raw) {
  for (const std::string& name : mtl_reader.missing)
    raw.warnings.push_back(file + ": material library '" + name + "' not found (default materials used)");
  std::vector<std::string> unknown;
  const std::string& warn = obj.warn;
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

// map_Ka / map_Kd / map_Ks that exist become the material's textures (the
// missing ones are reported by the caller and the colors stay); every
// texture file the material names and that is missing goes into `report`.
void add_mtl_textures(const tinyobj::material_t& t, const fs::path& mtl, MtlReport& report, RawMesh& raw) {
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
       {&t.ambient_texname, &t.diffuse_texname, &t.specular_texname, &t.specular_highlight_texname, &t.bump_texname,
        &t.displacement_texname, &t.alpha_texname, &t.reflection_texname, &t.roughness_texname, &t.metallic_texname,
        &t.sheen_texname, &t.emissive_texname, &t.normal_texname}) {
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

// One warning per kind of finding per material library.
void warn_mtl_findings(const fs::path& mtl, const MtlReport& r, RawMesh& raw) {
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
    raw.warnings.push_back(name + ": " + plural(r.missing_textures.size(), "texture file", "texture files") +
                           " not found (defaults used): " + name_list(r.missing_textures));
}

// Materials, and what went wrong with them: one warning per kind per file.
void add_obj_materials(const ObjParse& obj, const MtlReader& mtl_reader, const std::string& file, RawMesh& raw) {
  warn_missing_materials(obj, mtl_reader, file, raw);
  std::map<fs::path, MtlReport> reports;
  std::vector<fs::path> report_order;
  for (size_t i = 0; i < obj.materials.size(); ++i) {
    const bool known = i < mtl_reader.origin.size();
    const fs::path mtl = known ? mtl_reader.origin[i].mtl : fs::path(file);
    if (!reports.count(mtl)) report_order.push_back(mtl);
    MtlReport& report = reports[mtl];
    MtlBlock block;
    if (known) block = mtl_reader.origin[i].block;
    raw.materials.push_back(map_mtl(obj.materials[i], block, report));
    add_mtl_textures(obj.materials[i], mtl, report, raw);
  }
  for (const fs::path& mtl : report_order) warn_mtl_findings(mtl, reports[mtl], raw);
}

}  // namespace

MeshFile load_obj(const fs::path& path, const std::string& file, std::vector<unsigned char> bytes, size_t budget,
                  bool vertex_normals) {
  std::string converted;
  const std::string_view text = obj_text(bytes, converted, file);
  ObjParse obj;
  MtlReader mtl_reader(path.parent_path());
  std::vector<BadVertexText> bad_vertex_text = parse_obj(text, file, mtl_reader, obj);
  // bytes and converted stay alive: error paths below scan the text again.

  RawMesh raw;
  const tinyobj::attrib_t& attrib = obj.attrib;
  raw.positions.resize(attrib.vertices.size() / 3);
  for (size_t v = 0; v < raw.positions.size(); ++v)
    raw.positions[v] = {attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]};
  raw.bad_vertex_text = std::move(bad_vertex_text);
  raw.nonfinite_vertex_error = [&](uint32_t v) {
    return Error(SourceLocation{file, find_obj_statement(text, "v", v), 0},
                 "vertex coordinate is not a finite number (out of float range)");
  };

  const std::vector<size_t> true_sizes = true_face_sizes(obj.shapes, text, file);
  reserve_triangles(obj, budget, file, raw);
  add_obj_faces(obj, true_sizes, file, raw);
  if (!raw.has_normals) raw.normals.clear();
  if (!raw.has_uvs) raw.uvs.clear();
  raw.small_faces = count_occurrences(obj.warn, "Degenerated face found");
  if (raw.positions.empty() && raw.indices.empty() && raw.non_faces == 0)
    fail(file, "no vertices or faces: not a Wavefront OBJ file");

  add_obj_materials(obj, mtl_reader, file, raw);
  return finish(std::move(raw), file, vertex_normals);
}

}  // namespace glint::mesh_io
