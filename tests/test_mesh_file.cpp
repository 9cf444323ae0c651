// load_mesh_file against the contract (shared/spec/scene-format.md, "objects":
// mesh, "Mesh normals", the MTL table) and issue 3's "Bad input": OBJ with MTL
// (every illum), polygons triangulated, file vs angle-weighted normals,
// degenerate triangles, PLY ASCII and binary, glTF, and every error class
// with its message and location. Fixtures live in tests/meshes/; broken files
// are written per test into a temporary folder.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "glint/error.h"
#include "glint/io/mesh_file.h"
#include "needs_assimp.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

fs::path fixture(const std::string& name) { return fs::path(GLINT_SOURCE_DIR) / "tests" / "meshes" / name; }

// A fresh folder per test for files written on the fly.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("glint-mesh-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  fs::path write(const std::string& name, const std::string& bytes) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The load must fail with a glint::Error whose message holds `part`, at this line:column.
void expect_error(const fs::path& path, const std::string& part, int line = 0, int column = 0) {
  try {
    load_mesh_file(path);
    ADD_FAILURE() << path << ": loaded, expected an error with '" << part << "'";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find(part), std::string::npos) << "message: " << e.what();
    EXPECT_EQ(e.location().file, path.string()) << e.what();
    EXPECT_EQ(e.location().line, line) << e.what();
    EXPECT_EQ(e.location().column, column) << e.what();
  }
}

void expect_vec(const Vec3f& got, double x, double y, double z, double tol = 1e-6) {
  EXPECT_NEAR(got.x, x, tol);
  EXPECT_NEAR(got.y, y, tol);
  EXPECT_NEAR(got.z, z, tol);
}

void expect_color(const Color& got, double r, double g, double b, const std::string& what) {
  EXPECT_NEAR(got.x, r, 1e-6) << what;
  EXPECT_NEAR(got.y, g, 1e-6) << what;
  EXPECT_NEAR(got.z, b, 1e-6) << what;
}

size_t count_containing(const std::vector<std::string>& lines, const std::string& part) {
  size_t n = 0;
  for (const auto& l : lines) n += l.find(part) != std::string::npos;
  return n;
}

const Material& material_named(const MeshFile& m, const std::string& name) {
  for (const Material& mat : m.materials)
    if (mat.name == name) return mat;
  throw std::runtime_error("no material " + name);
}

Vec3f corner_position(const MeshFile& m, size_t triangle, int corner) {
  return m.positions[m.indices[3 * triangle + corner]];
}

// --- OBJ and MTL -------------------------------------------------------------

TEST(MeshFileObj, UsemtlGivesEachFaceItsMaterial) {
  const MeshFile m = load_mesh_file(fixture("materials.obj"));
  ASSERT_EQ(m.triangle_count(), 14u);
  ASSERT_EQ(m.materials.size(), 13u);
  EXPECT_EQ(m.triangle_material[0], -1);  // before any usemtl
  const char* names[] = {"illum0", "illum1", "illum2", "illum3",  "illum4",   "illum5", "illum6",
                         "illum7", "illum8", "illum9", "illum10", "defaults", "gray"};
  for (size_t t = 1; t < 14; ++t) {
    ASSERT_GE(m.triangle_material[t], 0);
    EXPECT_EQ(m.materials[m.triangle_material[t]].name, names[t - 1]) << "triangle " << t;
  }
}

TEST(MeshFileObj, IllumModelsMapByTheContractTable) {
  const MeshFile m = load_mesh_file(fixture("materials.obj"));
  const Material& i0 = material_named(m, "illum0");
  EXPECT_TRUE(i0.unlit);
  expect_color(i0.diffuse, 0.1, 0.2, 0.3, "illum 0: the color is Kd");

  const Material& i1 = material_named(m, "illum1");
  expect_color(i1.ambient, 0.05, 0.05, 0.05, "illum 1 Ka");
  expect_color(i1.diffuse, 0.5, 0.5, 0.5, "illum 1 Kd");
  expect_color(i1.specular, 0, 0, 0, "illum 1: specular 0");
  EXPECT_FALSE(i1.unlit);

  const Material& i2 = material_named(m, "illum2");
  expect_color(i2.ambient, 0.1, 0.1, 0.1, "illum 2 Ka");
  expect_color(i2.diffuse, 0.6, 0.5, 0.4, "illum 2 Kd");
  expect_color(i2.specular, 0.3, 0.3, 0.3, "illum 2 Ks");
  EXPECT_DOUBLE_EQ(i2.shininess, 50);
  expect_color(i2.reflectivity, 0, 0, 0, "illum 2: no mirror");

  const Material& i3 = material_named(m, "illum3");
  expect_color(i3.reflectivity, 0.4, 0.5, 0.6, "illum 3: reflectivity = Ks");
  EXPECT_EQ(i3.transparency, 0);
  EXPECT_FALSE(i3.fresnel);

  const Material& i4 = material_named(m, "illum4");
  expect_color(i4.reflectivity, 0.2, 0.2, 0.2, "illum 4 reflectivity");
  EXPECT_NEAR(i4.transparency, 0.75, 1e-6);  // 1 - d
  EXPECT_DOUBLE_EQ(i4.ior, 1.0);             // Ni ignored: glass without bending
  EXPECT_FALSE(i4.fresnel);

  const Material& i5 = material_named(m, "illum5");
  expect_color(i5.reflectivity, 0.3, 0.3, 0.3, "illum 5 reflectivity");
  EXPECT_TRUE(i5.fresnel);
  EXPECT_EQ(i5.transparency, 0);

  // illum 6: transparency = mean over channels of (1 - Ks) * Tf, ior = Ni.
  const Material& i6 = material_named(m, "illum6");
  expect_color(i6.reflectivity, 0.2, 0.4, 0.6, "illum 6 reflectivity");
  EXPECT_NEAR(i6.transparency, (0.8 * 1 + 0.6 * 0.5 + 0.4 * 0) / 3, 1e-6);
  EXPECT_NEAR(i6.ior, 1.33, 1e-6);
  EXPECT_FALSE(i6.fresnel);

  // illum 7: as 6 with fresnel; Tf left out filters nothing.
  const Material& i7 = material_named(m, "illum7");
  EXPECT_NEAR(i7.transparency, 0.9, 1e-6);
  EXPECT_NEAR(i7.ior, 2.0, 1e-6);
  EXPECT_TRUE(i7.fresnel);

  // 8, 9, 10 read as 2, 4, 1.
  const Material& i8 = material_named(m, "illum8");
  expect_color(i8.specular, 0.5, 0.5, 0.5, "illum 8 as 2");
  expect_color(i8.reflectivity, 0, 0, 0, "illum 8 as 2");
  const Material& i9 = material_named(m, "illum9");
  expect_color(i9.reflectivity, 0.5, 0.5, 0.5, "illum 9 as 4");
  EXPECT_NEAR(i9.transparency, 0.6, 1e-6);
  EXPECT_DOUBLE_EQ(i9.ior, 1.0);
  const Material& i10 = material_named(m, "illum10");
  expect_color(i10.specular, 0, 0, 0, "illum 10 as 1");
  expect_color(i10.reflectivity, 0, 0, 0, "illum 10 as 1");
}

