// Mesh files into MeshFile: each format's reader parses, glint applies the contract.
// This file picks the reader by the file's extension; the readers live in
// io/mesh/ (obj, obj_reader, obj_checks, mtl; ply_checks, gltf_checks,
// assimp_import; mesh_builder, the back end they share; text_scan, common).
// - .obj: glint's own reader (obj_reader.cpp), in parallel: the text cut into
//   chunks at line ends, each parsed straight into its place in the arrays.
//   It keeps the file's vertex indices and reads what tinyobjloader read
//   before it (tests/test_obj_reader.cpp compares the two); a bad number or
//   index is an error at file:line:col (obj_checks), a "nan"/"inf" vertex
//   one only where a triangle uses it.
// - .mtl: tinyobjloader. Its gaps are covered in mtl.cpp: it reads what is
//   not a number as 0 and "Kd 0.5" as red, and cannot say which MTL keys were
//   given, so a short scan of the text finds those (and file:line for errors).
// - .ply, .gltf, .glb: assimp. Its PLY reader crashes, aborts or hangs on
//   truncated or inconsistent files, so every PLY is checked first against its
//   own header (counts against the file size, every record present, indices
//   in range) by a structural walk that stores nothing. Its glTF reader trusts
//   the JSON: glint's JSON reader checks it first (what it claims in memory,
//   accessors within their views, sparse parts), and assimp gets it reduced
//   to what glint uses (no skins, animations, morph targets, cameras or
//   embedded images).
// - Every format: what the file claims or implies in memory is checked
//   against a budget (memory_limit.h) before it is allocated.
// Then, for every format: polygons triangulated (quads on the shorter
// diagonal, larger polygons as fans), NaN/Inf vertices used by a triangle are
// errors, zero-area triangles dropped with one counted warning, corner normals
// from the file or angle-weighted per vertex index, unused vertices removed.
#include "glint/io/mesh_file.h"

#include <new>
#include <system_error>

#include "glint/error.h"
#include "glint/io/file_io.h"
#if GLINT_HAVE_ASSIMP
#include "glint/io/mesh/assimp_import.h"
#endif
#include "glint/io/mesh/common.h"
#include "glint/io/mesh/mesh_builder.h"
#include "glint/io/mesh/obj.h"

namespace glint {
namespace fs = std::filesystem;
using mesh_io::fail;
using mesh_io::format_count;
using mesh_io::lower;

std::string missing_mesh_support(const fs::path& path) {
#if GLINT_HAVE_ASSIMP
  (void)path;
  return {};
#else
  const std::string ext = lower(path.extension().string());
  if (ext == ".ply" || ext == ".gltf" || ext == ".glb")
    return "this glint was built without assimp: PLY and glTF meshes are not available";
  return {};
#endif
}

MeshFile load_mesh_file(const fs::path& path, size_t memory_budget, bool vertex_normals) {
  const std::string file = path.string();
  try {
    std::error_code ec;
    const auto status = fs::status(path, ec);
    if (!fs::exists(status)) fail(file, "mesh file not found");
    if (fs::is_directory(status)) fail(file, "is a directory, not a mesh file");
    const std::string ext = lower(path.extension().string());
    if (ext != ".obj" && ext != ".ply" && ext != ".gltf" && ext != ".glb")
      fail(file, "unsupported mesh format '" + path.extension().string() + "' (supported: .obj, .ply, .gltf, .glb)");
    if (const std::string missing = missing_mesh_support(path); !missing.empty()) fail(file, missing);
    // Not a device or a pipe: /dev/zero would be read until memory runs out.
    if (!fs::is_regular_file(status)) fail(file, "not a regular file");
    // The readers hold the whole file and more, so a file beyond the budget is refused unread.
    const uintmax_t size = fs::file_size(path, ec);
    if (!ec) {
      const std::string excess = exceeds_budget(static_cast<double>(size), memory_budget);
      if (!excess.empty()) fail(file, "file of " + format_bytes(static_cast<double>(size)) + ": reading it " + excess);
    }
    if (ext == ".obj") return mesh_io::load_obj_file(path, file, memory_budget, vertex_normals);
    std::vector<unsigned char> bytes = read_file(path);
    if (bytes.empty()) fail(file, "empty file");
#if GLINT_HAVE_ASSIMP
    if (ext == ".ply") return mesh_io::load_ply(file, std::move(bytes), memory_budget, vertex_normals);
    return mesh_io::load_gltf(path, file, bytes, ext == ".glb", memory_budget, vertex_normals);
#else
    fail(file, missing_mesh_support(path));  // not reached: refused above
#endif
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(file, "out of memory reading the mesh");
  } catch (const std::exception& e) {
    fail(file, std::string("cannot read mesh: ") + e.what());
  } catch (...) {
    fail(file, "cannot read mesh: unknown error");
  }
}

MeshFile mesh_from_arrays(std::vector<Vec3f> positions, std::vector<uint32_t> indices,
                          const std::vector<Vec3f>& normals, const std::vector<UVf>& uvs, const std::string& name,
                          bool vertex_normals) {
  mesh_io::RawMesh raw;
  raw.positions = std::move(positions);
  raw.indices = std::move(indices);
  // Per-vertex values become per-corner ones, as a file's would be.
  auto corners = [&](const auto& per_vertex, auto& out) {
    out.reserve(raw.indices.size());
    using T = std::decay_t<decltype(per_vertex[0])>;
    for (uint32_t i : raw.indices) out.push_back(i < per_vertex.size() ? per_vertex[i] : T{});
  };
  if (!normals.empty()) {
    corners(normals, raw.normals);
    raw.has_normals = true;
  }
  if (!uvs.empty()) {
    corners(uvs, raw.uvs);
    raw.has_uvs = true;
  }
  return mesh_io::finish(std::move(raw), name, vertex_normals);
}

}  // namespace glint
