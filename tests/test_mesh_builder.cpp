// mesh_io::finish (io/mesh/mesh_builder.h), the back end of every mesh
// reader: its passes run in parallel over runs of triangles and rewrite the
// RawMesh's arrays in place, so the MeshFile must not depend on the cut or
// the number of threads -- checked bit for bit against one run on one thread
// on random meshes with degenerate triangles, corners without (or with
// zero, NaN, Inf, tiny) normals, unused vertices, UVs and materials; and on
// a small mesh whose every value is worked out by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "glint/error.h"
#include "glint/io/mesh/common.h"
#include "glint/io/mesh/mesh_builder.h"

namespace glint::mesh_io {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// A mesh with some of everything finish() treats: degenerate triangles
// (repeated indices, and points on a coarse grid that are collinear),
// unused vertices, normals zero, NaN, Inf, tiny or huge, UVs, materials with
// and without names and per-triangle lists shorter or longer than the
// triangles; now and then an index out of range or a NaN vertex.
RawMesh random_mesh(std::mt19937& g, bool errors) {
  std::uniform_int_distribution<int> d(0, 99);
  RawMesh raw;
  const int vertices = 1 + d(g) % 40, triangles = d(g) % 60;
  const int grid = d(g) < 50 ? 4 : 100;
  for (int v = 0; v < vertices; ++v) {
    Vec3f p{float(d(g) % grid) / 3.f, float(d(g) % grid) * 0.7f, float(d(g) % 5)};
    if (errors && d(g) < 2) p.y = kNaN;
    raw.positions.push_back(p);
  }
  const int used = std::max(1, vertices - d(g) % 5);
  raw.has_normals = d(g) < 60;
  raw.has_uvs = d(g) < 40;
  for (int t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      uint32_t i = uint32_t(d(g) % used);
      if (k > 0 && d(g) < 8) i = raw.indices.back();
      if (errors && d(g) < 1) i = uint32_t(vertices + d(g));
      raw.indices.push_back(i);
      if (raw.has_normals) {
        Vec3f n{float(d(g) - 50) * (d(g) < 5 ? 1e30f : 0.1f), float(d(g) - 50), float(d(g) % 3)};
        const int z = d(g);
        if (z < 10) n = {0, 0, 0};
        else if (z < 12) n.x = kNaN;
        else if (z < 13) n.z = -kInf;
        else if (z < 15) n = {1e-44f, 0, 0};
        raw.normals.push_back(n);
      }
      if (raw.has_uvs) raw.uvs.push_back({float(d(g)), float(d(g)) / 7});
    }
  }
  const int materials = d(g) % 4;
  for (int m = 0; m < materials; ++m) {
    raw.materials.emplace_back();
    if (d(g) < 50) raw.materials.back().name = "m" + std::to_string(m);
  }
  const int listed = d(g) < 20 ? d(g) % (triangles + 1) : triangles + (d(g) < 10 ? 3 : 0);
  for (int t = 0; t < listed; ++t) raw.triangle_material.push_back(d(g) % (materials + 2) - 1);
  if (errors && d(g) < 10) raw.bad_vertex_text.push_back({uint32_t(d(g) % (vertices + 1)), 3, 4, "nan"});
  if (d(g) < 10) raw.small_faces = 2;
  return raw;
}

struct Outcome {
  MeshFile mesh;
  std::string error;
};

Outcome run(const RawMesh& raw, bool vertex_normals, FinishOptions options) {
  Outcome o;
  try {
    o.mesh = finish(raw, "m.obj", vertex_normals, options);
  } catch (const Error& e) {
    o.error = e.what();
  }
  return o;
}

