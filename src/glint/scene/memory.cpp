#include "glint/scene/memory.h"

namespace glint {

namespace {

template <class T>
size_t bytes_of(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

size_t polygon_bytes(const Scene& scene) {
  size_t bytes = bytes_of(scene.polygons);
  for (const Polygon& p : scene.polygons) bytes += bytes_of(p.vertices) + bytes_of(p.normals) + bytes_of(p.triangles);
  return bytes;
}

}  // namespace

SceneMemory scene_memory(const Scene& scene) {
  SceneMemory m;
  for (const Mesh& mesh : scene.meshes)
    m.meshes += bytes_of(mesh.positions) + bytes_of(mesh.indices) + bytes_of(mesh.corner_normals) +
                bytes_of(mesh.triangle_material) + bytes_of(mesh.corner_uvs);
  for (const TextureImage& image : scene.texture_images) m.textures += bytes_of(image.texels);
  m.rest = bytes_of(scene.objects) + bytes_of(scene.spheres) + bytes_of(scene.planes) + bytes_of(scene.triangles) +
           bytes_of(scene.boxes) + bytes_of(scene.transforms) + bytes_of(scene.materials) + bytes_of(scene.lights) +
           bytes_of(scene.cones) + bytes_of(scene.disks) + polygon_bytes(scene) + bytes_of(scene.meshes) +
           bytes_of(scene.textures);
  return m;
}

}  // namespace glint
