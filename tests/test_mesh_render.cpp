// Mesh objects in scenes: loaded once per file and instanced, smooth normals
// interpolated per the contract (vertex normals through the inverse transpose,
// normalized, then interpolated), flat facets with smooth: false, MTL
// materials unless the object names one, and the two-level BVH against brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/math/rng.h"
#include "glint/render/integrator.h"
#include "glint/render/renderer.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

class MeshScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("glint-mesh-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // A unit quad in z = 0 made of two triangles, with vertex normals tilted
    // outward so that smooth shading differs from flat.
    write("quad.obj",
          "mtllib quad.mtl\n"
          "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
          "vn -0.5 -0.5 1\nvn 0.5 -0.5 1\nvn 0.5 0.5 1\nvn -0.5 0.5 1\n"
          "usemtl red\n"
          "f 1//1 2//2 3//3\nf 1//1 3//3 4//4\n");
    write("quad.mtl", "newmtl red\nKd 0.9 0.1 0.1\nKa 0 0 0\nKs 0 0 0\nillum 1\n");
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  Scene load(const std::string& objects, const std::string& extra = "") {
    write("scene.json",
          R"({"render": {"width": 16, "height": 16}, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
      "materials": {"blue": {"diffuse": [0.1, 0.2, 0.9]}}, )" +
              extra + R"("lights": [{"type": "directional", "direction": [0, 0, -1]}],
      "objects": [)" +
              objects + "]}");
    return load_scene(dir_ / "scene.json");
  }
  fs::path dir_;
};

TEST_F(MeshScene, OneFileIsLoadedOnceForManyObjects) {
  const Scene scene = load(R"({"type": "mesh", "file": "quad.obj"},
      {"type": "mesh", "file": "quad.obj", "transform": {"translate": [3, 0, 0]}},
      {"type": "mesh", "file": "./quad.obj", "material": "blue"})");
  EXPECT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.objects.size(), 3u);
  EXPECT_EQ(scene.meshes[0].triangle_count(), 2u);
}

TEST_F(MeshScene, SmoothNormalsAreInterpolatedAndFlatUsesTheFacet) {
  const Scene scene = load(R"({"type": "mesh", "file": "quad.obj"},
      {"type": "mesh", "file": "quad.obj", "smooth": false, "transform": {"translate": [0, 0, -1]}})");
  const auto accel = build_accelerator(scene);
  // A ray straight down onto the quad at (0.5, -0.5).
  const Ray ray{{0.5, -0.5, 5}, {0, 0, -1}};
  const auto hit = accel->intersect(ray);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->object, 0u);
  const SurfacePoint sp = evaluate_hit(scene, ray, *hit);
  // Triangle 1-2-3 at (0.5, -0.5): barycentrics from the triangle, normals interpolated.
  const Vec3 n1 = normalize(Vec3{-0.5, -0.5, 1}), n2 = normalize(Vec3{0.5, -0.5, 1}), n3 = normalize(Vec3{0.5, 0.5, 1});
  // p = v1 + b1 (v2 - v1) + b2 (v3 - v1) with v1 (-1,-1), v2 (1,-1), v3 (1,1): b2 = 0.25, b1 = 0.5.
  const Vec3 want = normalize(0.25 * n1 + 0.5 * n2 + 0.25 * n3);
  EXPECT_NEAR(sp.shading_normal.x, want.x, 1e-6);
  EXPECT_NEAR(sp.shading_normal.y, want.y, 1e-6);
  EXPECT_NEAR(sp.shading_normal.z, want.z, 1e-6);
  EXPECT_NEAR(sp.geometric_normal.z, 1.0, 1e-12);
  EXPECT_NEAR(sp.p.x, 0.5, 1e-6);

  Scene flat = scene;
  flat.objects[0].smooth = false;
  const auto flat_accel = build_accelerator(flat);
  const SurfacePoint fp = evaluate_hit(flat, ray, *flat_accel->intersect(ray));
  EXPECT_NEAR(fp.shading_normal.z, 1.0, 1e-12);
}

TEST_F(MeshScene, VertexNormalsOnlyForFilesShadedSmoothly) {
  // Only flat: no vertex normals are kept (nor computed), and the image is
  // the one rendered with them loaded for another, smooth, object far away.
  const Scene flat_only = load(R"({"type": "mesh", "file": "quad.obj", "smooth": false})");
  EXPECT_TRUE(flat_only.meshes[0].corner_normals.empty());
  const Scene both = load(R"({"type": "mesh", "file": "quad.obj", "smooth": false},
      {"type": "mesh", "file": "quad.obj", "transform": {"translate": [100, 0, 0]}})");
  EXPECT_EQ(both.meshes[0].corner_normals.size(), 6u);
  EXPECT_EQ(load(R"({"type": "mesh", "file": "quad.obj"})").meshes[0].corner_normals.size(), 6u);  // smooth by default
  const Image a = render_image(flat_only, *build_accelerator(flat_only));
  const Image b = render_image(both, *build_accelerator(both));
  EXPECT_EQ(a.rgb, b.rgb);
  // A scene built in code that asks for smooth shading without normals gets facets.
  Scene asked = flat_only;
  asked.objects[0].smooth = true;
  EXPECT_EQ(render_image(asked, *build_accelerator(asked)).rgb, a.rgb);
}

