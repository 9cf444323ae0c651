// The plugin glint-assimp.so (plugin.h): PLY and glTF meshes read by assimp.
#include "glint/program/api.h"
#include "glint/version.h"

GLINT_PLUGIN_ENTRY const glint::plugin::AssimpApi* glint_assimp_api() {
  static const glint::plugin::AssimpApi api{
      {sizeof api, GLINT_VERSION_STRING}, &glint::mesh_io::load_ply, &glint::mesh_io::load_gltf};
  return &api;
}