TEST(MeshFileObj, KeysTheMtlLeavesOutTakeTheContractDefaults) {
  const MeshFile m = load_mesh_file(fixture("materials.obj"));
  const Material& d = material_named(m, "defaults");
  const Material contract;  // glint::Material's defaults are the contract's
  expect_color(d.ambient, contract.ambient.x, contract.ambient.y, contract.ambient.z, "ambient");
  expect_color(d.diffuse, 0.8, 0.8, 0.8, "diffuse");
  expect_color(d.specular, 0, 0, 0, "specular");
  EXPECT_DOUBLE_EQ(d.shininess, 32);
  expect_color(d.reflectivity, 0, 0, 0, "reflectivity");
  EXPECT_EQ(d.transparency, 0);
  EXPECT_DOUBLE_EQ(d.ior, 1.5);
  EXPECT_FALSE(d.fresnel);
  EXPECT_FALSE(d.unlit);  // illum left out is 2
}

TEST(MeshFileObj, OneValueColorIsGrayAndNsZeroIsOneWithOneWarning) {
  const MeshFile m = load_mesh_file(fixture("materials.obj"));
  const Material& g = material_named(m, "gray");
  expect_color(g.diffuse, 0.25, 0.25, 0.25, "Kd 0.25 means gray");
  EXPECT_DOUBLE_EQ(g.shininess, 1);
  const std::string mtl = (fixture("materials.mtl")).string();
  EXPECT_EQ(count_containing(m.warnings, "Ns below 1 read as 1"), 1u);
  EXPECT_EQ(count_containing(m.warnings, mtl + ":63: Ns below 1 read as 1 (1 material)"), 1u);
}

TEST(MeshFileObj, Illum8To10WarnOncePerFileWithACount) {
  const MeshFile m = load_mesh_file(fixture("materials.obj"));
  EXPECT_EQ(count_containing(m.warnings, "illum 8, 9, 10 read as 2, 4, 1"), 1u);
  EXPECT_EQ(count_containing(m.warnings, "(3 materials)"), 1u);
}

TEST(MeshFileObj, MissingTextureIsAWarning) {
  const MeshFile m = load_mesh_file(fixture("materials.obj"));
  EXPECT_EQ(count_containing(m.warnings, "1 texture file not found (defaults used): 'missing_texture.png'"), 1u);
  EXPECT_EQ(m.warnings.size(), 3u);  // Ns, illum 8-10, texture: nothing else
}

TEST(MeshFileObj, MissingMtlIsAWarningAndDefaultsAreUsed) {
  const MeshFile m = load_mesh_file(fixture("missing_mtl.obj"));
  ASSERT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.triangle_material[0], -1);
  EXPECT_TRUE(m.materials.empty());
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_EQ(m.warnings[0], fixture("missing_mtl.obj").string() +
                               ": material library 'nowhere.mtl' not found (default materials used)");
}

TEST(MeshFileObj, UsemtlOfAnUnknownNameIsAWarning) {
  TempDir dir;
  dir.write("m.mtl", "newmtl red\nKd 1 0 0\n");
  const fs::path obj = dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl blue\nf 1 2 3\n");
  const MeshFile m = load_mesh_file(obj);
  EXPECT_EQ(m.triangle_material[0], -1);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_NE(m.warnings[0].find("usemtl 'blue' not in the material library"), std::string::npos);
}

// A file of triangles only hands its corners and face materials over as
// they stand (obj.cpp); one quad more sends it through the triangulation.
// Both must give the same triangles, materials included.
TEST(MeshFileObj, TrianglesOnlyAndMixedFacesGiveTheSameTriangles) {
  TempDir dir;
  dir.write("m.mtl", "newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\n");
  const std::string triangles =
      "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
      "f 1 2 3\nusemtl green\nf 1 3 4\nusemtl blue\nf 2 3 5\nusemtl red\nf -5 -4 -1\n";
  const MeshFile only = load_mesh_file(dir.write("only.obj", triangles));
  const MeshFile mixed = load_mesh_file(dir.write("mixed.obj", triangles + "usemtl green\nf 1 2 3 4\n"));
  ASSERT_EQ(only.triangle_count(), 4u);
  ASSERT_EQ(mixed.triangle_count(), 6u);
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3, 1, 2, 4, 0, 1, 4};
  EXPECT_EQ(only.indices, indices);
  EXPECT_EQ(std::vector<uint32_t>(mixed.indices.begin(), mixed.indices.begin() + 12), indices);
  const auto material = [](const MeshFile& m, size_t t) {
    return m.triangle_material[t] < 0 ? std::string("-") : m.materials[m.triangle_material[t]].name;
  };
  const char* expected[] = {"-", "green", "-", "red"};
  for (size_t t = 0; t < 4; ++t) {
    EXPECT_EQ(material(only, t), expected[t]) << "triangle " << t;
    EXPECT_EQ(material(mixed, t), expected[t]) << "triangle " << t;
  }
  EXPECT_EQ(material(mixed, 4), "green");
  EXPECT_EQ(material(mixed, 5), "green");
}

TEST(MeshFileObj, QuadsSplitOnTheShorterDiagonalAndPolygonsFan) {
  const MeshFile m = load_mesh_file(fixture("quads.obj"));
  ASSERT_EQ(m.triangle_count(), 5u);
  // The kite: diagonal 1-3 (length 2) rather than 2-4 (length 6).
  const uint32_t want[5][3] = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {4, 7, 8}};
  for (size_t t = 0; t < 5; ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.indices[3 * t + k], want[t][k]) << "triangle " << t;
  expect_vec(m.positions[1], 1, -3, 0);
  for (const Vec3f& n : m.corner_normals) expect_vec(n, 0, 0, 1);
}

TEST(MeshFileObj, PolygonsOfMoreThan255Vertices) {
  // tinyobjloader counts a face's vertices in 8 bits; the loader recovers.
  TempDir dir;
  std::string text;
  const int n = 300;
  for (int i = 0; i < n; ++i) {  // piece by piece: `"v " + std::string` trips GCC 12's bogus -Wrestrict
    text += "v ";
    text += std::to_string(std::cos(2 * M_PI * i / n));
    text += ' ';
    text += std::to_string(std::sin(2 * M_PI * i / n));
    text += " 0\n";
  }
  text += "v 5 5 0\nv 6 5 0\nv 5 6 0\nf";
  for (int i = 1; i <= n; ++i) {
    text += ' ';
    text += std::to_string(i);
  }
  text += "\nf 301 302 303\n";
  const MeshFile m = load_mesh_file(dir.write("big.obj", text));
  EXPECT_EQ(m.triangle_count(), size_t(n - 2 + 1));
  expect_vec(corner_position(m, n - 2, 0), 5, 5, 0);
}