TEST_F(MeshScene, NormalsFollowTheInverseTransposeOfANonUniformScale) {
  const Scene scene = load(R"({"type": "mesh", "file": "quad.obj", "transform": {"scale": [4, 1, 1]}})");
  const auto accel = build_accelerator(scene);
  const Ray ray{{-4, -1, 5}, {0, 0, -1}};  // exactly at vertex 1 (scaled)
  const auto hit = accel->intersect(ray);
  ASSERT_TRUE(hit);
  const SurfacePoint sp = evaluate_hit(scene, ray, *hit);
  const Vec3 want = normalize(Vec3{-0.5 / 4, -0.5, 1});
  EXPECT_NEAR(sp.shading_normal.x, want.x, 1e-6);
  EXPECT_NEAR(sp.shading_normal.y, want.y, 1e-6);
  EXPECT_NEAR(sp.shading_normal.z, want.z, 1e-6);
}

TEST_F(MeshScene, MtlMaterialsUnlessTheObjectNamesOne) {
  const Scene scene = load(R"({"type": "mesh", "file": "quad.obj"},
      {"type": "mesh", "file": "quad.obj", "material": "blue", "transform": {"translate": [0, 0, -1]}})");
  const auto accel = build_accelerator(scene);
  const Ray ray{{0, 0.2, 5}, {0, 0, -1}};
  const SurfacePoint a = evaluate_hit(scene, ray, *accel->intersect(ray));
  EXPECT_EQ(scene.materials[a.material].name, "red");
  EXPECT_NEAR(scene.materials[a.material].diffuse.x, 0.9, 1e-6);  // MTL numbers are read as float
  Hit behind;
  ASSERT_TRUE(intersect_object(scene, 1, ray, behind));
  const SurfacePoint b = evaluate_hit(scene, ray, behind);
  EXPECT_EQ(scene.materials[b.material].name, "blue");
}

TEST_F(MeshScene, MissingMeshFileIsAnErrorAtTheSceneKey) {
  try {
    load(R"({"type": "mesh", "file": "nope.obj"})");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("objects[0].file"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("not found"), std::string::npos) << e.what();
    EXPECT_GT(e.location().line, 0);
  }
}

// A folder or a device named as the mesh file was reported at the folder's
// own path, without the scene position the "not found" error has.
TEST_F(MeshScene, MeshFileThatIsAFolderOrADeviceIsAnErrorAtTheSceneKey) {
  fs::create_directories(dir_ / "folder.obj");
  fs::create_symlink("/dev/zero", dir_ / "zero.obj");
  for (const char* name : {"folder.obj", "zero.obj"}) {
    try {
      load(std::string(R"({"type": "mesh", "file": ")") + name + "\"}");
      FAIL() << name;
    } catch (const Error& e) {
      EXPECT_EQ(e.location().file, (dir_ / "scene.json").string()) << e.what();
      EXPECT_GT(e.location().line, 0) << e.what();
      EXPECT_NE(e.message().find("objects[0].file"), std::string::npos) << e.what();
      EXPECT_NE(e.message().find(std::string(name) == "folder.obj" ? "is a directory" : "not a regular file"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST_F(MeshScene, TwoLevelBvhMatchesBruteForce) {
  // A 20x20 grid of small tilted quads as one mesh, instanced three times.
  std::string obj;
  int v = 1;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const double x = i * 0.5 - 5, y = j * 0.5 - 5, z = std::sin(i * 0.7) * std::cos(j * 0.3);
      obj += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
      obj += "v " + std::to_string(x + 0.4) + " " + std::to_string(y) + " " + std::to_string(z + 0.1) + "\n";
      obj += "v " + std::to_string(x + 0.4) + " " + std::to_string(y + 0.4) + " " + std::to_string(z) + "\n";
      obj += "f " + std::to_string(v) + " " + std::to_string(v + 1) + " " + std::to_string(v + 2) + "\n";
      v += 3;
    }
  write("grid.obj", obj);
  const Scene scene = load(R"({"type": "mesh", "file": "grid.obj"},
      {"type": "mesh", "file": "grid.obj", "transform": {"rotate": {"axis": [1, 0, 0], "angle": 40}, "translate": [0, 0, -3]}},
      {"type": "mesh", "file": "grid.obj", "transform": {"scale": [1, 2, 0.5], "translate": [1, 1, 2]}},
      {"type": "sphere", "center": [0, 0, 0], "radius": 1})");
  const auto bvh = build_accelerator(scene);
  const auto brute = build_brute_force(scene);
  Rng rng(3);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    Ray ray;
    ray.origin = {rng.next_double() * 16 - 8, rng.next_double() * 16 - 8, 6 + rng.next_double() * 4};
    ray.direction = normalize(Vec3{rng.next_double() - 0.5, rng.next_double() - 0.5, -1});
    const auto a = bvh->intersect(ray), b = brute->intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << i;
    if (a) {
      ++hits;
      EXPECT_EQ(a->object, b->object);
      EXPECT_EQ(a->primitive, b->primitive);
      EXPECT_EQ(a->t, b->t);
    }
    EXPECT_EQ(bvh->occluded(ray), brute->occluded(ray));
  }
  EXPECT_GT(hits, 500);
}

}  // namespace
}  // namespace glint
