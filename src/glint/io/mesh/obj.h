// Wavefront OBJ (+ its MTL libraries) through tinyobjloader, with glint's
// checks of the text beside it (obj_checks.h, mtl.h).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/io/mesh_file.h"

namespace glint::mesh_io {

MeshFile load_obj(const std::filesystem::path& path, const std::string& file, std::vector<unsigned char> bytes,
                  size_t budget, bool vertex_normals);

}  // namespace glint::mesh_io
