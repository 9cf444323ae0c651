// glint's parallel OBJ reader (io/mesh/obj_reader.h) against tinyobjloader,
// which read OBJ files before it: on every OBJ of the repository and of
// Debian's assimp-testmodels both must read the same vertices (bit for bit),
// normals, texture coordinates, faces, materials per face, kept lines and
// points; a file that tinyobjloader or glint's check rejects, the reader
// rejects too. And the reader's result must not depend on how the text is
// cut into chunks.
#include <gtest/gtest.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "glint/error.h"
#include "glint/io/mesh/mtl.h"
#include "glint/io/mesh/obj_checks.h"
#include "glint/io/mesh/obj_reader.h"
#include "glint/io/mesh/text_scan.h"

namespace glint::mesh_io {
namespace {

namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> obj_files_under(const fs::path& root) {
  std::vector<fs::path> out;
  std::error_code ec;
  if (!fs::is_directory(root, ec)) return out;
  for (auto it = fs::recursive_directory_iterator(root, ec); it != fs::recursive_directory_iterator(); ++it) {
    if (!it->is_regular_file(ec)) continue;
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".obj") out.push_back(it->path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// tinyobjloader's result, flattened the way glint used it (obj.cpp before
// the reader): faces in file order with their corners and materials.
struct Reference {
  bool ok = false;
  std::string err;
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::material_t> materials;
  std::vector<size_t> face_sizes;
  std::vector<tinyobj::index_t> corners;
  std::vector<int> face_material;
  size_t small_faces = 0, non_faces = 0;
  std::vector<std::string> unknown_materials;
};

size_t count_of(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + what.size())) ++n;
  return n;
}

Reference read_with_tinyobj(std::string_view text, const fs::path& folder) {
  Reference r;
  MtlReader mtl(folder);
  std::vector<tinyobj::shape_t> shapes;
  std::string warn;
  MemoryStreambuf buffer(text.data(), text.size());
  std::istream in(&buffer);
  r.ok = tinyobj::LoadObj(&r.attrib, &shapes, &r.materials, &warn, &r.err, &in, &mtl, /*triangulate=*/false,
                          /*default_vcols_fallback=*/false);
  if (!r.ok) return r;
  // A polygon's corner count is kept in 8 bits: the text's when they disagree.
  size_t stored = 0, indices = 0;
  for (const auto& s : shapes) {
    for (unsigned char n : s.mesh.num_face_vertices) stored += n;
    indices += s.mesh.indices.size();
  }
  const std::vector<size_t> true_sizes = stored != indices ? scan_obj_face_sizes(text) : std::vector<size_t>{};
  for (const auto& s : shapes) {
    for (size_t f = 0; f < s.mesh.num_face_vertices.size(); ++f) {
      r.face_sizes.push_back(true_sizes.empty() ? s.mesh.num_face_vertices[f] : true_sizes[r.face_sizes.size()]);
      r.face_material.push_back(s.mesh.material_ids[f]);
    }
    r.corners.insert(r.corners.end(), s.mesh.indices.begin(), s.mesh.indices.end());
    r.non_faces += s.lines.num_line_vertices.size() + s.points.indices.size();
  }
  r.small_faces = count_of(warn, "Degenerated face found");
  for (size_t p = warn.find("material [ '"); p != std::string::npos; p = warn.find("material [ '", p + 1))
    r.unknown_materials.push_back(warn.substr(p + 12, warn.find("' ]", p + 12) - (p + 12)));
  return r;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Compares everything glint uses; returns the first difference ("" when none).
std::string difference(const Reference& ref, const ObjData& obj) {
  const auto& a = ref.attrib;
  if (a.vertices.size() != 3 * obj.positions.size()) return "vertex count";
  for (size_t v = 0; v < obj.positions.size(); ++v) {
    const Vec3f& p = obj.positions[v];
    if (!same_bits(a.vertices[3 * v], p.x) || !same_bits(a.vertices[3 * v + 1], p.y) ||
        !same_bits(a.vertices[3 * v + 2], p.z))
      return "vertex " + std::to_string(v);
  }
  if (a.normals.size() != 3 * obj.normals.size()) return "normal count";
  for (size_t v = 0; v < obj.normals.size(); ++v) {
    const Vec3f& n = obj.normals[v];
    if (!same_bits(a.normals[3 * v], n.x) || !same_bits(a.normals[3 * v + 1], n.y) ||
        !same_bits(a.normals[3 * v + 2], n.z))
      return "normal " + std::to_string(v);
  }
  if (a.texcoords.size() != 2 * obj.texcoords.size()) return "texture coordinate count";
  for (size_t v = 0; v < obj.texcoords.size(); ++v)
    if (!same_bits(a.texcoords[2 * v], obj.texcoords[v].u) || !same_bits(a.texcoords[2 * v + 1], obj.texcoords[v].v))
      return "texture coordinate " + std::to_string(v);
  if (ref.face_sizes.size() != obj.face_count()) return "face count";
  if (ref.corners.size() != obj.corner_vertex.size()) return "corner count";
  for (size_t f = 0; f < obj.face_count(); ++f) {
    if (obj.face_start[f + 1] - obj.face_start[f] != ref.face_sizes[f]) return "size of face " + std::to_string(f);
    if (obj.face_material[f] != ref.face_material[f]) return "material of face " + std::to_string(f);
  }
  for (size_t c = 0; c < ref.corners.size(); ++c) {
    const int vt = obj.corner_texcoord.empty() ? -1 : obj.corner_texcoord[c];
    const int vn = obj.corner_normal.empty() ? -1 : obj.corner_normal[c];
    if (ref.corners[c].vertex_index != static_cast<int>(obj.corner_vertex[c]) || ref.corners[c].texcoord_index != vt ||
        ref.corners[c].normal_index != vn)
      return "corner " + std::to_string(c);
  }
  if (ref.materials.size() != obj.materials.size()) return "material count";
  for (size_t m = 0; m < obj.materials.size(); ++m)
    if (ref.materials[m].name != obj.materials[m].name ||
        std::memcmp(ref.materials[m].diffuse, obj.materials[m].diffuse, sizeof(ref.materials[m].diffuse)) != 0)
      return "material " + std::to_string(m);
  if (ref.unknown_materials != obj.unknown_materials) return "usemtl names not found";
  if (ref.small_faces != obj.small_faces) return "faces with fewer than 3 corners";
  if (ref.non_faces != obj.non_faces) return "lines and points kept";
  return "";
}

// The text glint reads (obj.cpp strips a UTF-8 byte-order mark); empty for
// what glint never hands to the reader (UTF-16, binary content).
std::string_view readable_text(const std::string& bytes) {
  std::string_view text = bytes;
  if (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF") return {};
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  if (text.find('\0') != std::string_view::npos) return {};
  return text;
}

// Both readers on one text (its materials in `folder`): the same result, or
// both reject it. Counts it as compared or rejected.
void expect_same_text_as_tinyobj(std::string_view text, const fs::path& folder, const std::string& name,
                                 size_t& compared, size_t& rejected) {
  const Reference ref = read_with_tinyobj(text, folder);
  const TextProblem check = find_obj_bad_statement(text);
  for (size_t chunks : {size_t{1}, size_t{3}}) {
    MtlReader mtl(folder);
    if (!ref.ok || check.line > 0) {
      // glint rejected the file before (its check, or tinyobjloader's error).
      EXPECT_THROW(read_obj(text, name, &mtl, {chunks, 2}), Error) << ref.err << check.message;
      if (chunks == 1) ++rejected;
      continue;
    }
    ObjData obj;
    ASSERT_NO_THROW(obj = read_obj(text, name, &mtl, {chunks, 2}));
    EXPECT_EQ(difference(ref, obj), "") << chunks << " chunks";
    EXPECT_EQ(obj.bad_vertex_text.size(), scan_obj_nonfinite_text(text).size());
    if (chunks == 1) ++compared;
  }
}

// Both readers on one file: the same result, or both reject it.
void expect_same_as_tinyobj(const fs::path& path, size_t& compared, size_t& rejected) {
  SCOPED_TRACE(path.string());
  const std::string bytes = slurp(path);
  const std::string_view text = readable_text(bytes);
  if (text.empty()) return;
  expect_same_text_as_tinyobj(text, path.parent_path(), path.string(), compared, rejected);
}

TEST(ObjReader, ReadsEveryRepositoryObjAsTinyobjloaderDoes) {
  const fs::path root = GLINT_SOURCE_DIR;
  size_t compared = 0, rejected = 0;
  for (const char* dir : {"scenes", "tests", "bench", "fuzz", "docs", "examples"})
    for (const fs::path& p : obj_files_under(root / dir)) expect_same_as_tinyobj(p, compared, rejected);
  EXPECT_GE(compared, 8u);  // scenes/meshes, tests/meshes at least
  std::printf("compared %zu OBJ files of the repository, %zu rejected by both\n", compared, rejected);
}

TEST(ObjReader, ReadsEveryAssimpTestModelAsTinyobjloaderDoes) {
  const std::vector<fs::path> files = obj_files_under(kModels);
  if (files.empty())
    GTEST_SKIP() << kModels << " has no OBJ files: install Debian's assimp-testmodels to run this comparison";
  size_t compared = 0, rejected = 0;
  for (const fs::path& p : files) expect_same_as_tinyobj(p, compared, rejected);
  EXPECT_GE(compared, 10u);
  std::printf("compared %zu OBJ files of assimp-testmodels, %zu rejected by both\n", compared, rejected);
}

// The same text read in 1 to 40 chunks gives the same arrays.
void expect_same_for_any_chunks(const std::string& text, const ObjData& expected, const fs::path& folder) {
  for (size_t chunks = 1; chunks <= 40; ++chunks) {
    SCOPED_TRACE(std::to_string(chunks) + " chunks");
    MtlReader mtl(folder);
    const ObjData obj = read_obj(text, "t.obj", &mtl, {chunks, 3});
    EXPECT_EQ(obj.positions.size(), expected.positions.size());
    for (size_t v = 0; v < std::min(obj.positions.size(), expected.positions.size()); ++v)
      EXPECT_TRUE(same_bits(obj.positions[v].x, expected.positions[v].x)) << v;
    EXPECT_EQ(obj.face_start, expected.face_start);
    EXPECT_EQ(obj.corner_vertex, expected.corner_vertex);
    EXPECT_EQ(obj.corner_texcoord, expected.corner_texcoord);
    EXPECT_EQ(obj.corner_normal, expected.corner_normal);
    EXPECT_EQ(obj.face_material, expected.face_material);
    EXPECT_EQ(obj.unknown_materials, expected.unknown_materials);
    EXPECT_EQ(obj.small_faces, expected.small_faces);
    EXPECT_EQ(obj.non_faces, expected.non_faces);
    ASSERT_EQ(obj.bad_vertex_text.size(), expected.bad_vertex_text.size());
    for (size_t i = 0; i < obj.bad_vertex_text.size(); ++i) {
      EXPECT_EQ(obj.bad_vertex_text[i].vertex, expected.bad_vertex_text[i].vertex);
      EXPECT_EQ(obj.bad_vertex_text[i].line, expected.bad_vertex_text[i].line);
      EXPECT_EQ(obj.bad_vertex_text[i].column, expected.bad_vertex_text[i].column);
    }
  }
}

TEST(ObjReader, ChunkBoundariesFollowLineEndsAndNeverSplitCrLf) {
  const std::string text = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
  for (size_t chunks = 1; chunks <= 12; ++chunks) {
    const std::vector<size_t> b = split_obj_chunks(text, chunks);
    ASSERT_EQ(b.size(), chunks + 1);
    EXPECT_EQ(b.front(), 0u);
    EXPECT_EQ(b.back(), text.size());
    for (size_t i = 1; i < chunks; ++i) {
      EXPECT_GE(b[i], b[i - 1]);
      EXPECT_TRUE(b[i] == text.size() || text[b[i] - 1] == '\n') << chunks << " chunks, boundary " << i;
    }
  }
  // Two chunks of this 16-byte text aim at offset 8, the '\n' of the first
  // "\r\n": the cut would fall inside it and moves past the '\n'.
  const std::string crlf = "v 1 2 3\r\nf 1 1 1";
  ASSERT_EQ(crlf.substr(7, 2), "\r\n");
  EXPECT_EQ(split_obj_chunks(crlf, 2), (std::vector<size_t>{0, 9, crlf.size()}));
}

// A file whose statements cross every chunk boundary: indices that count
// back into earlier chunks, a usemtl whose material holds in later chunks,
// CRLF and LF line ends, comments, blank lines, polygons and small faces.
std::string mixed_text() {
  std::string t = "mtllib materials.mtl\r\n# a comment\r\nusemtl illum2\r\n";
  for (int i = 0; i < 60; ++i) {
    const double x = i * 0.37, y = (i % 7) * 1.5;
    t += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(-x) + (i % 2 ? "\r\n" : "\n");
    t += "vn 0 0 1\n";
    t += "vt " + std::to_string(i * 0.01) + " 0.5\n";
    if (i % 3 == 2) {
      t += "f -3/-3/-3 -2/-2/-2 -1/-1/-1\r\n";  // counts back across chunks
      t += "f 1 -2 -1   \t\n\n";                // absolute and relative mixed, trailing blanks
    }
    if (i == 20) t += "usemtl illum5\n";
    if (i == 30) t += "g second\nusemtl nosuch\n";
    if (i == 40) t += "usemtl illum2\no third\nf -1 -2\nl 1 2 3\n";
    if (i >= 4 && i % 10 == 4) t += "f -5//-5 -4//-4 -3//-3 -2//-2 -1//-1\n";  // a pentagon
  }
  return t;
}

TEST(ObjReader, SameResultForAnyNumberOfChunks) {
  const fs::path folder = fs::path(GLINT_SOURCE_DIR) / "tests" / "meshes";
  const std::string text = mixed_text();
  MtlReader mtl(folder);
  const ObjData one = read_obj(text, "t.obj", &mtl, {1, 1});
  // The values themselves: the first face counts back from vertex 3.
  ASSERT_GE(one.face_count(), 40u);
  EXPECT_EQ(one.corner_vertex[0], 0u);
  EXPECT_EQ(one.corner_vertex[2], 2u);
  EXPECT_EQ(one.corner_normal[2], 2);
  EXPECT_EQ(one.corner_texcoord[2], 2);
  EXPECT_EQ(one.small_faces, 1u);
  EXPECT_GT(one.non_faces, 0u);
  EXPECT_EQ(one.unknown_materials, std::vector<std::string>{"nosuch"});
  // usemtl illum2 (near the start) holds for faces far into later chunks.
  ASSERT_FALSE(one.materials.empty());
  const int red = one.face_material[0];
  ASSERT_GE(red, 0);
  EXPECT_EQ(one.materials[static_cast<size_t>(red)].name, "illum2");
  EXPECT_EQ(one.face_material[12], red);
  expect_same_for_any_chunks(text, one, folder);
  // Among those splits, cuts aimed inside a "\r\n" (at its '\n'), and a usemtl
  // in the first chunk whose material holds in the last.
  size_t inside_crlf = 0;
  for (size_t chunks = 2; chunks <= 40; ++chunks)
    for (size_t i = 1; i < chunks; ++i) {
      const size_t aim = text.size() / chunks * i;
      if (text[aim] == '\n' && text[aim - 1] == '\r') ++inside_crlf;
    }
  EXPECT_GT(inside_crlf, 0u);
  EXPECT_EQ(one.face_material.back(), red);
  // And tinyobjloader agrees.
  const Reference ref = read_with_tinyobj(text, folder);
  ASSERT_TRUE(ref.ok) << ref.err;
  EXPECT_EQ(difference(ref, one), "");
  for (size_t chunks : {1, 2, 3, 7}) {
    MtlReader m(folder);
    EXPECT_EQ(difference(ref, read_obj(text, "t.obj", &m, {chunks, 2})), "") << chunks;
  }
}

// An error found in a late chunk is reported as with one chunk: the same
// message, line and column.
TEST(ObjReader, ErrorsAreTheSameForAnyNumberOfChunks) {
  std::string base;
  for (int i = 0; i < 50; ++i) base += "v " + std::to_string(i) + " 1 0\nf -1 -1 -1\n";
  const std::vector<std::string> bad = {
      base + "f 1 2 -52\n",      // counts back past the first vertex
      base + "f 1 2 51\n",       // beyond the last vertex so far
      base + "f 1 0 2\n",        // index 0
      base + "f 1 2 3/x\n",      // not a number
      base + "v 1 2\n",          // too few numbers
      base + "vn 1 a 2\n",       // not a number
      base + "f 1/1/1/1 2 3\n",  // tinyobjloader's error
      base + "f 1// 2// 3//\n",  // ditto
  };
  for (const std::string& text : bad) {
    SCOPED_TRACE(text.substr(base.size()));
    std::string first;
    for (size_t chunks : {1, 2, 3, 7, 20}) {
      try {
        read_obj(text, "t.obj", nullptr, {chunks, 2});
        ADD_FAILURE() << "no error with " << chunks << " chunks";
      } catch (const Error& e) {
        if (first.empty()) first = e.what();
        EXPECT_EQ(std::string(e.what()), first) << chunks << " chunks";
      }
    }
    EXPECT_NE(first.find("t.obj:101"), std::string::npos) << first;
  }
}

// The statements tinyobjloader rejects and the check lets pass are reported
// at the first corner rejected.
TEST(ObjReader, LibraryRejectionsNameTheirCorner) {
  const std::string base = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"f 1// 2// 3//\n", "t.obj:6:3: face with a vertex index of 0 or not a number"},
      {"f 1 2/1/1/1 3\n", "t.obj:6:5: face with a vertex index of 0 or not a number"},
      {"f  1 2 3//\n", "t.obj:6:8: face with a vertex index of 0 or not a number"},
      {"l 1 2//\n", "t.obj:6:5: line or point with a vertex index of 0 or not a number"},
  };
  for (const auto& [statement, message] : cases) {
    try {
      read_obj(base + statement, "t.obj", nullptr, {1, 1});
      ADD_FAILURE() << "no error for " << statement;
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), message) << statement;
    }
  }
}