void expect_same(const Outcome& a, const Outcome& b, const std::string& what) {
  ASSERT_EQ(a.error, b.error) << what;
  EXPECT_TRUE(same_bits(a.mesh.positions, b.mesh.positions)) << what;
  EXPECT_TRUE(same_bits(a.mesh.indices, b.mesh.indices)) << what;
  EXPECT_TRUE(same_bits(a.mesh.corner_normals, b.mesh.corner_normals)) << what;
  EXPECT_TRUE(same_bits(a.mesh.corner_uvs, b.mesh.corner_uvs)) << what;
  EXPECT_TRUE(same_bits(a.mesh.triangle_material, b.mesh.triangle_material)) << what;
  EXPECT_EQ(a.mesh.warnings, b.mesh.warnings) << what;
  ASSERT_EQ(a.mesh.materials.size(), b.mesh.materials.size()) << what;
  for (size_t m = 0; m < a.mesh.materials.size(); ++m)
    EXPECT_EQ(a.mesh.materials[m].name, b.mesh.materials[m].name) << what;
}

TEST(MeshFinish, SameResultForEveryCutAndThreadCount) {
  std::mt19937 g(20240516);
  size_t loaded = 0, refused = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    const RawMesh raw = random_mesh(g, iter % 4 == 0);
    const bool vertex_normals = iter % 3 != 0;
    const Outcome serial = run(raw, vertex_normals, {1, size_t(1) << 30});
    (serial.error.empty() ? loaded : refused)++;
    for (size_t per_run : {1, 2, 5})
      for (size_t threads : {1, 3})
        expect_same(serial, run(raw, vertex_normals, {threads, per_run}),
                    "mesh " + std::to_string(iter) + ", " + std::to_string(per_run) + " per run, " +
                        std::to_string(threads) + " threads");
    if (testing::Test::HasFailure()) break;
  }
  EXPECT_GT(loaded, 2000u);  // most meshes load; the others fail as the serial run does
  EXPECT_GT(refused, 100u);
}

// Vertices 0..4, vertex 3 unused; triangle 1 degenerate. Every kept face
// lies in z = 0 facing +z, so each computed (angle-weighted) normal is (0, 0, 1).
RawMesh hand_mesh() {
  RawMesh raw;
  raw.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}, {1, 1, 0}};
  raw.indices = {0, 1, 2, 1, 1, 2, 1, 4, 2};
  raw.has_normals = true;
  raw.normals = {{0, 0, 2}, {0, 0, 0}, {0, 3, 4}, {9, 9, 9}, {9, 9, 9}, {9, 9, 9}, {kNaN, 0, 0}, {0, 0, -1}, {1, 0, 0}};
  raw.has_uvs = true;
  raw.uvs = {{0, 0}, {1, 0}, {0, 1}, {7, 7}, {7, 7}, {7, 7}, {1, 0}, {1, 1}, {0, 1}};
  raw.materials.resize(3);
  raw.materials[0].name = "a";
  raw.materials[2].name = "c";  // named: kept though unused; material 1 has no name and goes
  raw.triangle_material = {-1, 0, 0};
  return raw;
}

TEST(MeshFinish, HandWorkedMeshOnEveryCut) {
  for (size_t per_run : {1, 2, 3, 65536}) {
    for (size_t threads : {1, 2}) {
      const MeshFile m = finish(hand_mesh(), "m.obj", true, {threads, per_run});
      const std::vector<Vec3f> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
      EXPECT_TRUE(same_bits(m.positions, positions));
      EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
      // The file's normals made unit ((0, 3, 4) / 5), and computed where a corner has none usable.
      const std::vector<Vec3f> normals = {{0, 0, 1}, {0, 0, 1}, {0, 0.6f, 0.8f}, {0, 0, 1}, {0, 0, -1}, {1, 0, 0}};
      EXPECT_TRUE(same_bits(m.corner_normals, normals));
      const std::vector<UVf> uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 0}, {1, 1}, {0, 1}};
      EXPECT_TRUE(same_bits(m.corner_uvs, uvs));
      EXPECT_EQ(m.triangle_material, (std::vector<int32_t>{-1, 0}));
      ASSERT_EQ(m.materials.size(), 2u);
      EXPECT_EQ(m.materials[0].name, "a");
      EXPECT_EQ(m.materials[1].name, "c");
      EXPECT_EQ(m.warnings, std::vector<std::string>{"m.obj: dropped 1 degenerate triangle"});

      const MeshFile flat = finish(hand_mesh(), "m.obj", false, {threads, per_run});
      EXPECT_TRUE(flat.corner_normals.empty());
      EXPECT_EQ(flat.indices, m.indices);
    }
  }
}

