// Wavefront OBJ (+ its MTL libraries): glint's parallel reader (obj_reader.h)
// with its checks (obj_checks.h); the MTL libraries through tinyobjloader (mtl.h).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/io/mesh_file.h"

namespace glint::mesh_io {

MeshFile load_obj(const std::filesystem::path& path, const std::string& file, std::vector<unsigned char> bytes,
                  size_t budget, bool vertex_normals);

// The same, reading the file itself (into huge pages, without read_file's
// second copy); read_file's errors where it cannot.
MeshFile load_obj_file(const std::filesystem::path& path, const std::string& file, size_t budget,
                       bool vertex_normals);

}  // namespace glint::mesh_io
