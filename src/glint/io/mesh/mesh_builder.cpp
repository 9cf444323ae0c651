#include "glint/io/mesh/mesh_builder.h"

#include <cmath>
#include <utility>

#include "glint/io/mesh/common.h"

namespace glint::mesh_io {
namespace {

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

// No triangles, indices out of range, and NaN/Inf vertices used by a
// triangle (degenerate or not) are errors.
void check_vertices(const RawMesh& raw, const std::string& file) {
  const size_t vertex_count = raw.positions.size();
  if (raw.indices.size() / 3 == 0) {
    if (raw.non_faces > 0 || raw.small_faces > 0) fail(file, "no triangles (only points or lines)");
    if (vertex_count > 0) fail(file, "no triangles (vertices only)");
    fail(file, "no triangles (no meshes in the file)");
  }
  for (uint32_t i : raw.indices)
    if (i >= vertex_count)
      fail(file,
           "vertex index " + std::to_string(i) + " out of range (" + plural(vertex_count, "vertex", "vertices") + ")");

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
}

// The triangles kept (non-zero area) and their unit face normals.
struct Faces {
  std::vector<uint8_t> keep;
  size_t dropped = 0;
  std::vector<Vec3d> normal;
};

// Drops zero-area triangles (one counted warning); none left is an error.
Faces kept_faces(RawMesh& raw, const std::string& file) {
  const size_t triangle_count = raw.indices.size() / 3;
  Faces faces;
  faces.keep.assign(triangle_count, 1);
  faces.normal.resize(triangle_count);
  for (size_t t = 0; t < triangle_count; ++t) {
    const Vec3d p0 = to_d(raw.positions[raw.indices[3 * t]]);
    const Vec3d p1 = to_d(raw.positions[raw.indices[3 * t + 1]]);
    const Vec3d p2 = to_d(raw.positions[raw.indices[3 * t + 2]]);
    const Vec3d n = cross(sub(p1, p0), sub(p2, p0));
    const double len = length(n);
    if (!(len > 0) || !std::isfinite(len)) {
      faces.keep[t] = 0;
      ++faces.dropped;
      continue;
    }
    faces.normal[t] = {n.x / len, n.y / len, n.z / len};
  }
  if (faces.dropped > 0)
    raw.warnings.push_back(file + ": dropped " + plural(faces.dropped, "degenerate triangle", "degenerate triangles"));
  if (faces.dropped == triangle_count)
    fail(file, triangle_count == 1 ? std::string("no triangles (the only one is degenerate)")
                                   : "no triangles (all " + std::to_string(triangle_count) + " are degenerate)");
  return faces;
}

// The file's normal at a corner, made unit; false when there is none (or it
// is zero or non-finite), so the corner needs a computed one.
bool file_normal(const RawMesh& raw, size_t corner, Vec3d& n) {
  if (!raw.has_normals) return false;
  n = to_d(raw.normals[corner]);
  const double len = length(n);
  if (!(len > 0) || !std::isfinite(len)) return false;
  n = {n.x / len, n.y / len, n.z / len};
  return true;
}

bool needs_computed_normals(const RawMesh& raw, const Faces& faces, bool vertex_normals) {
  bool need_computed = vertex_normals && !raw.has_normals;
  if (vertex_normals && !need_computed) {
    Vec3d n;
    for (size_t t = 0; t < faces.keep.size() && !need_computed; ++t)
      if (faces.keep[t])
        for (int k = 0; k < 3; ++k)
          if (!file_normal(raw, 3 * t + k, n)) need_computed = true;
  }
  return need_computed;
}

// Angle-weighted vertex normals per vertex index: each face adds its unit
// normal times its interior angle at the vertex. All three cross products
// of a triangle's edges have the same length, so angle = atan2(|n|, dot).
std::vector<Vec3d> angle_weighted_normals(const RawMesh& raw, const Faces& faces) {
  std::vector<Vec3d> vertex_normal(raw.positions.size(), Vec3d{0, 0, 0});
  for (size_t t = 0; t < faces.keep.size(); ++t) {
    if (!faces.keep[t]) continue;
    const uint32_t i[3] = {raw.indices[3 * t], raw.indices[3 * t + 1], raw.indices[3 * t + 2]};
    const Vec3d p[3] = {to_d(raw.positions[i[0]]), to_d(raw.positions[i[1]]), to_d(raw.positions[i[2]])};
    const double twice_area = length(cross(sub(p[1], p[0]), sub(p[2], p[0])));
    for (int k = 0; k < 3; ++k) {
      const Vec3d a = sub(p[(k + 1) % 3], p[k]);
      const Vec3d b = sub(p[(k + 2) % 3], p[k]);
      const double angle = std::atan2(twice_area, dot(a, b));
      Vec3d& acc = vertex_normal[i[k]];
      acc.x += faces.normal[t].x * angle;
      acc.y += faces.normal[t].y * angle;
      acc.z += faces.normal[t].z * angle;
    }
  }
  return vertex_normal;
}

// Removes vertices no kept triangle uses (out.positions), keeping the file's
// order; returns the new number of every old vertex (UINT32_MAX: removed).
std::vector<uint32_t> compact_vertices(const RawMesh& raw, const Faces& faces, MeshFile& out) {
  const size_t vertex_count = raw.positions.size();
  std::vector<uint32_t> remap(vertex_count, UINT32_MAX);
  uint32_t next = 0;
  for (size_t t = 0; t < faces.keep.size(); ++t)
    if (faces.keep[t])
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
  return remap;
}

// Materials no triangle uses and that have no name are noise (tinyobjloader
// adds one for an empty .mtl): drop those, keep the rest in file order.
void keep_materials(RawMesh& raw, MeshFile& out) {
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
}

}  // namespace

MeshFile finish(RawMesh raw, const std::string& file, bool vertex_normals) {
  check_vertices(raw, file);
  const size_t triangle_count = raw.indices.size() / 3;

  // Drop zero-area triangles; face normals and corner angles of the others.
  MeshFile out;
  const Faces faces = kept_faces(raw, file);
  std::vector<Vec3d> vertex_normal;
  if (needs_computed_normals(raw, faces, vertex_normals)) vertex_normal = angle_weighted_normals(raw, faces);
  const std::vector<uint32_t> remap = compact_vertices(raw, faces, out);

  const size_t kept = triangle_count - faces.dropped;
  out.indices.reserve(3 * kept);
  if (vertex_normals) out.corner_normals.reserve(3 * kept);
  out.triangle_material.reserve(kept);
  for (size_t t = 0; t < triangle_count; ++t) {
    if (!faces.keep[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = raw.indices[3 * t + k];
      out.indices.push_back(remap[v]);
      if (raw.has_uvs) out.corner_uvs.push_back(raw.uvs[3 * t + k]);
      if (!vertex_normals) continue;
      Vec3d n;
      if (!file_normal(raw, 3 * t + k, n)) {
        n = vertex_normal[v];
        const double len = length(n);
        // Opposite faces can cancel at a vertex: the face's own normal then.
        n = len > 0 && std::isfinite(len) ? Vec3d{n.x / len, n.y / len, n.z / len} : faces.normal[t];
      }
      out.corner_normals.push_back({static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)});
    }
    out.triangle_material.push_back(t < raw.triangle_material.size() ? raw.triangle_material[t] : -1);
  }
  keep_materials(raw, out);

  if (raw.small_faces > 0)
    raw.warnings.push_back(file + ": skipped " + plural(raw.small_faces, "face", "faces") +
                           " with fewer than 3 vertices");
  out.textures = std::move(raw.textures);
  out.warnings = std::move(raw.warnings);
  return out;
}

}  // namespace glint::mesh_io
