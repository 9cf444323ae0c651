// The bytes a Scene holds, as `glint info` reports them and glint serve's
// undo bounds them (serve/session.h).
#pragma once

#include <cstddef>

#include "glint/scene/scene.h"

namespace glint {

// By capacity, not size: what the scene's vectors have allocated, which is
// what it costs in memory (a loader's vector may hold spare room).
struct SceneMemory {
  // Each mesh's arrays (positions, indices, corner normals and UVs, triangle
  // materials), once per mesh however many objects instance it.
  size_t meshes = 0;
  size_t textures = 0;  // the texture images' texels
  // Objects and shapes (polygons with their arrays), transforms, materials,
  // lights, and the mesh and texture records themselves.
  size_t rest = 0;

  size_t total() const { return meshes + textures + rest; }
};

SceneMemory scene_memory(const Scene& scene);

}  // namespace glint
