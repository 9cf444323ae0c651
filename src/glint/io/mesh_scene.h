// A bare mesh file as a scene: `glint render model.glb -o out.png` and
// `glint serve model.obj` frame the model with a fixed rig (docs/cli.md,
// "A mesh file as a scene"), so any mesh glint reads can be looked at
// without writing a scene first.
#pragma once

#include <filesystem>
#include <string>

namespace glint {

// .obj .ply .gltf .glb, case-insensitive: the mesh formats glint reads.
bool is_mesh_file(const std::filesystem::path& path);

// The scene JSON that frames the mesh (its `file` relative to the mesh's
// folder, so the text loads with that folder as its base). Reads the mesh
// for its bounds; its errors are the mesh loader's.
std::string mesh_scene_json(const std::filesystem::path& mesh);

}  // namespace glint
