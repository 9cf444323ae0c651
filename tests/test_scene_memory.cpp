// scene_memory: the bytes a Scene holds, by capacity (what is allocated), as
// `glint info` prints them and the preview's undo bounds them.
#include <gtest/gtest.h>

#include <utility>

#include "glint/scene/memory.h"

namespace {

using namespace glint;

TEST(SceneMemory, CountsEachMeshOnceByCapacityApartFromTheRest) {
  Scene scene;
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.indices.reserve(30);  // spare room is allocated memory too
  mesh.corner_normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.triangle_material = {0};
  const uint32_t m = add_mesh(scene, std::move(mesh));
  add_mesh_object(scene, m);
  add_mesh_object(scene, m);  // an instance: the mesh's arrays count once
  const Mesh& held = scene.meshes[m];
  const size_t mesh_arrays = held.positions.capacity() * sizeof(Vec3f) + held.indices.capacity() * sizeof(uint32_t) +
                             held.corner_normals.capacity() * sizeof(Vec3f) +
                             held.triangle_material.capacity() * sizeof(uint32_t);
  ASSERT_GE(held.indices.capacity(), 30u);

  TextureImage image;
  image.width = 2, image.height = 3;
  image.texels.assign(6, Vec3f{0.5f, 0.5f, 0.5f});
  scene.texture_images.push_back(std::move(image));
  scene.textures.push_back(Texture{});

  const SceneMemory memory = scene_memory(scene);
  EXPECT_EQ(memory.meshes, mesh_arrays);
  EXPECT_EQ(memory.textures, scene.texture_images[0].texels.capacity() * sizeof(Vec3f));
  const size_t rest = scene.objects.capacity() * sizeof(Object) + scene.materials.capacity() * sizeof(Material) +
                      scene.transforms.capacity() * sizeof(Transform) + scene.meshes.capacity() * sizeof(Mesh) +
                      scene.textures.capacity() * sizeof(Texture);
  EXPECT_EQ(memory.rest, rest);
  EXPECT_EQ(memory.total(), memory.meshes + memory.textures + memory.rest);
}

}  // namespace
