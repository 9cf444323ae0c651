// The cache of mesh and texture files (io/file_cache.h) that lets glint
// serve parse a scene again after an edit without reading its files again,
// and the geometry key that tells a Renderer when the triangles changed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "glint/api/scene_state.h"
#include "glint/glint.h"
#include "glint/io/file_cache.h"
#include "glint/io/file_io.h"

namespace {

namespace fs = std::filesystem;

// The rendered bytes of a scene (a small image): equal scenes, equal bytes.
std::vector<unsigned char> api_image(const glint::api::Scene& scene) {
  glint::api::Renderer renderer(scene);
  return glint::api::encode_image(renderer.render({}).image, "pfm");
}

class FileCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("glint-file-cache-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A square of two triangles with an .mtl whose material has a diffuse map.
    write("quad.obj", "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl tile\nf 1 2 3\nf 1 3 4\n");
    write("quad.mtl", "newmtl tile\nKd 0.5 0.5 0.5\nmap_Kd tile.pfm\n");
    write_pfm("tile.pfm", 0.25f);
    write("scene.json", R"({
      "render": { "width": 16, "height": 16 },
      "camera": { "position": [0.5, 0.5, 3], "look_at": [0.5, 0.5, 0] },
      "materials": { "red": { "diffuse": [0.8, 0.1, 0.1], "shininess": 10 } },
      "lights": [ { "type": "point", "position": [0, 0, 5] } ],
      "objects": [ { "type": "mesh", "file": "quad.obj" },
                   { "type": "sphere", "center": [3, 0, 0], "radius": 0.5, "material": "red" } ]
    })");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name, std::ios::binary) << text; }
  // A 1 x 1 PFM (linear RGB floats) of one gray value.
  void write_pfm(const std::string& name, float value) {
    std::ofstream out(dir_ / name, std::ios::binary);
    out << "PF\n1 1\n-1.0\n";
    const float rgb[3] = {value, value, value};
    out.write(reinterpret_cast<const char*>(rgb), sizeof rgb);
  }
  // Gives `name` the modification time of `like` (as a rewrite within the
  // clock's granularity would keep it).
  void copy_mtime(const std::string& name, const struct stat& like) {
    const timespec times[2] = {like.st_atim, like.st_mtim};
    ASSERT_EQ(::utimensat(AT_FDCWD, (dir_ / name).c_str(), times, 0), 0);
  }
  struct stat stat_of(const std::string& name) {
    struct stat s {};
    EXPECT_EQ(::stat((dir_ / name).c_str(), &s), 0);
    return s;
  }

  fs::path dir_;
};

TEST_F(FileCacheTest, ReadsAMeshOnceWhileItAndItsMtlAreUnchanged) {
  glint::FileCache cache;
  const auto first = cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true);
  EXPECT_EQ(cache.reads(), 1u);
  ASSERT_EQ(first->triangle_count(), 2u);
  ASSERT_EQ(first->materials.size(), 1u);
  EXPECT_FLOAT_EQ(first->materials[0].diffuse.x, 0.5f);
  // Spelled another way, the same file.
  const auto again = cache.mesh(dir_ / "." / "quad.obj", glint::default_memory_budget(), true);
  EXPECT_EQ(cache.reads(), 1u);
  EXPECT_EQ(again, first);
  // Without vertex normals it is another reading (the loader asks for what it needs).
  cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), false);
  EXPECT_EQ(cache.reads(), 2u);
  // The .mtl is part of the mesh: a new one (another size) is read again.
  write("quad.mtl", "newmtl tile\nKd 0.25 0.5 0.75\nmap_Kd tile.pfm\n");
  const auto changed = cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true);
  EXPECT_EQ(cache.reads(), 3u);
  EXPECT_FLOAT_EQ(changed->materials[0].diffuse.x, 0.25f);
  EXPECT_FLOAT_EQ(changed->materials[0].diffuse.z, 0.75f);
  // The files to watch include the .mtl read beside the OBJ.
  const auto files = cache.files();
  EXPECT_NE(std::find(files.begin(), files.end(), fs::canonical(dir_ / "quad.mtl")), files.end());
  EXPECT_NE(std::find(files.begin(), files.end(), fs::canonical(dir_ / "quad.obj")), files.end());
}

