// The common back end of every mesh reader: triangles as the libraries gave
// them (RawMesh) -> glint's MeshFile, with the contract's rules applied.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "glint/error.h"
#include "glint/io/mesh_file.h"

namespace glint::mesh_io {

// A vertex whose text was "nan"/"inf" (or overflowed) where the library read a
// finite number; an error only if a triangle uses it.
struct BadVertexText {
  uint32_t vertex;
  int line, column;
  std::string text;
};

struct RawMesh {
  std::vector<Vec3f> positions;
  std::vector<uint32_t> indices;  // 3 per triangle
  std::vector<Vec3f> normals;     // 3 per triangle when has_normals; (0,0,0): none for that corner
  bool has_normals = false;
  std::vector<UVf> uvs;  // 3 per triangle when has_uvs; (0,0) for a corner without one
  bool has_uvs = false;
  std::vector<int32_t> triangle_material;  // per triangle
  std::vector<Material> materials;
  std::vector<MeshTexture> textures;
  std::vector<std::string> warnings;
  std::vector<BadVertexText> bad_vertex_text;
  // The error for a used vertex that is NaN/Inf in memory (file:line where known).
  std::function<Error(uint32_t vertex)> nonfinite_vertex_error;
  size_t small_faces = 0;  // faces with fewer than 3 vertices (skipped)
  size_t non_faces = 0;    // points and lines
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

// How finish() cuts the triangles into runs for its passes over them in
// parallel. The result does not depend on it (tests compare them).
struct FinishOptions {
  size_t threads = 0;  // 0: one per hardware thread
  size_t triangles_per_run = 65536;
};

// Polygons triangulated already; checks the vertices the triangles use
// (NaN/Inf is an error), drops zero-area triangles (one counted warning),
// gives every corner a unit normal when `vertex_normals` (the file's, or
// angle-weighted per vertex index), and removes unused vertices and unnamed
// unused materials. Throws glint::Error when no triangle is left. The
// arrays of `raw` become the MeshFile's, rewritten in place.
MeshFile finish(RawMesh raw, const std::string& file, bool vertex_normals, const FinishOptions& options = {});

}  // namespace glint::mesh_io
