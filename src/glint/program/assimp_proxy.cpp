// PLY and glTF meshes through the plugin glint-assimp.so (plugin.h).
#include "glint/program/api.h"
#include "glint/version.h"

namespace glint::mesh_io {

namespace {
const plugin::AssimpApi& assimp() {
  return plugin::api<plugin::AssimpApi>("assimp", "glint_assimp_api", GLINT_VERSION_STRING);
}
}  // namespace

MeshFile load_ply(const std::string& file, std::vector<unsigned char> bytes, size_t budget, bool vertex_normals) {
  return assimp().load_ply(file, std::move(bytes), budget, vertex_normals);
}

MeshFile load_gltf(const std::filesystem::path& path, const std::string& file, const std::vector<unsigned char>& bytes,
                   bool binary, size_t budget, bool vertex_normals) {
  return assimp().load_gltf(path, file, bytes, binary, budget, vertex_normals);
}

}  // namespace glint::mesh_io
