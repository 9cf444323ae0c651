// Mesh files (.obj with its .mtl, .ply; more where the loader allows) read into
// plain arrays in the file's own space, with the contract's rules applied:
// polygons triangulated, degenerate triangles dropped (one warning with a
// count), vertex normals from the file or else angle-weighted averages per
// vertex index, MTL materials mapped by illum. The scene loader turns a
// MeshFile into a Scene mesh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/io/memory_limit.h"
#include "glint/scene/scene.h"

namespace glint {

// A texture one of the file's materials names (MTL map_Ka / map_Kd / map_Ks,
// a glTF base color texture) and that exists; the scene loader reads it.
struct MeshTexture {
  std::filesystem::path file;  // resolved against the file that names it
  std::string name;            // as written there
  std::string named_by;        // that file (the .mtl or the mesh), for warnings
  TextureWrap wrap = TextureWrap::repeat;
  double scale_u = 1, scale_v = 1, offset_u = 0, offset_v = 0;
};

struct MeshFile {
  std::vector<Vec3f> positions;
  std::vector<uint32_t> indices;           // 3 per triangle, into positions
  std::vector<Vec3f> corner_normals;       // 3 per triangle, unit: from the file, or computed;
                                           // empty when not asked for (load_mesh_file)
  std::vector<int32_t> triangle_material;  // per triangle: index into `materials`, or -1 for none
  std::vector<UVf> corner_uvs;             // 3 per triangle, or empty when the file has no UVs
  std::vector<Material> materials;         // from the .mtl (contract defaults for keys it leaves out);
                                           // their *_texture fields index `textures`
  std::vector<MeshTexture> textures;
  std::vector<std::string> warnings;  // one line each, e.g. "mesh.obj: dropped 3 degenerate triangles"

  size_t triangle_count() const { return indices.size() / 3; }
};

// Throws glint::Error naming the mesh file (and line:col where it has one)
// for a missing, unreadable or broken file, or one with no triangles. A file
// larger than `memory_budget`, or whose header claims more vertices,
// triangles or data than it allows (PLY element counts, glTF accessor counts,
// with instancing), is refused before anything is allocated for it.
// `vertex_normals` false leaves corner_normals empty: flat shading does not
// need them, and angle-weighting them costs about 0.15 s per million triangles.
MeshFile load_mesh_file(const std::filesystem::path& path, size_t memory_budget = default_memory_budget(),
                        bool vertex_normals = true);

// Empty when this glint reads mesh files like `path` (by its extension);
// otherwise why not, the message load_mesh_file gives for them: PLY and glTF
// need assimp, which a build may leave out (GLINT_ASSIMP). For a scene
// loader to report it where the file is named, and for tests to skip.
std::string missing_mesh_support(const std::filesystem::path& path);

// A mesh given as arrays (the scene format's inline mesh, a glint addition):
// per-vertex `normals` and `uvs` (each empty or one per position), with the
// same rules as a file whose every corner uses one index for its position,
// UV and normal (an OBJ `f a/a/a`): degenerate triangles dropped with a
// warning, missing or zero normals computed. `name` is what warnings and
// errors call the mesh. The caller has checked that indices are in range.
MeshFile mesh_from_arrays(std::vector<Vec3f> positions, std::vector<uint32_t> indices,
                          const std::vector<Vec3f>& normals, const std::vector<UVf>& uvs, const std::string& name,
                          bool vertex_normals = true);

}  // namespace glint