// An OBJ of 20 MB is read in pieces on all cores (obj.cpp, 8 MiB each):
// every vertex and face must come out whole and in order.
TEST(MeshFileObj, ABigFileReadInPiecesLoadsWhole) {
  const TempDir dir;
  constexpr int kSide = 600;  // 360,000 vertices, 717,602 triangles, about 20 MB
  std::string text;
  text.reserve(size_t{22} << 20);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) text += "v " + std::to_string(i) + " " + std::to_string(j) + " 0.5\n";
  auto vertex = [](int i, int j) { return static_cast<uint32_t>(j * kSide + i); };
  std::vector<uint32_t> expected;
  for (int j = 0; j + 1 < kSide; ++j)
    for (int i = 0; i + 1 < kSide; ++i) {
      for (uint32_t v :
           {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)})
        expected.push_back(v);
      text += "f " + std::to_string(vertex(i, j) + 1) + " " + std::to_string(vertex(i + 1, j) + 1) + " " +
              std::to_string(vertex(i + 1, j + 1) + 1) + "\nf " + std::to_string(vertex(i, j) + 1) + " " +
              std::to_string(vertex(i + 1, j + 1) + 1) + " " + std::to_string(vertex(i, j + 1) + 1) + "\n";
    }
  ASSERT_GT(text.size(), size_t{16} << 20);  // three pieces or more
  const MeshFile m = load_mesh_file(dir.write("big.obj", text));
  ASSERT_EQ(m.positions.size(), size_t{kSide} * kSide);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      const Vec3f& p = m.positions[vertex(i, j)];
      ASSERT_TRUE(p.x == static_cast<float>(i) && p.y == static_cast<float>(j) && p.z == 0.5f) << i << " " << j;
    }
  EXPECT_EQ(m.indices, expected);
}

TEST(MeshFileObj, NegativeIndicesCountBack) {
  TempDir dir;
  const MeshFile m = load_mesh_file(dir.write("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"));
  ASSERT_EQ(m.triangle_count(), 1u);
  expect_vec(corner_position(m, 0, 2), 0, 1, 0);
}

TEST(MeshFileObj, PositionsAreTheFilesAsFloat) {
  TempDir dir;
  const MeshFile m = load_mesh_file(dir.write("p.obj", "v 0.1 -2.5 1e3\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  expect_vec(m.positions[0], 0.1f, -2.5f, 1000.0f, 0);
}

TEST(MeshFileObj, ByteOrderMarksAndUtf16) {
  TempDir dir;
  const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(load_mesh_file(dir.write("bom.obj", "\xEF\xBB\xBF" + text)).triangle_count(), 1u);
  std::string utf16 = "\xFF\xFE";
  for (char c : text) utf16 += std::string{c, '\0'};
  EXPECT_EQ(load_mesh_file(dir.write("utf16.obj", utf16)).triangle_count(), 1u);
}

// --- normals -----------------------------------------------------------------

TEST(MeshFileNormals, FromTheFileNormalizedWithZeroLengthFallingBack) {
  const MeshFile m = load_mesh_file(fixture("normals.obj"));
  ASSERT_EQ(m.triangle_count(), 2u);
  expect_vec(m.corner_normals[0], 0, 0.6, 0.8);                          // tilted, as the file says
  expect_vec(m.corner_normals[1], 0, 0, 1);                              // "vn 0 0 2" normalized
  expect_vec(m.corner_normals[2], 0, 0, 1);                              // "vn 0 0 0": computed
  for (int k = 3; k < 6; ++k) expect_vec(m.corner_normals[k], 0, 0, 1);  // face without normals
}

TEST(MeshFileNormals, CubeCornersAreAngleWeighted) {
  const MeshFile m = load_mesh_file(fixture("cube.obj"));
  ASSERT_EQ(m.triangle_count(), 12u);
  const double s = 1 / std::sqrt(3.0);
  for (size_t c = 0; c < m.indices.size(); ++c) {
    const Vec3f p = m.positions[m.indices[c]];
    // Outward along the diagonal through the corner, whatever the triangulation.
    expect_vec(m.corner_normals[c], (p.x - 0.5) * 2 * s, (p.y - 0.5) * 2 * s, (p.z - 0.5) * 2 * s);
  }
}

TEST(MeshFileNormals, AngleWeightsNotAreaWeights) {
  const MeshFile m = load_mesh_file(fixture("fan.obj"));
  ASSERT_EQ(m.triangle_count(), 2u);
  // Vertex 1 (index 0) is corner 0 of both triangles: 90 degrees each.
  const double h = 1 / std::sqrt(2.0);
  expect_vec(m.corner_normals[0], h, 0, h);
  expect_vec(m.corner_normals[3], h, 0, h);
  // Area weighting would have given (5, 0, 1) / sqrt(26): far from this.
  EXPECT_GT(std::abs(m.corner_normals[0].x - 5 / std::sqrt(26.0)), 0.2);
  // Vertex 3 (0,1,0) is shared too: angles atan(1) = 45 deg (+z) and atan(5) (+x).
  const double a = std::atan(1.0), b = std::atan(5.0), len = std::hypot(a, b);
  expect_vec(m.corner_normals[2], b / len, 0, a / len);
  // Vertex 2 and 4 belong to one triangle each: that face's normal.
  expect_vec(m.corner_normals[1], 0, 0, 1);
  expect_vec(m.corner_normals[4], 1, 0, 0);
}

TEST(MeshFileNormals, VerticesAreNotMergedByPosition) {
  // Two faces at right angles that share an edge by position only.
  TempDir dir;
  const MeshFile m = load_mesh_file(
      dir.write("split.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\nf 4 6 5\n"));
  ASSERT_EQ(m.triangle_count(), 2u);
  for (int k = 0; k < 3; ++k) expect_vec(m.corner_normals[k], 0, 0, 1);
  for (int k = 3; k < 6; ++k) expect_vec(m.corner_normals[k], 0, -1, 0);
}

TEST(MeshFileNormals, OppositeFacesOnOneVertexFallBackToTheFaceNormal) {
  TempDir dir;
  const MeshFile m = load_mesh_file(dir.write("two-sided.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n"));
  ASSERT_EQ(m.triangle_count(), 2u);
  for (int k = 0; k < 3; ++k) expect_vec(m.corner_normals[k], 0, 0, 1);
  for (int k = 3; k < 6; ++k) expect_vec(m.corner_normals[k], 0, 0, -1);
}

TEST(MeshFileNormals, DegenerateTrianglesDroppedWithOneCountedWarning) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  const fs::path path = fixture("degenerate.obj");
  const MeshFile m = load_mesh_file(path);
  ASSERT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.positions.size(), 4u);  // vertices only the dropped ones used are gone
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_EQ(m.warnings[0], path.string() + ": dropped 2 degenerate triangles");
  for (const Vec3f& n : m.corner_normals) expect_vec(n, 0, 0, 1);
  EXPECT_EQ(m.triangle_material.size(), 2u);
}

