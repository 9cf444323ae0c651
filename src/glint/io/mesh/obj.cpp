#include "glint/io/mesh/obj.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <tiny_obj_loader.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <istream>
#include <map>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>

#include "glint/accel/huge_pages.h"
#include "glint/io/file_io.h"
#include "glint/io/mesh/common.h"
#include "glint/io/mesh/mesh_builder.h"
#include "glint/io/mesh/mtl.h"
#include "glint/io/mesh/obj_checks.h"
#include "glint/io/mesh/obj_reader.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {
namespace fs = std::filesystem;
namespace {

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
std::string_view obj_text(std::string_view text, std::string& converted, const std::string& file) {
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

// Triangles the faces make (polygons of n corners make n - 2).
size_t triangle_total(const ObjData& obj) {
  size_t total = 0;
  for (size_t f = 0; f < obj.face_count(); ++f) total += obj.face_start[f + 1] - obj.face_start[f] - 2;
  return total;
}

// Checks the triangles' memory against the budget before the large arrays are made.
void check_budget(size_t triangles, size_t vertices, size_t budget, const std::string& file) {
  // OBJ states no counts, but text is dense: "f 1 2 3 4 ..." makes a
  // triangle per 2 bytes, 50 times that in memory. Checked once the
  // compact arrays are read, before the large ones are made.
  const std::string excess =
      exceeds_budget(kBytesPerTriangle * double(triangles) + kBytesPerVertex * double(vertices), budget);
  if (!excess.empty()) fail(file, plural(triangles, "triangle", "triangles") + " (about): that " + excess);
}

// The faces, triangulated, into `raw` (with their normals, UVs and
// materials), in parallel over runs of faces: each run knows where its
// triangles start. read_obj checked every index against what came before it.
// Every face has at least 3 corners, so as many triangles as faces means all
// are triangles: the corners' vertices are then the triangles' indices and
// the faces' materials theirs, taken over rather than copied (on a 1M
// triangle file, 16 MB neither allocated nor written again).
void add_obj_faces(ObjData& obj, size_t triangles, RawMesh& raw) {
  raw.has_normals = std::any_of(obj.corner_normal.begin(), obj.corner_normal.end(), [](int32_t i) { return i >= 0; });
  raw.has_uvs = std::any_of(obj.corner_texcoord.begin(), obj.corner_texcoord.end(), [](int32_t i) { return i >= 0; });
  const size_t faces = obj.face_count();
  const bool all_triangles = triangles == faces;
  if (all_triangles) {
    raw.indices = std::move(obj.corner_vertex);
    raw.triangle_material = std::move(obj.face_material);
  } else {
    resize_in_huge_pages(raw.indices, 3 * triangles);
    resize_in_huge_pages(raw.triangle_material, triangles);
  }
  if (raw.has_normals) resize_in_huge_pages(raw.normals, 3 * triangles);
  if (raw.has_uvs) resize_in_huge_pages(raw.uvs, 3 * triangles);
  const uint32_t* const corner_vertex = all_triangles ? raw.indices.data() : obj.corner_vertex.data();
  const int32_t* const face_material = all_triangles ? raw.triangle_material.data() : obj.face_material.data();
  const size_t runs = std::clamp<size_t>(faces / 65536, 1, 64);
  std::vector<size_t> first_triangle(runs + 1, 0);
  auto run_faces = [&](size_t r) { return std::pair{faces * r / runs, faces * (r + 1) / runs}; };
  for (size_t r = 0; r < runs; ++r) {
    const auto [from, to] = run_faces(r);
    // Each face of n corners makes n - 2 triangles.
    first_triangle[r + 1] = first_triangle[r] + (obj.face_start[to] - obj.face_start[from]) - 2 * (to - from);
  }
  const int32_t material_count = static_cast<int32_t>(obj.materials.size());
  run_parallel(runs, 0, [&](size_t r) {
    const auto [from, to] = run_faces(r);
    size_t t = first_triangle[r];
    for (size_t f = from; f < to; ++f) {
      const size_t first = obj.face_start[f], n = obj.face_start[f + 1] - first;
      const uint32_t* vertex = corner_vertex + first;
      // Read before the triangle's own material is written (the same
      // element when the arrays were taken over).
      const int32_t material = face_material[f] < material_count ? face_material[f] : -1;
      triangulate(
          n, [&](size_t k) { return raw.positions[vertex[k]]; },
          [&](size_t a, size_t b, size_t c) {
            const size_t corner[3] = {a, b, c};
            for (size_t k = 0; k < 3; ++k) {
              if (!all_triangles) raw.indices[3 * t + k] = vertex[corner[k]];
              if (raw.has_normals) {
                const int32_t ni = obj.corner_normal[first + corner[k]];
                if (ni >= 0) raw.normals[3 * t + k] = obj.normals[static_cast<size_t>(ni)];
              }
              if (raw.has_uvs) {
                const int32_t ti = obj.corner_texcoord[first + corner[k]];
                if (ti >= 0) raw.uvs[3 * t + k] = obj.texcoords[static_cast<size_t>(ti)];
              }
            }
            raw.triangle_material[t++] = material;
          });
    }
  });
}

// The per-corner arrays are done with once the triangles are made: freed
// before finish(), so that they are not held at the load's peak. (Assigning
// fresh vectors: `v = {}` would pick the initializer-list assignment, which
// keeps the capacity.)
void release_corners(ObjData& obj) {
  obj.face_start = decltype(obj.face_start)();
  obj.corner_vertex = decltype(obj.corner_vertex)();
  obj.corner_texcoord = decltype(obj.corner_texcoord)();
  obj.corner_normal = decltype(obj.corner_normal)();
  obj.face_material = decltype(obj.face_material)();
  obj.normals = decltype(obj.normals)();
  obj.texcoords = decltype(obj.texcoords)();
}

// Missing material libraries, and usemtl names none of them has: one warning each.
void warn_missing_materials(const ObjData& obj, const MtlReader& mtl_reader, const std::string& file, RawMesh& raw) {
  for (const std::string& name : mtl_reader.missing)
    raw.warnings.push_back(file + ": material library '" + name + "' not found (default materials used)");
  std::vector<std::string> unknown;
  for (const std::string& name : obj.unknown_materials)
    if (std::find(unknown.begin(), unknown.end(), name) == unknown.end()) unknown.push_back(name);
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
void add_obj_materials(const ObjData& obj, const MtlReader& mtl_reader, const std::string& file, RawMesh& raw) {
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

// A regular file's bytes read straight into memory that asks for 2 MiB
// pages: a 1M-triangle OBJ is 76 MB, which read_file copies twice and faults
// in 4 KiB at a time (about a quarter of the load once the parse is parallel).
struct WholeFile {
  char* data = nullptr;
  size_t size = 0, capacity = 0;
  WholeFile() = default;
  WholeFile(const WholeFile&) = delete;
  WholeFile& operator=(const WholeFile&) = delete;
  ~WholeFile() {
    if (data) HugePageAllocator<char>().deallocate(data, capacity);
  }
};

// Bytes [offset, offset + bytes) of the file into `out`; false on an error
// or an early end (the file shrank).
bool read_range(int fd, char* out, size_t offset, size_t bytes) {
  while (bytes > 0) {
    const ssize_t n = ::pread(fd, out, bytes, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    out += n;
    offset += static_cast<size_t>(n);
    bytes -= static_cast<size_t>(n);
  }
  return true;
}

// False when the file cannot be read so (read_file then reads it, and reports).
// Big files are read in pieces on all cores: copying them out of the page
// cache, and the first touch of each page of the buffer, are most of the
// read, and both go as fast on two cores as on one.
bool read_whole_file(const fs::path& path, WholeFile& out) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat info {};
  bool ok = ::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0;
  if (ok) {
    const auto size = static_cast<size_t>(info.st_size);
    out.capacity = size + 1;  // a file that grew is read by read_file
    out.data = HugePageAllocator<char>().allocate(out.capacity);
    constexpr size_t kPiece = size_t{8} << 20;
    const size_t pieces = (size + kPiece - 1) / kPiece;
    std::atomic<bool> read_all{true};
    run_parallel(pieces, 0, [&](size_t i) {
      const size_t begin = i * kPiece, bytes = std::min(kPiece, size - begin);
      if (!read_range(fd, out.data + begin, begin, bytes)) read_all = false;
    });
    char past_end = 0;
    ssize_t more = 0;
    do more = ::pread(fd, &past_end, 1, static_cast<off_t>(size));
    while (more < 0 && errno == EINTR);
    ok = read_all && more == 0;
    out.size = size;
  }
  ::close(fd);
  return ok;
}

MeshFile load_obj_text(const fs::path& path, const std::string& file, std::string_view bytes, size_t budget,
                       bool vertex_normals) {
  std::string converted;
  const std::string_view text = obj_text(bytes, converted, file);
  MtlReader mtl_reader(path.parent_path());
  ObjData obj = read_obj(text, file, &mtl_reader);
  if (mtl_reader.error)  // at the .mtl's line; the message names the OBJ that uses it
    throw Error(mtl_reader.error->location(), mtl_reader.error->message() + " (material library of " + file + ")");
  // bytes and converted stay alive: error paths below scan the text again.

  RawMesh raw;
  raw.positions = std::move(obj.positions);
  raw.bad_vertex_text = std::move(obj.bad_vertex_text);
  raw.nonfinite_vertex_error = [&](uint32_t v) {
    return Error(SourceLocation{file, find_obj_statement(text, "v", v), 0},
                 "vertex coordinate is not a finite number (out of float range)");
  };

  const size_t triangles = triangle_total(obj);
  check_budget(triangles, raw.positions.size(), budget, file);
  add_obj_faces(obj, triangles, raw);
  release_corners(obj);
  raw.non_faces = obj.non_faces;
  raw.small_faces = obj.small_faces;
  if (raw.positions.empty() && raw.indices.empty() && raw.non_faces == 0)
    fail(file, "no vertices or faces: not a Wavefront OBJ file");

  add_obj_materials(obj, mtl_reader, file, raw);
  return finish(std::move(raw), file, vertex_normals);
}

}  // namespace

MeshFile load_obj(const fs::path& path, const std::string& file, std::vector<unsigned char> bytes, size_t budget,
                  bool vertex_normals) {
  return load_obj_text(path, file, {reinterpret_cast<const char*>(bytes.data()), bytes.size()}, budget, vertex_normals);
}

MeshFile load_obj_file(const fs::path& path, const std::string& file, size_t budget, bool vertex_normals) {
  WholeFile whole;
  if (!read_whole_file(path, whole)) return load_obj(path, file, read_file(path), budget, vertex_normals);
  return load_obj_text(path, file, {whole.data, whole.size}, budget, vertex_normals);
}

}  // namespace glint::mesh_io