// Opposite faces on the same vertices cancel: their corners take their own face's normal.
TEST(MeshFinish, CancelledVertexNormalsTakeTheFaceNormal) {
  RawMesh raw;
  raw.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  raw.indices = {0, 1, 2, 0, 2, 1};
  for (size_t per_run : {1, 2}) {
    const MeshFile m = finish(raw, "m.obj", true, {2, per_run});
    const std::vector<Vec3f> normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
    EXPECT_TRUE(same_bits(m.corner_normals, normals));
    EXPECT_EQ(m.triangle_material, (std::vector<int32_t>{-1, -1}));
  }
}

std::string error_of(const RawMesh& raw, FinishOptions options) {
  try {
    finish(raw, "m.obj", true, options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Several problems: the one the serial checks met first, whichever run finds which.
TEST(MeshFinish, FirstErrorInFileOrderOnEveryCut) {
  RawMesh raw;
  raw.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {kNaN, 0, 0}};
  raw.indices = {0, 1, 2, 3, 1, 2, 0, 42, 2, 0, 1, 2, 99, 1, 2};
  for (size_t per_run : {1, 2, 100})
    for (size_t threads : {1, 4})
      EXPECT_EQ(error_of(raw, {threads, per_run}), "m.obj: vertex index 42 out of range (4 vertices)");
  raw.indices = {0, 1, 2, 0, 1, 2, 1, 2, 3};  // in range: the NaN vertex, used by the last
  for (size_t per_run : {1, 2, 100})
    EXPECT_EQ(error_of(raw, {2, per_run}), "m.obj: vertex 3 has a non-finite coordinate");
  raw.indices.push_back(7);  // an index beyond the last whole triangle is checked last
  EXPECT_EQ(error_of(raw, {2, 1}), "m.obj: vertex index 7 out of range (4 vertices)");
  raw.indices = {0, 1, 1, 2, 2, 0};
  raw.positions.pop_back();
  EXPECT_EQ(error_of(raw, {2, 1}), "m.obj: no triangles (all 2 are degenerate)");
}

TEST(MeshFinish, ResizeInHugePagesKeepsAndZeroes) {
  std::vector<int32_t> v = {5, 6};
  resize_in_huge_pages(v, size_t(3) << 20);  // 12 MiB: advised
  ASSERT_EQ(v.size(), size_t(3) << 20);
  EXPECT_EQ(v[0], 5);
  EXPECT_EQ(v[1], 6);
  EXPECT_EQ(std::count(v.begin() + 2, v.end(), 0), static_cast<ptrdiff_t>(v.size() - 2));
  resize_in_huge_pages(v, 1);
  EXPECT_EQ(v, std::vector<int32_t>{5});
  fit_capacity(v);
  EXPECT_EQ(v.capacity(), 1u);
  EXPECT_EQ(v, std::vector<int32_t>{5});
}

// The arrays a reader grew by push_back are kept at their exact size (the
// renderer holds them for the whole render).
TEST(MeshFinish, KeepsNoSlackCapacity) {
  RawMesh raw = hand_mesh();
  raw.positions.reserve(1000);
  raw.indices.reserve(3000);
  const MeshFile m = finish(std::move(raw), "m.obj", true, {2, 1});
  EXPECT_EQ(m.positions.capacity(), m.positions.size());
  EXPECT_EQ(m.indices.capacity(), m.indices.size());
  EXPECT_EQ(m.corner_normals.capacity(), m.corner_normals.size());  // 9 corners held, 6 kept
  EXPECT_EQ(m.triangle_material.capacity(), m.triangle_material.size());
}

}  // namespace
}  // namespace glint::mesh_io