// --- PLY -------------------------------------------------------------------

// quad_normals.ply's mesh as binary PLY, little or big endian.
std::string binary_ply(bool big_endian, int face_count = 2) {
  const float v[5][6] = {
      {0, 0, 0, 0, 0, 1}, {1, 0, 0, 0, 0, 1}, {1, 1, 0, 0, 0.6f, 0.8f}, {0, 1, 0, 0, 0, 1}, {2, 0, 0, 0, 0, -1}};
  std::string out = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\nelement face " +
                    std::to_string(face_count) + "\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&](const void* p, size_t n) {
    std::string bytes(static_cast<const char*>(p), n);
    if (big_endian) std::reverse(bytes.begin(), bytes.end());
    out += bytes;
  };
  for (const auto& row : v)
    for (float f : row) put(&f, 4);
  const std::vector<std::vector<int32_t>> faces = {{0, 1, 2, 3}, {1, 4, 2}};
  for (const auto& f : faces) {
    out += static_cast<char>(f.size());
    for (int32_t i : f) put(&i, 4);
  }
  return out;
}

void expect_quad_normals_mesh(const MeshFile& m) {
  ASSERT_EQ(m.triangle_count(), 3u);
  ASSERT_EQ(m.positions.size(), 5u);
  expect_vec(m.positions[4], 2, 0, 0);
  // The square's diagonals tie: split as (0,1,3), (1,2,3); then the triangle.
  const uint32_t want[9] = {0, 1, 3, 1, 2, 3, 1, 4, 2};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(m.indices[i], want[i]) << i;
  expect_vec(m.corner_normals[4], 0, 0.6, 0.8);  // vertex 2: the file's normal
  expect_vec(m.corner_normals[7], 0, 0, -1);     // vertex 4
  for (int32_t mat : m.triangle_material) EXPECT_EQ(mat, -1);
  EXPECT_TRUE(m.warnings.empty());
}

// Built without assimp (GLINT_ASSIMP off), PLY and glTF files are refused
// with one clear message naming the file, before they are read; OBJ always works.
TEST(MeshFileSupport, PlyAndGltfNeedAssimp) {
  EXPECT_EQ(missing_mesh_support("a.obj"), "");
  const std::string missing = missing_mesh_support("a.ply");
  for (const char* name : {"b.PLY", "c.gltf", "d.glb"}) EXPECT_EQ(missing_mesh_support(name), missing) << name;
  if (missing.empty()) GTEST_SKIP() << "built with assimp: PLY and glTF meshes are read";
  EXPECT_EQ(missing, "this glint was built without assimp: PLY and glTF meshes are not available");
  const fs::path ply = fixture("quad_normals.ply");
  try {
    load_mesh_file(ply);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.message(), missing);
    EXPECT_EQ(e.location().file, ply.string());
  }
}

TEST(MeshFilePly, AsciiWithNormalsAndAQuad) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  expect_quad_normals_mesh(load_mesh_file(fixture("quad_normals.ply")));
}

TEST(MeshFilePly, BinaryLittleAndBigEndianMatchAscii) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  expect_quad_normals_mesh(load_mesh_file(dir.write("le.ply", binary_ply(false))));
  expect_quad_normals_mesh(load_mesh_file(dir.write("be.ply", binary_ply(true))));
}

TEST(MeshFilePly, WithoutNormalsTheyAreComputed) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  const MeshFile m = load_mesh_file(
      dir.write("plain.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 1\nproperty list uchar uint vertex_index\nend_header\n0 0 0\n0 1 0\n0 0 1\n3 0 1 2\n"));
  ASSERT_EQ(m.triangle_count(), 1u);
  for (const Vec3f& n : m.corner_normals) expect_vec(n, 1, 0, 0);
}

TEST(MeshFilePly, FacesOfFewerThanThreeVerticesAreSkippedWithAWarning) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  const fs::path p = dir.write(
      "short.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 3\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n0\n");
  const MeshFile m = load_mesh_file(p);
  EXPECT_EQ(m.triangle_count(), 1u);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_EQ(m.warnings[0], p.string() + ": skipped 2 faces with fewer than 3 vertices");
}

// --- glTF ------------------------------------------------------------------

void expect_triangle_gltf(const MeshFile& m) {
  ASSERT_EQ(m.triangle_count(), 2u);  // one mesh, two nodes
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].name, "paint");
  expect_color(m.materials[0].diffuse, 0.2, 0.4, 0.6, "baseColorFactor");
  EXPECT_EQ(m.triangle_material[0], 0);
  EXPECT_EQ(m.triangle_material[1], 0);
  // The second node: scale 2, then translate by 5 in x.
  bool moved = false;
  for (size_t t = 0; t < 2; ++t) {
    const Vec3f p = corner_position(m, t, 1);
    if (p.x > 4) {
      moved = true;
      expect_vec(p, 7, 0, 0);
      expect_vec(corner_position(m, t, 2), 5, 2, 0);
    }
  }
  EXPECT_TRUE(moved);
  for (const Vec3f& n : m.corner_normals) expect_vec(n, 0, 0, 1);
}

TEST(MeshFileGltf, NodesPlaceTheMeshAndMaterialsMap) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  expect_triangle_gltf(load_mesh_file(fixture("triangle.gltf")));
}

TEST(MeshFileGltf, BinaryGlb) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  // triangle.gltf's JSON with its data moved into a GLB's BIN chunk.
  std::ifstream in(fixture("triangle.gltf"));
  std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t uri = json.find("\"uri\"");
  ASSERT_NE(uri, std::string::npos);
  const size_t end = json.find('"', json.find(':', uri) + 3);
  json.erase(json.rfind(',', uri), end + 1 - json.rfind(',', uri));
  while (json.size() % 4) json += ' ';
  std::string bin(44, '\0');
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const uint16_t idx[3] = {0, 1, 2};
  std::memcpy(bin.data(), pos, 36);
  std::memcpy(bin.data() + 36, idx, 6);
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string glb = "glTF" + u32(2) + u32(12 + 8 + json.size() + 8 + bin.size()) + u32(json.size()) + "JSON" +
                          json + u32(bin.size()) + std::string("BIN\0", 4) + bin;
  TempDir dir;
  expect_triangle_gltf(load_mesh_file(dir.write("triangle.glb", glb)));
  expect_error(dir.write("cut.glb", glb.substr(0, glb.size() - 10)), "truncated");
}