TEST_F(FileCacheTest, ForgetReadsAgainWhatTheStampCannotTell) {
  glint::FileCache cache;
  const struct stat before = stat_of("quad.obj");
  cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true);
  // The same size, the same time and the same inode, another triangle: a
  // rewrite within the clock's tick. Only the watcher can tell.
  write("quad.obj", "mtllib quad.mtl\nv 0 0 0\nv 2 0 0\nv 1 1 0\nv 0 1 0\nusemtl tile\nf 1 2 3\nf 1 3 4\n");
  copy_mtime("quad.obj", before);
  ASSERT_EQ(stat_of("quad.obj").st_size, before.st_size);
  EXPECT_FLOAT_EQ(cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true)->positions[1].x, 1.0f);
  EXPECT_EQ(cache.reads(), 1u);
  cache.forget(dir_ / "quad.obj");
  EXPECT_FLOAT_EQ(cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true)->positions[1].x, 2.0f);
  EXPECT_EQ(cache.reads(), 2u);
  // Forgetting the .mtl drops the mesh read with it too.
  cache.forget(dir_ / "quad.mtl");
  cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true);
  EXPECT_EQ(cache.reads(), 3u);
}

TEST_F(FileCacheTest, TexturesErrorsAndKeepOnly) {
  glint::FileCache cache;
  EXPECT_FLOAT_EQ(cache.texture(dir_ / "tile.pfm")->texels.at(0).x, 0.25f);
  EXPECT_FLOAT_EQ(cache.texture(dir_ / "tile.pfm")->texels.at(0).x, 0.25f);
  EXPECT_EQ(cache.reads(), 1u);
  write_pfm("tile.pfm", 0.5f);  // same size: the time tells (or the watcher would)
  cache.forget(dir_ / "tile.pfm");
  EXPECT_FLOAT_EQ(cache.texture(dir_ / "tile.pfm")->texels.at(0).x, 0.5f);
  EXPECT_EQ(cache.reads(), 2u);
  // A missing file throws every time; nothing is kept of it.
  EXPECT_THROW(cache.texture(dir_ / "missing.pfm"), glint::Error);
  EXPECT_THROW(cache.texture(dir_ / "missing.pfm"), glint::Error);
  EXPECT_EQ(cache.reads(), 4u);
  // keep_only lets go of the files no scene names any more.
  cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true);
  cache.keep_only({dir_ / "quad.obj"});
  cache.texture(dir_ / "tile.pfm");
  cache.mesh(dir_ / "quad.obj", glint::default_memory_budget(), true);
  EXPECT_EQ(cache.reads(), 6u);  // the texture again, the mesh from the cache
}

TEST_F(FileCacheTest, EditsOfASceneReadNoFileAgain) {
  auto cache = std::make_shared<glint::FileCache>();
  glint::api::Scene scene = glint::api::load_scene_with(dir_ / "scene.json", cache);
  // The OBJ and the texture its .mtl names.
  EXPECT_EQ(cache->reads(), 2u);
  const size_t geometry = scene.geometry_key();
  scene.set("materials.red.shininess", 40.0);
  scene.set("lights[0].position", std::array<double, 3>{1, 2, 5});
  scene.set("camera.fov_y", 30.0);
  scene.set("render.max_depth", 3);
  EXPECT_EQ(cache->reads(), 2u);
  EXPECT_EQ(scene.geometry_key(), geometry);
  // The scene is the one the loader makes from the files (as glint render reads them).
  const glint::api::Scene fresh = glint::api::Scene::from_json(scene.to_json(), dir_);
  const glint::Scene& a = *scene.state()->scene;
  const glint::Scene& b = *fresh.state()->scene;
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].positions.size(), b.meshes[0].positions.size());
  EXPECT_EQ(a.meshes[0].corner_normals.size(), b.meshes[0].corner_normals.size());
  ASSERT_EQ(a.texture_images.size(), 1u);
  EXPECT_EQ(a.texture_images[0].texels.size(), b.texture_images[0].texels.size());
  EXPECT_EQ(api_image(scene), api_image(fresh));
  // An object that names the mesh again is not another reading either.
  scene.append_json("objects", R"({ "type": "mesh", "file": "quad.obj", "transform": { "translate": [0, 2, 0] } })");
  EXPECT_EQ(cache->reads(), 2u);
  EXPECT_NE(scene.geometry_key(), geometry);
}

TEST_F(FileCacheTest, GeometryKeyFollowsTheTrianglesNotTheFileTime) {
  const struct stat before = stat_of("quad.obj");
  const size_t key = glint::api::Scene::load(dir_ / "scene.json").geometry_key();
  EXPECT_EQ(glint::api::Scene::load(dir_ / "scene.json").geometry_key(), key);
  // Another triangle under the same size and time: another key (a Renderer
  // that kept its BVH would show the old mesh).
  write("quad.obj", "mtllib quad.mtl\nv 0 0 0\nv 2 0 0\nv 1 1 0\nv 0 1 0\nusemtl tile\nf 1 2 3\nf 1 3 4\n");
  copy_mtime("quad.obj", before);
  EXPECT_NE(glint::api::Scene::load(dir_ / "scene.json").geometry_key(), key);
}

}  // namespace
