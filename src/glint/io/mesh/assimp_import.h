// PLY and glTF meshes read by assimp, after glint's checks of the file
// (ply_checks.h, gltf_checks.h). Built only with assimp (GLINT_ASSIMP).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/io/mesh_file.h"

namespace glint::mesh_io {

MeshFile load_ply(const std::string& file, std::vector<unsigned char> bytes, size_t budget, bool vertex_normals);

MeshFile load_gltf(const std::filesystem::path& path, const std::string& file, const std::vector<unsigned char>& bytes,
                   bool binary, size_t budget, bool vertex_normals);

}  // namespace glint::mesh_io