// --- errors ------------------------------------------------------------------

TEST(MeshFileErrors, MissingFileDirectoryAndUnsupportedFormat) {
  TempDir dir;
  expect_error(dir.path() / "nothing.obj", "mesh file not found");
  fs::create_directories(dir.path() / "folder.obj");
  expect_error(dir.path() / "folder.obj", "is a directory");
  expect_error(dir.write("model.stl", "solid x\nendsolid x\n"), "unsupported mesh format '.stl'");
  expect_error(dir.write("model", "v 0 0 0\n"), "unsupported mesh format ''");
}

TEST(MeshFileErrors, EmptyFiles) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  expect_error(dir.write("empty.obj", ""), "empty file");
  expect_error(dir.write("blank.obj", "\n  \n\t\n"), "empty file");
  expect_error(dir.write("empty.ply", ""), "empty file");
  expect_error(dir.write("empty.gltf", ""), "empty file");
}

TEST(MeshFileErrors, NoTriangles) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  expect_error(dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n"), "no triangles (only points or lines)");
  expect_error(dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n"), "no triangles (only points or lines)");
  expect_error(dir.write("cloud.obj", "v 0 0 0\nv 1 0 0\n"), "no triangles (vertices only)");
  expect_error(dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n"),
               "no triangles (all 2 are degenerate)");
  expect_error(dir.write("cloud.ply",
                         "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                         "property float z\nend_header\n0 0 0\n1 1 1\n"),
               "no triangles (vertices only)");
}

TEST(MeshFileErrors, NotAMeshFile) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  expect_error(dir.write("image.obj", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)),
               "not a Wavefront OBJ file (binary content)");
  expect_error(dir.write("notes.obj", "Shopping list:\n- milk\n- eggs\n"),
               "no vertices or faces: not a Wavefront OBJ file");
  expect_error(dir.write("notes.ply", "hello\n"), "not a PLY file");
  expect_error(dir.write("notes.gltf", "<html></html>"), "not a glTF file");
  expect_error(dir.write("notes.glb", "just text, no magic"), "not a binary glTF file");
  expect_error(dir.write("object.gltf", "{\"hello\": 1}"), "no asset.version: not a glTF 2.0 file", 1, 1);
  expect_error(dir.write("v1.gltf", "{\"asset\": {\"version\": \"1.0\"}, \"meshes\": {}}"),
               "asset.version: glTF 1.0 is not supported (only glTF 2.0)", 1, 23);
  expect_error(dir.write("no-meshes.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": {}}"), "cannot read glTF");
  expect_error(dir.write("obj-inside.gltf", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "not a glTF file");
}

TEST(MeshFileErrors, ObjIndicesOutOfRangeWithLineAndColumn) {
  TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expect_error(dir.write("high.obj", v + "f 1 2 3\nf 1 2 9\n"), "vertex index 9 out of range (3 vertices)", 5, 7);
  expect_error(dir.write("quad.obj", v + "f 1 2 3 4\n"), "vertex index 4 out of range (3 vertices)", 4, 9);
  expect_error(dir.write("neg.obj", v + "f -1 -2 -4\n"), "vertex index -4 out of range", 4, 9);
  expect_error(dir.write("normal.obj", v + "vn 0 0 1\nf 1//1 2//1 3//2\n"), "normal index 2 out of range (1 normal)", 5,
               13);
  expect_error(dir.write("zero.obj", v + "f 0 1 2\n"), "vertex index of 0 (OBJ counts from 1, or back from -1)", 4, 3);
  expect_error(dir.write("word.obj", v + "f a b c\n"), "vertex index 'a' is not a whole number", 4, 3);
  expect_error(dir.write("line.obj", v + "l 1 0\n"), "vertex index of 0", 4, 5);
}

// tinyobjloader reads indices with atoi and coordinates that are not numbers
// as 0: such files loaded as other meshes, silently.
TEST(MeshFileErrors, ObjIndicesThatAreNotWholeNumbersOrOverflow) {
  TempDir dir;
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  // atoi wrapped this to -1: the last vertex.
  expect_error(dir.write("huge.obj", v + "f 1 2 99999999999999999999\n"),
               "vertex index '99999999999999999999' out of range", 4, 7);
  expect_error(dir.write("big.obj", v + "f 1 2 4294967298\n"), "vertex index 4294967298 out of range (3 vertices)", 4,
               7);
  expect_error(dir.write("fraction.obj", v + "f 1.5 2 3\n"), "vertex index '1.5' is not a whole number", 4, 3);
  expect_error(dir.write("suffix.obj", v + "f 1 2 3x\n"), "vertex index '3x' is not a whole number", 4, 7);
  expect_error(dir.write("uv.obj", v + "vt 0 0\nf 1/1 2/1 3/9\n"),
               "texture coordinate index 9 out of range (1 texture coordinate)", 5, 11);
  expect_error(dir.write("uv-word.obj", v + "vt 0 0\nf 1/1 2/x 3/1\n"),
               "texture coordinate index 'x' is not a whole number", 5, 7);
  expect_error(dir.write("normal-neg.obj", v + "vn 0 0 1\nf 1//-1 2//-2 3//-1\n"),
               "normal index -2 out of range (1 normal before it)", 5, 9);
}

TEST(MeshFileErrors, ObjCoordinatesThatAreNotNumbers) {
  TempDir dir;
  expect_error(dir.write("word.obj", "v 0 0 0\nv a b c\nv 0 1 0\nf 1 2 3\n"), "vertex coordinate 'a' is not a number",
               2, 3);
  expect_error(dir.write("comma.obj", "v 0 0 0\nv 1,5 0 0\nv 0 1 0\nf 1 2 3\n"),
               "vertex coordinate '1,5' is not a number", 2, 3);
  expect_error(dir.write("short.obj", "v 0 0 0\nv 1\nv 0 1 0\nf 1 2 3\n"), "vertex with 1 number (x y z needed)", 2, 4);
  expect_error(dir.write("normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1\nf 1//1 2//1 3//1\n"),
               "normal with 2 numbers (x y z needed)", 4, 7);
  expect_error(dir.write("uv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt u v\nf 1/1 2/1 3/1\n"),
               "texture coordinate 'u' is not a number", 4, 4);
  // What the loader accepts: more numbers than needed (w, vertex colors),
  // a comment after them, 2 or 3 texture coordinates, and nan/inf (an error
  // only where a triangle uses it).
  const MeshFile m = load_mesh_file(dir.write(
      "fine.obj", "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 # top\nv nan 0 0\nvt 0.5\nvt 0 1 0\nf 1/1 2/2 3/1\n"));
  EXPECT_EQ(m.triangle_count(), 1u);
}

// tinyobjloader reads an MTL number it cannot parse as 0: "Kd nan 0 0" was
// black, "illum x" unlit, with no word said. The error names the .mtl file.
TEST(MeshFileErrors, MtlNumbersThatAreNotNumbersNonFiniteOrNegative) {
  TempDir dir;
  const std::string obj = "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  auto expect_mtl_error = [&](const std::string& mtl, const std::string& part, int line, int column) {
    const fs::path mtl_path = dir.write("m.mtl", mtl);
    try {
      load_mesh_file(dir.write("m.obj", obj));
      ADD_FAILURE() << "loaded, expected an error with '" << part << "' for " << mtl;
    } catch (const Error& e) {
      EXPECT_NE(e.message().find(part), std::string::npos) << "message: " << e.what();
      EXPECT_NE(e.message().find("(material library of " + (dir.path() / "m.obj").string() + ")"), std::string::npos)
          << e.what();
      EXPECT_EQ(e.location().file, mtl_path.lexically_normal().string()) << e.what();
      EXPECT_EQ(e.location().line, line) << e.what();
      EXPECT_EQ(e.location().column, column) << e.what();
    }
  };
  expect_mtl_error("newmtl a\nKd nan 0 0\n", "Kd 'nan' is not a finite number", 2, 4);
  expect_mtl_error("newmtl a\nKd 0.5 0.5 1e999\n", "Kd '1e999' is not a finite number", 2, 12);
  expect_mtl_error("newmtl a\nKa 0 -1 0\n", "Ka '-1': color components must be >= 0", 2, 6);
  expect_mtl_error("newmtl a\n  Ks red\n", "Ks 'red' is not a number", 2, 6);
  expect_mtl_error("newmtl a\nKd xyz 1 1 1\n", "(only r g b colors are read)", 2, 4);
  expect_mtl_error("newmtl a\nKd 1 1\n", "Kd: 1 or 3 numbers, not 2", 2, 6);
  expect_mtl_error("# first\nnewmtl a\nKd 1 1 1\nNs inf\n", "Ns 'inf' is not a finite number", 4, 4);
  expect_mtl_error("newmtl a\nillum x\n", "illum 'x' is not a whole number", 2, 7);
  expect_mtl_error("newmtl a\nd 0.5x\n", "d '0.5x' is not a number", 2, 3);
  // Accepted: one number for a gray, more than three (ignored), Ns 0 (a warning).
  dir.write("m.mtl", "newmtl a\nKd 0.5\nKs 1 1 1 1\nNs 0\nillum 2\n");
  const MeshFile m = load_mesh_file(dir.write("m.obj", obj));
  EXPECT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(count_containing(m.warnings, "Ns below 1 read as 1"), 1u);
}

TEST(MeshFileErrors, ObjNonFiniteVerticesUsedByATriangle) {
  TempDir dir;
  expect_error(dir.write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"),
               "vertex coordinate 'nan' is not a finite number", 2, 5);
  expect_error(dir.write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -INF\nf 1 2 3\n"),
               "vertex coordinate '-INF' is not a finite number", 3, 7);
  expect_error(dir.write("huge.obj", "v 0 0 0\n# comment\nv 1 0 1e40\nv 0 1 0\nf 1 2 3\n"),
               "vertex coordinate is not a finite number", 3);
  // Not used by any triangle: no error.
  const MeshFile m = load_mesh_file(dir.write("unused.obj", "v nan 0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 2 3 4\n"));
  EXPECT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.positions.size(), 3u);
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(MeshFileErrors, PlyAsciiBadData) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  expect_error(dir.write("index.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
               "vertex index 3 out of range (3 vertices)", 13, 7);
  expect_error(dir.write("negative.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"), "vertex index -1 out of range",
               13, 5);
  expect_error(dir.write("nan.ply", kPlyHead + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
               "vertex coordinate 'nan' is not a finite number", 11, 3);
  expect_error(dir.write("inf.ply", kPlyHead + "0 0 0\n1 0 0\n0 1e999 0\n3 0 1 2\n"),
               "vertex coordinate '1e999' is not a finite number", 12, 3);
  expect_error(dir.write("float.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 -4e38\n3 0 1 2\n"),
               "vertex coordinate '-4e38' is not a finite number", 12, 5);
  expect_error(dir.write("word.ply", kPlyHead + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"), "'zero' is not a number", 11, 3);
  expect_error(dir.write("short.ply", kPlyHead + "0 0 0\n1 0\n0 1 0\n3 0 1 2\n"), "too few values", 11);
  // Too short for the counts at all, or short by a record.
  expect_error(dir.write("cut.ply", kPlyHead + "0 0 0\n1 0 0\n"),
               "truncated or corrupt: the header claims 3 'vertex' elements but only 12 bytes of data follow", 3);
  expect_error(dir.write("cut2.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n\n\n\n\n"),
               "truncated: the header promises 1 'face' elements but the file ends after 0");
  expect_error(dir.write("list.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n9 0 1 2\n"),
               "list length 9 does not match the values on the line", 13, 1);
}

TEST(MeshFileErrors, PlyBadHeaders) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  expect_error(dir.write("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"), "no end_header");
  expect_error(dir.write("noformat.ply", "ply\nelement vertex 0\nend_header\n"), "no format line");
  expect_error(dir.write("format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
               "unknown PLY format 'binary_middle_endian'", 2, 8);
  expect_error(dir.write("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"),
               "unknown PLY type 'quad'", 4, 10);
  expect_error(dir.write("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n"),
               "no x, y, z properties", 3);
  expect_error(dir.write("novertex.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n"), "no vertex element");
  expect_error(dir.write("count.ply", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n"),
               "bad PLY element count '-3'", 3, 16);
}

TEST(MeshFileErrors, PlyAbsurdCountsAreRefusedBeforeAllocating) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  // Counts that would fit in memory but not in the file (claims beyond
  // memory are refused earlier: MeshFileLimits below).
  std::string ascii = kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  ascii.replace(ascii.find("vertex 3"), 8, "vertex 4000000");
  expect_error(dir.write("ascii.ply", ascii),
               "the header claims 4000000 'vertex' elements but only 26 bytes of data follow", 3);
  std::string binary = binary_ply(false);
  binary.replace(binary.find("face 2"), 6, "face 20000000");
  expect_error(dir.write("binary.ply", binary), "the header claims 20000000 'face' elements", 10);
  // A list length that the rest of the file cannot hold.
  std::string list = binary_ply(false);
  list[list.size() - 13] = static_cast<char>(250);
  expect_error(dir.write("list.ply", list), "truncated");
}

TEST(MeshFileErrors, PlyBinaryTruncatedAtEveryByteIsAnError) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  const std::string whole = binary_ply(false);
  const size_t body = whole.find("end_header\n") + 11;
  for (size_t size = body; size < whole.size(); ++size) {
    const fs::path p = dir.write("cut.ply", whole.substr(0, size));
    try {
      load_mesh_file(p);
      ADD_FAILURE() << "cut at " << size << " loaded";
    } catch (const Error& e) {
      EXPECT_NE(e.message().find("truncated"), std::string::npos) << e.what();
    }
  }
}

TEST(MeshFileErrors, PlyBinaryBadData) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  std::string index = binary_ply(false);
  index[index.size() - 4] = 7;  // the last index: 2 -> 7
  expect_error(dir.write("index.ply", index), "face 1: vertex index 7 out of range (5 vertices)");
  std::string nan = binary_ply(true);
  const size_t body = nan.find("end_header\n") + 11;
  const unsigned char quiet_nan[4] = {0x7f, 0xc0, 0, 0};
  std::memcpy(nan.data() + body + 24 + 4, quiet_nan, 4);  // vertex 1, y
  expect_error(dir.write("nan.ply", nan), "vertex 1 has a non-finite coordinate");
}

// 1-based line and column of byte `offset` of `text`.
std::pair<int, int> line_and_column(const std::string& text, size_t offset) {
  int line = 1, column = 1;
  for (size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') ++line, column = 1;
    else ++column;
  }
  return {line, column};
}

TEST(MeshFileErrors, GltfBrokenData) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  std::ifstream in(fixture("triangle.gltf"));
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string count = good;
  count.replace(count.find("\"count\": 3,"), 11, "\"count\": 3000000,");
  expect_error(dir.write("count.gltf", count),
               "accessors[0]: 3000000 elements need 36000000 bytes of buffer view 0, which has 36", 63, 3);
  // A buffer's base64 must decode (assimp's decoder leaks when it throws).
  std::string base64 = good;
  base64[base64.find("base64,AAAA") + 7] = '*';
  expect_error(dir.write("base64.gltf", base64), "buffers[0].uri: a data URI whose base64 does not decode", 101, 11);
  std::string missing = good;
  missing.replace(missing.find("data:application"), 16, "nowhere.bin#");
  expect_error(dir.write("missing.gltf", missing), "cannot read glTF");
  // An external buffer file shorter than its byteLength (assimp leaked its
  // stream when it threw on that).
  std::string external = good;
  const size_t uri = external.find("data:application");
  external.replace(uri, external.find('"', uri) - uri, "short.bin");
  dir.write("short.bin", std::string(10, '\0'));
  const size_t length = external.find("\"byteLength\"", external.find("\"buffers\""));
  const auto [line, column] = line_and_column(external, external.find(':', length) + 2);
  expect_error(dir.write("external.gltf", external), "buffers[0].byteLength: 44 bytes, but 'short.bin' holds 10", line,
               column);
}

// --- memory limits -------------------------------------------------------------

// Claims in the gigabytes must exceed half of this machine's memory for the
// tests that use the default budget; skip on machines too big for that.
#define SKIP_IF_MEMORY_ABOVE(bytes)                                                      \
  if (static_cast<double>(default_memory_budget()) >= (bytes))                           \
  GTEST_SKIP() << "this machine has too much memory for a " << (bytes) / double(1 << 30) \
               << " GiB claim to exceed half of it"

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The error's message for loading `path` with `budget` ("" if it loads).
std::string message_for(const fs::path& path, size_t budget) {
  try {
    load_mesh_file(path, budget);
  } catch (const Error& e) {
    return e.message();
  }
  return "";
}

TEST(MeshFileLimits, PlyHeaderClaimingMoreThanHalfOfMemoryIsRefusedUpFront) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  SKIP_IF_MEMORY_ABOVE(4e9 * kBytesPerVertex);
  TempDir dir;
  // A 150-byte file whose header claims 4e9 vertices: refused before assimp
  // (or the truncation check) sees it, at the vertex element's line.
  std::string ply = kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  ply.replace(ply.find("vertex 3"), 8, "vertex 4000000000");
  const fs::path p = dir.write("huge.ply", ply);
  expect_error(p, "the header claims 4000000000 vertices and 1 face: that needs ", 3);
  EXPECT_NE(message_for(p, default_memory_budget()).find("GiB, more than half of this machine's"), std::string::npos);
  // Faces weigh more than vertices: the face line is the culprit.
  std::string faces = binary_ply(false);
  faces.replace(faces.find("face 2"), 6, "face 2000000000");
  expect_error(dir.write("faces.ply", faces), "the header claims 5 vertices and 2000000000 faces: that needs ", 10);
}