// "nan"/"inf" vertex texts are found in every chunk, at their line and column.
TEST(ObjReader, NonFiniteVertexTextsAtTheirPlace) {
  std::string text;
  for (int i = 0; i < 30; ++i) text += i == 25 ? "v 1 -inf 0\n" : i == 7 ? "v nan 0 0\n" : "v 1 2 3\n";
  text += "f 1 2 3\n";
  MtlReader mtl(".");
  const ObjData obj = read_obj(text, "t.obj", nullptr, {1, 1});
  ASSERT_EQ(obj.bad_vertex_text.size(), 2u);
  EXPECT_EQ(obj.bad_vertex_text[0].vertex, 7u);
  EXPECT_EQ(obj.bad_vertex_text[0].line, 8);
  EXPECT_EQ(obj.bad_vertex_text[0].column, 3);
  EXPECT_EQ(obj.bad_vertex_text[1].vertex, 25u);
  EXPECT_EQ(obj.bad_vertex_text[1].line, 26);
  EXPECT_EQ(obj.bad_vertex_text[1].column, 5);
  EXPECT_EQ(obj.bad_vertex_text[1].text, "-inf");
  EXPECT_EQ(obj.positions[25].y, 0.0f);  // read as 0, as tinyobjloader did
  expect_same_for_any_chunks(text, obj, ".");
}

}  // namespace
}  // namespace glint::mesh_io

