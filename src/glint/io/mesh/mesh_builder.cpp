#include "glint/io/mesh/mesh_builder.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <utility>

#include "glint/io/mesh/common.h"

// finish() goes over the triangles twice, each time in parallel over runs of
// them: a first pass checks the indices, finds the zero-area triangles and
// the vertices the others use, and makes the file's normals unit in place;
// a second writes each kept triangle's indices, normals, UVs and material
// over the arrays it read them from (a triangle only ever moves down), at its
// place among its run's kept triangles, and the runs are then moved together.
// Every value is computed as the serial version computed it, from the same
// inputs in the same order (the per-vertex sums of angle-weighted normals
// stay serial), so the arrays are the same bit for bit for any cut, and
// there are no fresh per-corner arrays whose pages would fault in one by one.
namespace glint::mesh_io {
namespace {

struct Vec3d {
  double x, y, z;
};
inline Vec3d to_d(const Vec3f& v) { return {v.x, v.y, v.z}; }
inline Vec3f to_f(const Vec3d& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}
inline Vec3d sub(const Vec3d& a, const Vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double length(const Vec3d& a) { return std::sqrt(dot(a, a)); }

// A triangle's unit normal; false when its area is zero or not finite.
// `twice_area` is the length of the cross product of its edges.
inline bool face_normal(const RawMesh& raw, const uint32_t* i, Vec3d& normal, double& twice_area) {
  const Vec3d p0 = to_d(raw.positions[i[0]]);
  const Vec3d p1 = to_d(raw.positions[i[1]]);
  const Vec3d p2 = to_d(raw.positions[i[2]]);
  const Vec3d n = cross(sub(p1, p0), sub(p2, p0));
  twice_area = length(n);
  if (!(twice_area > 0) || !std::isfinite(twice_area)) return false;
  normal = {n.x / twice_area, n.y / twice_area, n.z / twice_area};
  return true;
}

// Whether a file's normal can be made unit: its length in double is then
// positive and finite, which for float components is exactly this (their
// squares neither overflow nor vanish in double).
inline bool usable_normal(const Vec3f& n) { return is_finite(n) && (n.x != 0 || n.y != 0 || n.z != 0); }

// The triangles in runs for the passes over them: run r holds the triangles
// from(r) .. from(r + 1) - 1.
struct Runs {
  size_t triangles = 0, count = 1;
  size_t from(size_t r) const { return triangles * r / count; }
};

// What the first pass finds in one run.
struct RunScan {
  bool bad_index = false;
  uint32_t first_bad_index = 0;        // the run's first index out of range
  std::vector<size_t> dropped;         // its zero-area triangles, ascending
  bool needs_computed_normal = false;  // a kept corner has no usable normal from the file
  size_t kept(const Runs& runs, size_t r) const { return runs.from(r + 1) - runs.from(r) - dropped.size(); }
};

// f(t) for each kept triangle of run r, in order.
template <typename F>
void for_kept(const Runs& runs, size_t r, const RunScan& scan, F f) {
  auto d = scan.dropped.begin();
  for (size_t t = runs.from(r), end = runs.from(r + 1); t < end; ++t) {
    if (d != scan.dropped.end() && *d == t) {
      ++d;
      continue;
    }
    f(t);
  }
}

// The first pass over run r: indices in range (it stops at the first that
// is not), zero-area triangles, the vertices kept triangles use (`used`;
// runs may mark one vertex at once), and with `unit_normals` the file's
// normals of kept corners made unit in place (the others stay as they are,
// so that the second pass tells them again).
void scan_run(RawMesh& raw, const Runs& runs, size_t r, bool unit_normals, uint8_t* used, RunScan& scan) {
  const size_t vertex_count = raw.positions.size();
  for (size_t t = runs.from(r), end = runs.from(r + 1); t < end; ++t) {
    const uint32_t* i = &raw.indices[3 * t];
    for (int k = 0; k < 3; ++k) {
      if (i[k] >= vertex_count) {
        scan.bad_index = true;
        scan.first_bad_index = i[k];
        return;
      }
    }
    Vec3d normal{};
    double twice_area = 0;
    if (!face_normal(raw, i, normal, twice_area)) {
      scan.dropped.push_back(t);
      continue;
    }
    for (int k = 0; k < 3; ++k) std::atomic_ref<uint8_t>(used[i[k]]).store(1, std::memory_order_relaxed);
    if (!unit_normals) continue;
    for (size_t c = 3 * t; c < 3 * t + 3; ++c) {
      Vec3f& n = raw.normals[c];
      if (!usable_normal(n)) {
        scan.needs_computed_normal = true;
        continue;
      }
      const Vec3d d = to_d(n);
      const double len = length(d);
      n = to_f({d.x / len, d.y / len, d.z / len});
    }
  }
}

// No triangles, indices out of range (the first in the file), and NaN/Inf
// vertices used by a triangle (degenerate or not) are errors, in this order.
void check_vertices(const RawMesh& raw, const std::string& file, const Runs& runs, const std::vector<RunScan>& scans) {
  const size_t vertex_count = raw.positions.size();
  auto out_of_range = [&](uint32_t i) {
    fail(file,
         "vertex index " + std::to_string(i) + " out of range (" + plural(vertex_count, "vertex", "vertices") + ")");
  };
  for (const RunScan& scan : scans)
    if (scan.bad_index) out_of_range(scan.first_bad_index);
  for (size_t c = 3 * runs.triangles; c < raw.indices.size(); ++c)
    if (raw.indices[c] >= vertex_count) out_of_range(raw.indices[c]);

  const bool nonfinite =
      std::any_of(raw.positions.begin(), raw.positions.end(), [](const Vec3f& p) { return !is_finite(p); });
  if (raw.bad_vertex_text.empty() && !nonfinite) return;
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

void fail_without_triangles(const RawMesh& raw, const std::string& file) {
  if (raw.non_faces > 0 || raw.small_faces > 0) fail(file, "no triangles (only points or lines)");
  if (!raw.positions.empty()) fail(file, "no triangles (vertices only)");
  fail(file, "no triangles (no meshes in the file)");
}

// Zero-area triangles dropped make one counted warning; none left is an error.
void warn_dropped(RawMesh& raw, const std::string& file, const Runs& runs, const std::vector<RunScan>& scans) {
  size_t dropped = 0;
  for (const RunScan& scan : scans) dropped += scan.dropped.size();
  if (dropped > 0)
    raw.warnings.push_back(file + ": dropped " + plural(dropped, "degenerate triangle", "degenerate triangles"));
  if (dropped == runs.triangles)
    fail(file, runs.triangles == 1 ? std::string("no triangles (the only one is degenerate)")
                                   : "no triangles (all " + std::to_string(runs.triangles) + " are degenerate)");
}

// Angle-weighted vertex normals per vertex index: each kept face adds its
// unit normal times its interior angle at the vertex, in file order. All
// three cross products of a triangle's edges have the same length, so
// angle = atan2(|n|, dot).
std::vector<Vec3d> angle_weighted_normals(const RawMesh& raw, const Runs& runs, const std::vector<RunScan>& scans) {
  std::vector<Vec3d> vertex_normal;
  resize_in_huge_pages(vertex_normal, raw.positions.size());
  for (size_t r = 0; r < runs.count; ++r) {
    for_kept(runs, r, scans[r], [&](size_t t) {
      const uint32_t* i = &raw.indices[3 * t];
      Vec3d normal{};
      double twice_area = 0;
      face_normal(raw, i, normal, twice_area);
      const Vec3d p[3] = {to_d(raw.positions[i[0]]), to_d(raw.positions[i[1]]), to_d(raw.positions[i[2]])};
      for (int k = 0; k < 3; ++k) {
        const Vec3d a = sub(p[(k + 1) % 3], p[k]);
        const Vec3d b = sub(p[(k + 2) % 3], p[k]);
        const double angle = std::atan2(twice_area, dot(a, b));
        Vec3d& acc = vertex_normal[i[k]];
        acc.x += normal.x * angle;
        acc.y += normal.y * angle;
        acc.z += normal.z * angle;
      }
    });
  }
  return vertex_normal;
}

// The new number of every vertex when some are used by no kept triangle
// (UINT32_MAX: removed), keeping the file's order; empty when all are kept.
std::vector<uint32_t> vertex_remap(const std::vector<uint8_t>& used) {
  if (std::find(used.begin(), used.end(), uint8_t{0}) == used.end()) return {};
  std::vector<uint32_t> remap(used.size(), UINT32_MAX);
  uint32_t next = 0;
  for (size_t v = 0; v < used.size(); ++v)
    if (used[v]) remap[v] = next++;
  return remap;
}

// What the second pass reads and writes: the arrays of `raw`, and the
// normals (raw.normals, or fresh ones when the file has none).
struct Rewrite {
  RawMesh& raw;
  bool vertex_normals;
  std::vector<Vec3f>& normals;
  const std::vector<Vec3d>& vertex_normal;  // empty when no corner needs one
  const std::vector<uint32_t>& remap;       // empty when every vertex is kept
};

// The second pass over run r: its kept triangles, finished, written at the
// run's start in order (over the arrays they came from: the j-th kept
// triangle of a run is never after the j-th of the run).
void rewrite_run(const Rewrite& w, const Runs& runs, size_t r, const RunScan& scan) {
  RawMesh& raw = w.raw;
  size_t j = runs.from(r);
  for_kept(runs, r, scan, [&](size_t t) {
    const uint32_t v[3] = {raw.indices[3 * t], raw.indices[3 * t + 1], raw.indices[3 * t + 2]};
    for (size_t k = 0; k < 3; ++k) {
      raw.indices[3 * j + k] = w.remap.empty() ? v[k] : w.remap[v[k]];
      if (raw.has_uvs) raw.uvs[3 * j + k] = raw.uvs[3 * t + k];
      if (!w.vertex_normals) continue;
      if (raw.has_normals && usable_normal(raw.normals[3 * t + k])) {
        w.normals[3 * j + k] = raw.normals[3 * t + k];  // made unit by the first pass
        continue;
      }
      Vec3d n = w.vertex_normal[v[k]];
      const double len = length(n);
      if (len > 0 && std::isfinite(len)) {
        n = {n.x / len, n.y / len, n.z / len};
      } else {
        double twice_area = 0;  // opposite faces can cancel at a vertex: the face's own normal then
        face_normal(raw, v, n, twice_area);
      }
      w.normals[3 * j + k] = to_f(n);
    }
    raw.triangle_material[j] = raw.triangle_material[t];
    ++j;
  });
}

// Moves each run's kept triangles (at the run's start) down to follow the
// runs before it, and cuts the array to the kept triangles.
template <typename T>
void close_gaps(std::vector<T>& a, size_t per_triangle, const Runs& runs, const std::vector<RunScan>& scans) {
  size_t to = 0;
  for (size_t r = 0; r < runs.count; ++r) {
    const size_t from = runs.from(r), n = scans[r].kept(runs, r);
    if (to != from)
      std::copy(a.begin() + static_cast<ptrdiff_t>(per_triangle * from),
                a.begin() + static_cast<ptrdiff_t>(per_triangle * (from + n)),
                a.begin() + static_cast<ptrdiff_t>(per_triangle * to));
    to += n;
  }
  a.resize(per_triangle * to);
}

void compact_positions(std::vector<Vec3f>& positions, const std::vector<uint32_t>& remap) {
  if (remap.empty()) return;
  size_t next = 0;
  for (size_t v = 0; v < positions.size(); ++v)
    if (remap[v] != UINT32_MAX) positions[next++] = positions[v];
  positions.resize(next);
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

MeshFile finish(RawMesh raw, const std::string& file, bool vertex_normals, const FinishOptions& options) {
  const size_t triangles = raw.indices.size() / 3;
  if (triangles == 0) fail_without_triangles(raw, file);
  const size_t per_run = std::max<size_t>(1, options.triangles_per_run);
  const Runs runs{triangles, triangles / per_run + (triangles % per_run != 0)};

  // Checks, zero-area triangles, used vertices, the file's normals made unit.
  std::vector<RunScan> scans(runs.count);
  std::vector<uint8_t> used(raw.positions.size(), 0);
  const bool unit_normals = vertex_normals && raw.has_normals;
  run_parallel(runs.count, options.threads,
               [&](size_t r) { scan_run(raw, runs, r, unit_normals, used.data(), scans[r]); });
  check_vertices(raw, file, runs, scans);
  warn_dropped(raw, file, runs, scans);

  const bool computed_normals =
      vertex_normals && (!raw.has_normals || std::any_of(scans.begin(), scans.end(),
                                                         [](const RunScan& s) { return s.needs_computed_normal; }));
  std::vector<Vec3d> vertex_normal;
  if (computed_normals) vertex_normal = angle_weighted_normals(raw, runs, scans);
  const std::vector<uint32_t> remap = vertex_remap(used);
  if (raw.triangle_material.size() < triangles) {  // a triangle without one has none
    const size_t had = raw.triangle_material.size();
    resize_in_huge_pages(raw.triangle_material, triangles);
    std::fill(raw.triangle_material.begin() + static_cast<ptrdiff_t>(had), raw.triangle_material.end(), -1);
  }
  std::vector<Vec3f> fresh_normals;
  if (vertex_normals && !raw.has_normals) resize_in_huge_pages(fresh_normals, 3 * triangles);
  std::vector<Vec3f>& normals = raw.has_normals ? raw.normals : fresh_normals;

  // The kept triangles written over the arrays they came from.
  const Rewrite rewrite{raw, vertex_normals, normals, vertex_normal, remap};
  run_parallel(runs.count, options.threads, [&](size_t r) { rewrite_run(rewrite, runs, r, scans[r]); });
  MeshFile out;
  close_gaps(raw.indices, 3, runs, scans);
  out.indices = std::move(raw.indices);
  if (raw.has_uvs) {
    close_gaps(raw.uvs, 3, runs, scans);
    out.corner_uvs = std::move(raw.uvs);
  }
  if (vertex_normals) {
    close_gaps(normals, 3, runs, scans);
    out.corner_normals = std::move(normals);
  }
  close_gaps(raw.triangle_material, 1, runs, scans);
  out.triangle_material = std::move(raw.triangle_material);
  compact_positions(raw.positions, remap);
  out.positions = std::move(raw.positions);
  keep_materials(raw, out);
  fit_capacity(out.positions);
  fit_capacity(out.indices);
  fit_capacity(out.corner_normals);
  fit_capacity(out.corner_uvs);
  fit_capacity(out.triangle_material);

  if (raw.small_faces > 0)
    raw.warnings.push_back(file + ": skipped " + plural(raw.small_faces, "face", "faces") +
                           " with fewer than 3 vertices");
  out.textures = std::move(raw.textures);
  out.warnings = std::move(raw.warnings);
  return out;
}

}  // namespace glint::mesh_io