TEST(MeshFileLimits, ExplicitBudgetRefusesWhatTheDefaultAllows) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  // 3 vertices and 10 faces (the same triangle): 3 * 24 + 10 * 100 = 1072
  // bytes by the estimate, in a file of about 250.
  std::string ply = kPlyHead + "0 0 0\n1 0 0\n0 1 0\n";
  ply.replace(ply.find("face 1"), 6, "face 10");
  for (int i = 0; i < 10; ++i) ply += "3 0 1 2\n";
  const fs::path p = dir.write("small.ply", ply);
  ASSERT_LT(fs::file_size(p), 1071u);
  EXPECT_EQ(message_for(p, default_memory_budget()), "");
  EXPECT_EQ(message_for(p, 1071),
            "the header claims 3 vertices and 10 faces: that needs 1.05 KiB, more than the memory budget of 1.05 KiB");
  EXPECT_EQ(message_for(p, 1072), "");
}

TEST(MeshFileLimits, GltfAccessorCountBeyondMemoryIsRefusedAtTheCount) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  SKIP_IF_MEMORY_ABOVE(4e9 * 12);
  TempDir dir;
  // The error is at the count's value: its line and column in the text.
  auto expect_count_error = [&](const std::string& name, const std::string& text) {
    const size_t at = text.find("4000000000");
    const size_t line_start = text.rfind('\n', at) + 1;
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<ptrdiff_t>(at), '\n'));
    expect_error(dir.write(name, text), "accessors[0].count: 4000000000 elements: that needs 44.7 GiB, more than half",
                 line, static_cast<int>(at - line_start) + 1);
  };
  std::string gltf = slurp(fixture("triangle.gltf"));
  gltf.replace(gltf.find("\"count\": 3,"), 11, "\"count\": 4000000000,");
  expect_count_error("huge.gltf", gltf);
  // No buffer at all (a sparse or all-zero accessor): assimp would allocate it.
  std::string zeros = gltf;
  zeros.erase(zeros.find("\"bufferView\": 0,"), 16);
  expect_count_error("zeros.gltf", zeros);
}

