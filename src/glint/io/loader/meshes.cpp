// Mesh objects' geometry: mesh files (read once each, with their materials and
// textures), inline meshes and the API's attached arrays, all within the
// memory budget.
#include "glint/io/loader/scene_reader.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include "glint/io/file_cache.h"
#include "glint/io/memory_limit.h"
#include "glint/io/mesh_file.h"
#include "glint/scene.h"  // api::MeshArrays (attached meshes)

namespace glint::loader {

// Each mesh file is read once, however many objects use it (instances).
uint32_t SceneReader::load_mesh(const Value& v, const Path& path) {
  const std::string name = string(v, path);
  if (name.empty()) fail(v, path, "must name a mesh file");
  const std::filesystem::path file = beside_scene(name);
  std::error_code ec;
  const std::string cache_key = file_key(file);
  if (auto it = mesh_index_.find(cache_key); it != mesh_index_.end()) return it->second;
  if (!std::filesystem::exists(file, ec)) fail(v, path, "mesh file " + quote_text(file.string()) + " not found");
  if (std::filesystem::is_directory(file, ec))
    fail(v, path, "mesh file " + quote_text(file.string()) + " is a directory");
  if (!std::filesystem::is_regular_file(file, ec))
    fail(v, path, "mesh file " + quote_text(file.string()) + " is not a regular file (a device or a pipe)");
  // A format this build leaves out (GLINT_ASSIMP=OFF) is refused at the key that names it.
  if (const std::string missing = missing_mesh_support(file); !missing.empty())
    fail(v, path, quote_text(file.string()) + ": " + missing);
  const bool vertex_normals = smooth_mesh_files_.count(cache_key) > 0;
  MeshFile loaded = files_ ? *files_->mesh(file, memory_budget_, vertex_normals)
                           : load_mesh_file(file, memory_budget_, vertex_normals);
  for (std::string& w : loaded.warnings) scene_.warnings.push_back(std::move(w));
  // The file's textures join the scene's; one that cannot be read is a
  // warning and its material keeps its color (the contract: defaults used).
  std::vector<uint32_t> texture_of(loaded.textures.size(), kNoTexture);
  for (size_t i = 0; i < loaded.textures.size(); ++i) {
    const MeshTexture& mt = loaded.textures[i];
    try {
      Texture t;
      t.image = texture_image(mt.file);
      t.wrap = mt.wrap;
      t.scale_u = mt.scale_u;
      t.scale_v = mt.scale_v;
      t.offset_u = mt.offset_u;
      t.offset_v = mt.offset_v;
      scene_.textures.push_back(t);
      texture_of[i] = static_cast<uint32_t>(scene_.textures.size() - 1);
    } catch (const Error& e) {
      scene_.warnings.push_back(mt.named_by + ": texture '" + mt.name + "' not used (defaults used): " + e.what());
    }
  }
  auto remap_texture = [&](uint32_t& t) { t = t < texture_of.size() ? texture_of[t] : kNoTexture; };
  // The file's materials join the scene's; triangles without one use the default.
  std::vector<uint32_t> material_of(loaded.materials.size());
  for (size_t i = 0; i < loaded.materials.size(); ++i) {
    Material m = loaded.materials[i];
    remap_texture(m.ambient_texture);
    remap_texture(m.diffuse_texture);
    remap_texture(m.specular_texture);
    material_of[i] = add_material(scene_, std::move(m));
  }
  Mesh mesh;
  mesh.file = file.string();
  mesh.positions = std::move(loaded.positions);
  mesh.indices = std::move(loaded.indices);
  mesh.corner_normals = std::move(loaded.corner_normals);
  mesh.corner_uvs = std::move(loaded.corner_uvs);
  mesh.triangle_material.resize(mesh.triangle_count(), 0);
  for (size_t t = 0; t < loaded.triangle_material.size() && t < mesh.triangle_count(); ++t) {
    const int32_t m = loaded.triangle_material[t];
    if (m >= 0 && static_cast<size_t>(m) < material_of.size()) mesh.triangle_material[t] = material_of[m];
  }
  // Each file fits on its own (load_mesh_file checks); all of them, with
  // their BVHs, must fit too. Instances share their mesh and cost little.
  mesh_vertices_ += mesh.positions.size();
  mesh_triangles_ += mesh.triangle_count();
  const std::string excess = exceeds_budget(
      kBytesPerVertex * double(mesh_vertices_) + kBytesPerTriangle * double(mesh_triangles_), memory_budget_);
  if (!excess.empty())
    fail(v, path,
         "with this mesh the scene's " + std::to_string(mesh_index_.size() + 1) + " mesh files hold " +
             std::to_string(mesh_triangles_) + " triangles: that " + excess);
  const uint32_t index = add_mesh(scene_, std::move(mesh));
  mesh_index_[cache_key] = index;
  return index;
}

// "vertices" [[x,y,z]...], "triangles" [[i,j,k]...] (0-based), optional
// per-vertex "normals" [[x,y,z]...] and "uvs" [[u,v]...]: a mesh that
// lives in the scene document itself (what glint.Scene.add_mesh writes),
// with the rules of a mesh file (mesh_from_arrays) and every problem named
// by its path in the document.
uint32_t SceneReader::inline_mesh(const Value& v, const Path& path, bool smooth) {
  for (size_t k = 0; k < v.size(); ++k)
    if (v.key(k) == "file")
      throw Error(v.key_location(k), join(path, "file").str(),
                  "give either \"file\" or inline \"vertices\" and \"triangles\", not both");
  const Value verts = require(v, path, "vertices");
  const Path vp = join(path, "vertices");
  expect_array(verts, vp);
  const Value tris = require(v, path, "triangles");
  const Path tp = join(path, "triangles");
  expect_array(tris, tp);
  if (verts.size() > UINT32_MAX) fail(verts, vp, "more than 2^32 - 1 vertices");
  count_inline_mesh(v, path, verts.size(), tris.size());
  std::vector<Vec3f> positions(verts.size());
  for (size_t i = 0; i < verts.size(); ++i) positions[i] = float_vec3(verts[i], index(vp, i));
  std::vector<uint32_t> indices(3 * tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    const Value tri = tris[t];
    const Path p = index(tp, t);
    if (!tri.is_array() || tri.size() != 3)
      fail(tri, p,
           std::string("expected [i, j, k] (three vertex indices), got ") +
               (tri.is_array() ? "an array of " + std::to_string(tri.size()) : std::string(tri.kind_name())));
    for (size_t k = 0; k < 3; ++k) {
      const Path ip = index(p, k);
      const double x = number(tri[k], ip);
      if (!tri[k].is_integer() || x != std::floor(x))
        fail(tri[k], ip, "expected a whole number, got " + format_number(x));
      if (!(x >= 0 && x < double(verts.size())))
        fail(tri[k], ip,
             "vertex index " + format_number(x) + " out of range (" + std::to_string(verts.size()) +
                 (verts.size() == 1 ? " vertex)" : " vertices)"));
      indices[3 * t + k] = static_cast<uint32_t>(x);
    }
  }
  auto per_vertex = [&](std::string_view key) -> std::optional<Value> {
    const auto a = v.find(key);
    if (!a) return std::nullopt;
    const Path ap = join(path, key);
    expect_array(*a, ap);
    if (a->size() != verts.size())
      fail(*a, ap, "expected one per vertex (" + std::to_string(verts.size()) + "), got " + std::to_string(a->size()));
    return a;
  };
  std::vector<Vec3f> normals;
  if (auto n = per_vertex("normals")) {
    normals.resize(n->size());
    for (size_t i = 0; i < n->size(); ++i) normals[i] = float_vec3((*n)[i], index(join(path, "normals"), i));
  }
  std::vector<UVf> uvs;
  if (auto u = per_vertex("uvs")) {
    uvs.resize(u->size());
    for (size_t i = 0; i < u->size(); ++i) {
      const Path up = index(join(path, "uvs"), i);
      const std::array<double, 2> c = pair((*u)[i], up);
      uvs[i] = {static_cast<float>(c[0]), static_cast<float>(c[1])};
      if (!std::isfinite(uvs[i].u) || !std::isfinite(uvs[i].v)) fail((*u)[i], up, "does not fit in a 32-bit float");
    }
  }
  return add_mesh_from_arrays(v, path, std::move(positions), std::move(indices), normals, uvs, smooth);
}

// Counted with the mesh files: all of them, with their BVHs, must fit.
void SceneReader::count_inline_mesh(const Value& v, const Path& path, size_t vertices, size_t triangles) {
  mesh_vertices_ += vertices;
  mesh_triangles_ += triangles;
  const std::string excess = exceeds_budget(
      kBytesPerVertex * double(mesh_vertices_) + kBytesPerTriangle * double(mesh_triangles_), memory_budget_);
  if (!excess.empty())
    fail(v, path,
         "with this mesh the scene's meshes hold " + std::to_string(mesh_triangles_) + " triangles: that " + excess);
}

// The rules of a mesh file (mesh_from_arrays) applied to an inline or
// attached mesh, which becomes one of the scene's meshes.
uint32_t SceneReader::add_mesh_from_arrays(const Value& v, const Path& path, std::vector<Vec3f> positions,
                                           std::vector<uint32_t> indices, const std::vector<Vec3f>& normals,
                                           const std::vector<UVf>& uvs, bool smooth) {
  MeshFile built;
  try {
    built = mesh_from_arrays(std::move(positions), std::move(indices), normals, uvs, path.str(), smooth);
  } catch (const Error& e) {
    fail(v, path, e.message());  // "no triangles (all 2 are degenerate)"
  }
  for (std::string& w : built.warnings) scene_.warnings.push_back(std::move(w));
  Mesh mesh;
  mesh.file = path.str();  // no file: the object's path names it (geometry keys, messages)
  mesh.positions = std::move(built.positions);
  mesh.indices = std::move(built.indices);
  mesh.corner_normals = std::move(built.corner_normals);
  mesh.corner_uvs = std::move(built.corner_uvs);
  mesh.triangle_material.assign(mesh.triangle_count(), 0);  // the default material, as a file without one
  return add_mesh(scene_, std::move(mesh));
}

// A mesh whose arrays the API holds in memory (AttachedMeshes): read
// straight from them, with no JSON between. They were checked when added
// (sizes, index range, finite floats); mesh_from_arrays checks again.
uint32_t SceneReader::attached_mesh(const Value& v, const Path& path, bool smooth) {
  for (size_t k = 0; k < v.size(); ++k)
    for (std::string_view other : {"file", "vertices", "triangles", "normals", "uvs"})
      if (v.key(k) == other)
        throw Error(v.key_location(k), join(path, other).str(),
                    other == "file" ? "give either \"file\" or inline \"vertices\" and \"triangles\", not both"
                                    : "this mesh's arrays are set as a whole (they are held in memory)");
  const Value id = *v.find(kAttachedMeshKey);
  const Path ip = join(path, kAttachedMeshKey);
  const double x = number(id, ip);
  const auto it = id.is_integer() && x >= 0 ? attached_->find(static_cast<uint64_t>(x)) : attached_->end();
  if (it == attached_->end()) fail(id, ip, "no mesh arrays with this id");
  const api::MeshArrays& a = *it->second;
  const size_t n = a.positions.size() / 3;
  count_inline_mesh(v, path, n, a.triangles.size() / 3);
  std::vector<Vec3f> positions(n);
  for (size_t i = 0; i < n; ++i) positions[i] = {a.positions[3 * i], a.positions[3 * i + 1], a.positions[3 * i + 2]};
  std::vector<Vec3f> normals(a.normals.size() / 3);
  for (size_t i = 0; i < normals.size(); ++i)
    normals[i] = {a.normals[3 * i], a.normals[3 * i + 1], a.normals[3 * i + 2]};
  std::vector<UVf> uvs(a.uvs.size() / 2);
  for (size_t i = 0; i < uvs.size(); ++i) uvs[i] = {a.uvs[2 * i], a.uvs[2 * i + 1]};
  return add_mesh_from_arrays(v, path, std::move(positions), a.triangles, normals, uvs, smooth);
}

// [x, y, z] stored as floats (meshes are): each component must fit.
Vec3f SceneReader::float_vec3(const Value& v, const Path& path) const {
  const Vec3f f = to_vec3f(vec3(v, path));
  if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z))
    fail(v, path, "does not fit in a 32-bit float");
  return f;
}

}  // namespace glint::loader