namespace glint::mesh_io {
namespace {

// The reader takes the common corner and number forms on a fast path and
// everything else through the general one: each form, alone on its face or
// number line, must read as tinyobjloader reads it (or fail as before).
TEST(ObjReader, EveryCornerAndNumberFormReadsAsTinyobjloaderReadsIt) {
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 0 1 0\n";
  const std::vector<std::string> faces = {"f 1 2 3",
                                          "f 1 2 3 4",
                                          "f\t1  2\t3 ",
                                          "f 1/1 2/2 3/3",
                                          "f 1//1 2//2 3//1",
                                          "f 1/1/1 2/2/2 3/3/2",
                                          "f 1/1 2//2 3/3/1",
                                          "f 01 002 3",
                                          "f -4 -3 -2",
                                          "f +1 +2 +3",
                                          "f 1 2 5",
                                          "f 1 2 0",
                                          "f 1/4 2/1 3/1",
                                          "f 1//3 2//1 3//1",
                                          "f 1/ 2/ 3/",
                                          "f 1// 2// 3//",
                                          "f 1/1/ 2/2/ 3/3/",
                                          "f 1/1/1/1 2 3",
                                          "f 1 2 3x",
                                          "f 1 2 3#c",
                                          "f 1 2 1234567890123456789",
                                          "f 1 2 99999999999999999",
                                          "f 1/-1 2/-2 3/-3",
                                          "f 1//-1 2//-2 3//-2",
                                          "f 1 2 3\r",
                                          "f 1 2 3\v",
                                          "f 1 2 -5",
                                          "f 1 2 3 4 5 6 7 8 9"};
  const std::vector<std::string> numbers = {
      "v 0.5 -1 2",  "v .5 -.5 5.",    "v 1e3 -2E-2 3e+1",   "v -0 0 +0",   "v 1e40 1 1",
      "v 1e-50 1 1", "v 0e5 1 1",      "v 1e9999999999 1 1", "v +-1 1 1",   "v 1 2 3x",
      "v 1 2",       "v 1,5 2 3",      "v nan 1 1",          "v -inf 1 1",  "v 1 2 3 4",
      "v 1\t2\t3",   "vn 0.25 -0.5 1", "vt 0.5 0.25",        "vt 1.5abc 2", "v 1.000000000000000000001 2 3",
      "v 0x10 1 1",  "v 1e 2 3",       "v 1 2 3\r"};
  size_t compared = 0, rejected = 0;
  for (const std::string& face : faces) {
    SCOPED_TRACE(face);
    expect_same_text_as_tinyobj(head + face + "\n", ".", "t.obj", compared, rejected);
  }
  for (const std::string& number : numbers) {
    SCOPED_TRACE(number);
    expect_same_text_as_tinyobj(head + number + "\nf 1 2 3\n", ".", "t.obj", compared, rejected);
  }
  EXPECT_GE(compared, 25u);  // the forms both read
  EXPECT_GE(rejected, 10u);  // and those both refuse
}

// Numbers glint's check lets pass but tinyobjloader reads in its own way
// ("+-5" and "nan" as no number: 0; an exponent above 214748364x: 0; the
// v of "vt u v" is not checked at all): read as it read them.
TEST(ObjReader, OddNumbersAreReadAsTinyobjloaderReadThem) {
  const std::string text =
      "v +-5 .5 5.\nv -0.0 +.5e1 1e-50\nv 1e9999999999 -0 +3\nv nan -inf INF\nv 1e40 2 3\n"
      "vn +-5 0.125 3\nvn 1e+2 -.25 0\nvt 0.5 1.5abc\nvt 1 x\nvt 2\nvt +.5 -\n"
      "f 1/1/1 2/2/2 3/3/1\nf 1/4/2 4/4/2 5/1/1\n";
  const Reference ref = read_with_tinyobj(text, ".");
  ASSERT_TRUE(ref.ok) << ref.err;
  for (size_t chunks : {1, 2, 5}) {
    const ObjData obj = read_obj(text, "t.obj", nullptr, {chunks, 2});
    EXPECT_EQ(difference(ref, obj), "") << chunks << " chunks";
    EXPECT_EQ(obj.positions[0].x, 0.0f);        // "+-5"
    EXPECT_EQ(obj.positions[1].y, 5.0f);        // "+.5e1"
    EXPECT_EQ(obj.positions[2].x, 0.0f);        // the exponent tinyobjloader gives up on
    EXPECT_EQ(obj.texcoords[0].v, 1.5f);        // "1.5abc": the number at its start
    EXPECT_EQ(obj.bad_vertex_text.size(), 3u);  // nan, -inf, INF
  }
}

}  // namespace
}  // namespace glint::mesh_io