TEST(MeshFileLimits, GltfInstancesCountAgainstTheBudget) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  // triangle.gltf's mesh placed by 20 nodes.
  std::string gltf = slurp(fixture("triangle.gltf"));
  std::string nodes, refs;
  for (int i = 0; i < 20; ++i) {
    const std::string sep = i ? "," : "";
    nodes += sep + "{\"mesh\":0,\"translation\":[" + std::to_string(2 * i) + ",0,0]}";
    refs += sep + std::to_string(i);
  }
  const size_t scenes = gltf.find("\"scenes\"");
  gltf.replace(scenes, gltf.find("\"meshes\"") - scenes,
               "\"scenes\": [{\"nodes\": [" + refs + "]}], \"nodes\": [" + nodes + "], ");
  TempDir dir;
  const fs::path p = dir.write("twenty.gltf", gltf);
  // A 44-byte buffer, 42 bytes of accessor data, 20 instances of 3 vertices
  // and 1 triangle: 44 + 42 + 20 * (3 * 24 + 100) = 3526 bytes, in a file of
  // about 2 KiB.
  ASSERT_LT(fs::file_size(p), 3525u);
  EXPECT_EQ(load_mesh_file(p, 3526).triangle_count(), 20u);
  EXPECT_EQ(message_for(p, 3525),
            "the accessors claim 60 vertices and 20 triangles (instances counted): that needs 3.44 KiB, more than the "
            "memory budget of 3.44 KiB");
}

TEST(MeshFileLimits, GlbJsonChunkIsCheckedToo) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  SKIP_IF_MEMORY_ABOVE(4e9 * 12);
  TempDir dir;
  std::string glb = slurp(fs::path(GLINT_SOURCE_DIR) / "fuzz/corpus/glb/triangle.glb");
  const size_t at = glb.find("\"count\":3,");
  ASSERT_NE(at, std::string::npos);
  glb.replace(at, 10, "\"count\":4000000000,");  // 9 bytes longer: fix both lengths
  auto add_to_u32 = [&](size_t offset, uint32_t add) {
    uint32_t v;
    std::memcpy(&v, glb.data() + offset, 4);
    v += add;
    std::memcpy(glb.data() + offset, &v, 4);
  };
  add_to_u32(8, 9);
  add_to_u32(12, 9);
  expect_error(dir.write("huge.glb", glb), "accessors[0].count: 4000000000 elements: that needs");
  std::string cut = glb.substr(0, 30);
  expect_error(dir.write("cut.glb", cut), "truncated");
}

TEST(MeshFileLimits, ObjTrianglesAreCheckedBeforeTheyAreBuilt) {
  TempDir dir;
  // One polygon of 250 corners: 248 triangles (about 30 KB by the
  // estimate) from a file of about 3 KB.
  std::string obj;
  for (int i = 0; i < 250; ++i) {
    obj += "v ";
    obj += std::to_string(i);
    obj += i % 2 ? " 1 0\n" : " 0 0\n";
  }
  obj += "f";
  for (int i = 1; i <= 250; ++i) {
    obj += ' ';
    obj += std::to_string(i);
  }
  const fs::path p = dir.write("fan.obj", obj + "\n");
  const double bytes = 248 * kBytesPerTriangle + 250 * kBytesPerVertex;
  ASSERT_LT(double(fs::file_size(p)), bytes - 1);
  EXPECT_EQ(message_for(p, size_t(bytes)), "");
  EXPECT_EQ(message_for(p, size_t(bytes) - 1).rfind("248 triangles (about): that needs ", 0), 0u)
      << message_for(p, size_t(bytes) - 1);
}

TEST(MeshFileLimits, GltfBufferLengthBeyondTheBudgetIsRefused) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  const fs::path p = dir.write("t.gltf", slurp(fixture("triangle.gltf")));
  EXPECT_EQ(message_for(p, 10000), "");
  std::string big = slurp(fixture("triangle.gltf"));
  big.replace(big.find("\"byteLength\": 44"), 16, "\"byteLength\": 20000");
  EXPECT_EQ(message_for(dir.write("big.gltf", big), 10000),
            "buffers[0].byteLength: 20000 bytes: that needs 19.5 KiB, more than the memory budget of 9.77 KiB");
}

TEST(MeshFileLimits, FilesLargerThanTheBudgetAreNotRead) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  // A cube behind a long comment: more file than mesh.
  const fs::path cube = dir.write("cube.obj", "# " + std::string(4000, '-') + "\n" + slurp(fixture("cube.obj")));
  const size_t size = fs::file_size(cube);
  EXPECT_EQ(message_for(cube, size), "");
  EXPECT_EQ(message_for(cube, size - 1).rfind("file of " + format_bytes(double(size)) + ": reading it needs", 0), 0u)
      << message_for(cube, size - 1);
  // With the machine's budget: a sparse file (no disk space used) just beyond it.
  const fs::path big = dir.write("big.ply", "ply\n");
  fs::resize_file(big, default_memory_budget() + 1);
  expect_error(big, "reading it needs");
}

TEST(MeshFileLimits, DevicesAreNotMeshFiles) {
  TempDir dir;
  fs::create_symlink("/dev/zero", dir.path() / "zero.obj");
  expect_error(dir.path() / "zero.obj", "not a regular file");
}

// Random damage to valid files of every format: the loader either reads the
// result or throws glint::Error; nothing else escapes and nothing crashes.
TEST(MeshFileErrors, DamagedFilesOnlyEverThrowGlintErrors) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> originals = {{"m.obj", slurp(fixture("normals.obj"))},
                                                                      {"q.obj", slurp(fixture("quads.obj"))},
                                                                      {"a.ply", slurp(fixture("quad_normals.ply"))},
                                                                      {"le.ply", binary_ply(false)},
                                                                      {"be.ply", binary_ply(true)},
                                                                      {"t.gltf", slurp(fixture("triangle.gltf"))}};
  std::mt19937 rng(12345);
  const char noise[] = {'0', '9', '-', ' ', '\n', '/', 'e', '.', '\0', '\xff', 'n', '#'};
  for (const auto& [name, original] : originals) {
    for (int round = 0; round < 150; ++round) {
      std::string bytes = original;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits && !bytes.empty(); ++e) {
        const size_t at = rng() % bytes.size();
        switch (rng() % 4) {
          case 0: bytes[at] = noise[rng() % sizeof noise]; break;
          case 1: bytes.erase(at, 1 + rng() % 8); break;
          case 2: bytes.insert(at, 1, noise[rng() % sizeof noise]); break;
          default: bytes[at] = static_cast<char>(rng()); break;
        }
      }
      const fs::path p = dir.write(name, bytes);
      try {
        const MeshFile m = load_mesh_file(p);
        // What loads is well formed.
        ASSERT_EQ(m.indices.size() % 3, 0u);
        ASSERT_EQ(m.corner_normals.size(), m.indices.size());
        ASSERT_EQ(m.triangle_material.size(), m.triangle_count());
        for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
        for (const Vec3f& n : m.corner_normals) ASSERT_NEAR(std::hypot(n.x, n.y, n.z), 1.0, 1e-4);
      } catch (const Error&) {
      }
    }
  }
}

}  // namespace
}  // namespace glint
