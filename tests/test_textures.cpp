// Textures: image files decoded to linear (sRGB formula computed here),
// bilinear lookups, wrap modes, the checker, the (u, v) of every shape, mesh
// UVs and MTL maps, the loader's texture keys and errors, explain, and a
// rendered pixel equal to the shading formula with the texture's value.
#include <gtest/gtest.h>
#include <png.h>
#include <stb_image_write.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/io/image_file.h"
#include "glint/io/mesh_file.h"
#include "glint/io/scene_loader.h"
#include "glint/io/texture_file.h"
#include "glint/render/explain.h"
#include "glint/render/renderer.h"
#include "glint/render/texture.h"
#include "needs_assimp.h"

namespace glint {
namespace {

namespace fs = std::filesystem;
constexpr double kTol = 1e-6;

// The sRGB decoding formula (IEC 61966-2-1), written out here.
double srgb_to_linear(int byte) {
  const double c = byte / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

void expect_color(const Color& got, const Color& want, const std::string& what = "") {
  EXPECT_NEAR(got.x, want.x, kTol) << what;
  EXPECT_NEAR(got.y, want.y, kTol) << what;
  EXPECT_NEAR(got.z, want.z, kTol) << what;
}

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("glint-tex-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  // An 8-bit RGB PNG with exactly these bytes, rows from the top.
  fs::path png(const std::string& name, int w, int h, const std::vector<unsigned char>& rgb) const {
    const fs::path p = path_ / name;
    EXPECT_NE(stbi_write_png(p.c_str(), w, h, 3, rgb.data(), 3 * w), 0);
    return p;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// An image texture built in memory: one gray value per texel, rows from the top.
TextureImage gray_image(int w, int h, const std::vector<float>& values) {
  TextureImage image;
  image.width = w;
  image.height = h;
  for (float v : values) image.texels.push_back({v, v, v});
  return image;
}

// --- image files -------------------------------------------------------------

TEST(TextureFile, EightBitPngIsSrgbDecodedToLinear) {
  TempDir dir;
  const std::vector<unsigned char> bytes = {0, 64, 128, 200, 255, 10, 1, 2, 3, 90, 180, 250};
  const TextureImage image = load_texture_image(dir.png("t.png", 2, 2, bytes));
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  ASSERT_EQ(image.texels.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const Vec3f& t = image.texels[i];
    EXPECT_NEAR(t.x, srgb_to_linear(bytes[3 * i]), kTol) << i;
    EXPECT_NEAR(t.y, srgb_to_linear(bytes[3 * i + 1]), kTol) << i;
    EXPECT_NEAR(t.z, srgb_to_linear(bytes[3 * i + 2]), kTol) << i;
  }
  // Not the identity: byte 128 is about 0.216 in linear light.
  EXPECT_NEAR(image.texels[0].z, 0.2158605, 1e-6);
}

TEST(TextureFile, SixteenBitPngIsSrgbDecodedToLinear) {
  TempDir dir;
  const uint16_t values[6] = {0, 1000, 32768, 50000, 65535, 12345};
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = 2;
  image.height = 1;
  image.format = PNG_FORMAT_LINEAR_RGB;  // 16 bits a channel, stored as given
  const fs::path p = dir.path() / "t16.png";
  ASSERT_NE(png_image_write_to_file(&image, p.c_str(), 0, values, 0, nullptr), 0) << image.message;
  const TextureImage t = load_texture_image(p);
  ASSERT_EQ(t.texels.size(), 2u);
  auto decode = [](uint16_t x) {
    const double c = x / 65535.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(t.texels[i].x, decode(values[3 * i]), kTol) << i;
    EXPECT_NEAR(t.texels[i].y, decode(values[3 * i + 1]), kTol) << i;
    EXPECT_NEAR(t.texels[i].z, decode(values[3 * i + 2]), kTol) << i;
  }
}

TEST(TextureFile, RadianceHdrIsLinear) {
  TempDir dir;
  // Values RGBE stores exactly (a shared exponent, short mantissas).
  const float rgb[6] = {1.0f, 0.25f, 0.5f, 4.0f, 2.0f, 1.0f};
  const fs::path p = dir.path() / "t.hdr";
  ASSERT_NE(stbi_write_hdr(p.c_str(), 2, 1, 3, rgb), 0);
  const TextureImage image = load_texture_image(p);
  ASSERT_EQ(image.texels.size(), 2u);
  expect_color(to_vec3(image.texels[0]), {1.0, 0.25, 0.5});
  expect_color(to_vec3(image.texels[1]), {4.0, 2.0, 1.0});
}

TEST(TextureFile, ExrIsLinear) {
  TempDir dir;
  Image exr(1, 1);
  exr.rgb = {0.3f, 1.7f, 0.02f};
  write_image(exr, dir.path() / "t.exr");
  const TextureImage image = load_texture_image(dir.path() / "t.exr");
  ASSERT_EQ(image.texels.size(), 1u);
  EXPECT_EQ(image.texels[0].x, 0.3f);
  EXPECT_EQ(image.texels[0].y, 1.7f);
  EXPECT_EQ(image.texels[0].z, 0.02f);
}

TEST(TextureFile, Errors) {
  TempDir dir;
  EXPECT_THROW(load_texture_image(dir.path() / "missing.png"), Error);
  const fs::path corrupt = dir.write("bad.png", "not a png at all");
  try {
    load_texture_image(corrupt);
    ADD_FAILURE() << "a corrupt PNG loaded";
  } catch (const Error& e) {
    EXPECT_EQ(e.location().file, corrupt.string());
    EXPECT_NE(e.message().find("cannot read texture"), std::string::npos) << e.what();
  }
  const fs::path other = dir.write("t.gif89", "GIF89a");
  EXPECT_THROW(load_texture_image(other), Error);
  EXPECT_THROW(load_texture_image("/dev/zero"), Error);  // endless: refused, not read
}

// A float image can hold NaN, infinity and negative values; as reflectances
// they were rendered (NaN pixels) without a word.
TEST(TextureFile, NonFiniteOrNegativeTexelsAreErrors) {
  TempDir dir;
  auto expect_texel_error = [&](const std::string& name, std::vector<float> rgb, const std::string& part) {
    Image image(2, 2);
    image.rgb = std::move(rgb);
    write_image(image, dir.path() / name);
    try {
      load_texture_image(dir.path() / name);
      ADD_FAILURE() << name << ": loaded";
    } catch (const Error& e) {
      EXPECT_EQ(e.location().file, (dir.path() / name).string());
      EXPECT_NE(e.message().find(part), std::string::npos) << e.what();
    }
  };
  const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
  expect_texel_error("nan.pfm", {0, 0, 0, 0, 0, 0, 0, nan, 0, 0, 0, 0},
                     "texel (0, 1) from the top-left is not a finite number");
  expect_texel_error("inf.exr", {0, 0, 0, 0, 0, inf, 0, 0, 0, 0, 0, 0},
                     "texel (1, 0) from the top-left is not a finite number");
  expect_texel_error("neg.exr", {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -0.5f, 0},
                     "texel (1, 1) from the top-left is negative (a reflectance must be >= 0)");
}

// --- lookups -----------------------------------------------------------------

TEST(TextureLookup, TexelCentersAndBilinearMidpoints) {
  // 2x2: row 0 (top) = 0, 1; row 1 (bottom) = 2, 4.
  const TextureImage image = gray_image(2, 2, {0, 1, 2, 4});
  auto at = [&](double u, double v) { return sample_image(image, u, v, TextureWrap::clamp).x; };
  EXPECT_NEAR(at(0.25, 0.75), 0, kTol);  // top left texel center
  EXPECT_NEAR(at(0.75, 0.75), 1, kTol);  // top right
  EXPECT_NEAR(at(0.25, 0.25), 2, kTol);  // bottom left (v grows upward)
  EXPECT_NEAR(at(0.75, 0.25), 4, kTol);
  EXPECT_NEAR(at(0.5, 0.75), 0.5, kTol);                   // between the top two
  EXPECT_NEAR(at(0.25, 0.5), 1.0, kTol);                   // between the left two
  EXPECT_NEAR(at(0.5, 0.5), (0 + 1 + 2 + 4) / 4.0, kTol);  // all four
  EXPECT_NEAR(at(0.375, 0.75), 0.25, kTol);                // a quarter of the way
}

TEST(TextureLookup, WrapTexelIndices) {
  const int n = 4;
  const int repeat[] = {2, 3, 0, 1, 2, 3, 0, 1, 2, 3};  // i = -2 .. 7
  const int clamp[] = {0, 0, 0, 1, 2, 3, 3, 3, 3, 3};
  const int mirror[] = {1, 0, 0, 1, 2, 3, 3, 2, 1, 0};
  for (int i = -2; i <= 7; ++i) {
    EXPECT_EQ(wrap_texel(i, n, TextureWrap::repeat), repeat[i + 2]) << i;
    EXPECT_EQ(wrap_texel(i, n, TextureWrap::clamp), clamp[i + 2]) << i;
    EXPECT_EQ(wrap_texel(i, n, TextureWrap::mirror), mirror[i + 2]) << i;
  }
}

TEST(TextureLookup, WrapModesOutsideTheUnitSquare) {
  const TextureImage image = gray_image(4, 1, {0, 1, 2, 3});
  auto at = [&](double u, TextureWrap w) { return sample_image(image, u, 0.5, w).x; };
  // The centers of texel indices 4 and 5 (past the right edge) and -1.
  const double i4 = 4.5 / 4, i5 = 5.5 / 4, im1 = -0.5 / 4;
  EXPECT_NEAR(at(i4, TextureWrap::repeat), 0, kTol);
  EXPECT_NEAR(at(i5, TextureWrap::repeat), 1, kTol);
  EXPECT_NEAR(at(im1, TextureWrap::repeat), 3, kTol);
  EXPECT_NEAR(at(i4, TextureWrap::clamp), 3, kTol);
  EXPECT_NEAR(at(i5, TextureWrap::clamp), 3, kTol);
  EXPECT_NEAR(at(im1, TextureWrap::clamp), 0, kTol);
  EXPECT_NEAR(at(i4, TextureWrap::mirror), 3, kTol);
  EXPECT_NEAR(at(i5, TextureWrap::mirror), 2, kTol);
  EXPECT_NEAR(at(im1, TextureWrap::mirror), 0, kTol);
  // On the edge u = 1: repeat blends the last and the first texel.
  EXPECT_NEAR(at(1.0, TextureWrap::repeat), 1.5, kTol);
  EXPECT_NEAR(at(1.0, TextureWrap::clamp), 3, kTol);
  EXPECT_NEAR(at(1.0, TextureWrap::mirror), 3, kTol);
  // Far away and non-finite coordinates stay in the image.
  EXPECT_NEAR(at(1e6 + 0.125, TextureWrap::repeat), 0, kTol);
  EXPECT_TRUE(std::isfinite(at(1e300, TextureWrap::mirror)));
  EXPECT_TRUE(std::isfinite(at(std::nan(""), TextureWrap::repeat)));
}

TEST(TextureLookup, ScaleAndOffset) {
  Scene scene;
  scene.texture_images.push_back(gray_image(4, 1, {0, 1, 2, 3}));
  Texture t;
  t.scale_u = 2;
  t.offset_u = 0.25;
  // u' = 0.5 * 2 + 0.25 = 1.25; repeat reads u = 0.25, halfway between texels 0 and 1.
  EXPECT_NEAR(evaluate_texture(scene, t, {0.5, 0.5}).x, 0.5, kTol);
  t.wrap = TextureWrap::clamp;  // u = 1.25 is past the last texel
  EXPECT_NEAR(evaluate_texture(scene, t, {0.5, 0.5}).x, 3, kTol);
}

TEST(TextureLookup, Checker) {
  Scene scene;
  Texture t;
  t.kind = TextureKind::checker;
  t.even = {1, 0, 0};
  t.odd = {0, 0, 1};
  t.scale_u = t.scale_v = 2;  // 2 x 2 cells over the unit square
  expect_color(evaluate_texture(scene, t, {0.25, 0.25}), t.even);
  expect_color(evaluate_texture(scene, t, {0.75, 0.25}), t.odd);
  expect_color(evaluate_texture(scene, t, {0.25, 0.75}), t.odd);
  expect_color(evaluate_texture(scene, t, {0.75, 0.75}), t.even);
  expect_color(evaluate_texture(scene, t, {-0.25, 0.25}), t.odd);  // floor(-0.5) = -1
  expect_color(evaluate_texture(scene, t, {-0.25, -0.25}), t.even);
  expect_color(evaluate_texture(scene, t, {10.75, 3.25}), t.odd);  // 21 + 6
  t.offset_u = 0.5;                                                // shifts by one cell
  expect_color(evaluate_texture(scene, t, {0.25, 0.25}), t.odd);
}

// --- surface coordinates ---------------------------------------------------

TEST(TextureUV, Sphere) {
  Scene scene;
  add_sphere(scene, {{1, 2, 3}, 2.0}, 0, Transform::translate({10, 0, 0}));
  Hit hit;
  auto uv = [&](const Vec3& d) { return surface_uv(scene, hit, Vec3(11, 2, 3) + 2.0 * d); };
  const double pi = std::numbers::pi;
  EXPECT_NEAR(uv({0, 0, 1}).u, 0.5, kTol);
  EXPECT_NEAR(uv({0, 0, 1}).v, 0.5, kTol);
  EXPECT_NEAR(uv({1, 0, 0}).u, 0.75, kTol);
  EXPECT_NEAR(uv({-1, 0, 0}).u, 0.25, kTol);
  EXPECT_NEAR(uv({0, 1, 0}).v, 1.0, kTol);
  EXPECT_NEAR(uv({0, -1, 0}).v, 0.0, kTol);
  const Vec3 d = normalize(Vec3(1, 1, 1));
  EXPECT_NEAR(uv(d).u, 0.5 + (pi / 4) / (2 * pi), kTol);
  EXPECT_NEAR(uv(d).v, 1.0 - std::acos(d.y) / pi, kTol);
}

TEST(TextureUV, PlaneFrames) {
  Scene scene;
  add_plane(scene, {{1, 0, 2}, {0, 1, 0}});   // floor
  add_plane(scene, {{0, 0, -5}, {0, 0, 1}});  // wall facing +z
  add_plane(scene, {{3, 0, 0}, {1, 0, 0}});   // wall facing +x
  Hit hit;
  hit.object = 0;
  UV uv = surface_uv(scene, hit, {3, 0, -1});
  EXPECT_NEAR(uv.u, 2, kTol);
  EXPECT_NEAR(uv.v, 3, kTol);  // e_v = -z
  hit.object = 1;
  uv = surface_uv(scene, hit, {1, 2, -5});
  EXPECT_NEAR(uv.u, 1, kTol);
  EXPECT_NEAR(uv.v, 2, kTol);
  hit.object = 2;
  uv = surface_uv(scene, hit, {3, 2, -1});
  EXPECT_NEAR(uv.u, 1, kTol);  // e_u = -z
  EXPECT_NEAR(uv.v, 2, kTol);
  // Any normal: an orthonormal frame with n.
  for (const Vec3& n : {normalize(Vec3(1, 2, 3)), normalize(Vec3(-3, 1, 0.5)), Vec3(0, -1, 0)}) {
    Vec3 eu, ev;
    plane_frame(n, eu, ev);
    EXPECT_NEAR(length(eu), 1, kTol);
    EXPECT_NEAR(length(ev), 1, kTol);
    EXPECT_NEAR(dot(eu, ev), 0, kTol);
    EXPECT_NEAR(dot(cross(eu, ev), n), 1, kTol);
  }
}

TEST(TextureUV, BoxFaces) {
  Scene scene;
  add_box(scene, {{0, 0, 0}, {2, 4, 8}}, 0, Transform::translate({0, 10, 0}));
  Hit hit;
  hit.face = 5;  // +z
  UV uv = surface_uv(scene, hit, {0.5, 11, 8});
  EXPECT_NEAR(uv.u, 0.25, kTol);
  EXPECT_NEAR(uv.v, 0.25, kTol);
  hit.face = 1;  // +x: u along -z
  uv = surface_uv(scene, hit, {2, 11, 2});
  EXPECT_NEAR(uv.u, 0.75, kTol);
  EXPECT_NEAR(uv.v, 0.25, kTol);
  hit.face = 3;  // +y: u along +x, v along -z
  uv = surface_uv(scene, hit, {0.5, 14, 2});
  EXPECT_NEAR(uv.u, 0.25, kTol);
  EXPECT_NEAR(uv.v, 0.75, kTol);
  hit.face = 0;  // -x: u along +z
  uv = surface_uv(scene, hit, {0, 13, 6});
  EXPECT_NEAR(uv.u, 0.75, kTol);
  EXPECT_NEAR(uv.v, 0.75, kTol);
}

TEST(TextureUV, TriangleDefaultAndGiven) {
  Scene scene = parse_scene(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, "objects": [
    {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
    {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "uv": [[0, 0], [2, 0], [0, 4]]}]})",
                            "scene.json");
  Hit hit;
  hit.b1 = 0.25;
  hit.b2 = 0.5;
  UV uv = surface_uv(scene, hit, {});
  EXPECT_NEAR(uv.u, 0.25, kTol);
  EXPECT_NEAR(uv.v, 0.5, kTol);
  hit.object = 1;
  uv = surface_uv(scene, hit, {});
  EXPECT_NEAR(uv.u, 0.5, kTol);
  EXPECT_NEAR(uv.v, 2.0, kTol);
  EXPECT_EQ(scene.triangle_uvs.size(), 1u);  // only the triangle that gave them
}

// An OBJ quad with vt, an MTL whose material uses map_Kd.
struct TexturedObj {
  TempDir dir;
  explicit TexturedObj(const std::string& map_line) {
    dir.png("tex.png", 2, 1, {255, 0, 0, 0, 0, 255});
    dir.write("quad.mtl", "newmtl m\nKd 0.5 0.5 0.5\n" + map_line + "\n");
    dir.write("quad.obj",
              "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
              "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    dir.write("scene.json", R"({"camera": {"position": [0.5, 0.5, 3], "look_at": [0.5, 0.5, 0]},
      "render": {"width": 4, "height": 4},
      "lights": [{"type": "ambient", "color": 1}],
      "objects": [{"type": "mesh", "file": "quad.obj"}]})");
  }
};

TEST(TextureUV, ObjVertexTexcoordsInterpolated) {
  TexturedObj obj("map_Kd tex.png");
  const Scene scene = load_scene(obj.dir.path() / "scene.json");
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  ASSERT_EQ(mesh.corner_uvs.size(), 3 * mesh.triangle_count());
  Hit hit;
  hit.primitive = 0;  // (0,0), (1,0), (1,1)
  hit.b1 = 0.5;
  hit.b2 = 0.25;
  const UV uv = surface_uv(scene, hit, {});
  EXPECT_NEAR(uv.u, 0.75, kTol);
  EXPECT_NEAR(uv.v, 0.25, kTol);
}

TEST(TextureUV, MeshWithoutUVsStoresNone) {
  TempDir dir;
  dir.write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  dir.write("scene.json", R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "objects": [{"type": "mesh", "file": "t.obj"}]})");
  const Scene scene = load_scene(dir.path() / "scene.json");
  EXPECT_TRUE(scene.meshes[0].corner_uvs.empty());
}

TEST(TextureUV, PlyUV) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  TempDir dir;
  dir.write("t.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0 0.1 0.2\n1 0 0 0.9 0.2\n0 1 0 0.1 0.8\n3 0 1 2\n");
  dir.write("scene.json", R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
      "objects": [{"type": "mesh", "file": "t.ply"}]})");
  const Scene scene = load_scene(dir.path() / "scene.json");
  ASSERT_EQ(scene.meshes[0].corner_uvs.size(), 3u);
  Hit hit;
  hit.b1 = 0.5;
  hit.b2 = 0.5;
  const UV uv = surface_uv(scene, hit, {});
  EXPECT_NEAR(uv.u, 0.5, 1e-6);
  EXPECT_NEAR(uv.v, 0.5, 1e-6);
}

TEST(TextureUV, GltfTexcoordsAndBaseColorTexture) {
  GLINT_SKIP_WITHOUT_ASSIMP();
  // glTF puts uv (0, 0) at the image's top left; glint's v grows upward, so
  // the file's (0,0), (1,0), (0,1) read as (0,1), (1,1), (0,0).
  const fs::path file = fs::path(GLINT_SOURCE_DIR) / "tests" / "meshes" / "textured.gltf";
  const MeshFile mesh = load_mesh_file(file);
  ASSERT_EQ(mesh.corner_uvs.size(), 3u);
  const float want[3][2] = {{0, 1}, {1, 1}, {0, 0}};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(mesh.corner_uvs[k].u, want[k][0], 1e-6) << k;
    EXPECT_NEAR(mesh.corner_uvs[k].v, want[k][1], 1e-6) << k;
  }
  ASSERT_EQ(mesh.textures.size(), 1u);
  EXPECT_EQ(mesh.textures[0].file.filename(), "textured.png");
  EXPECT_EQ(mesh.textures[0].wrap, TextureWrap::mirror);
  ASSERT_EQ(mesh.materials.size(), 1u);
  EXPECT_EQ(mesh.materials[0].diffuse_texture, 0u);
}

// --- MTL maps ---------------------------------------------------------------

TEST(MtlTextures, MapKdBecomesTheDiffuseTexture) {
  TexturedObj obj("map_Kd -clamp on -s 2 3 1 tex.png");
  const Scene scene = load_scene(obj.dir.path() / "scene.json");
  EXPECT_TRUE(scene.warnings.empty());
  const Material& m = scene.materials.back();
  ASSERT_NE(m.diffuse_texture, kNoTexture);
  const Texture& t = scene.textures[m.diffuse_texture];
  EXPECT_EQ(t.wrap, TextureWrap::clamp);
  EXPECT_EQ(t.scale_u, 2);
  EXPECT_EQ(t.scale_v, 3);
  ASSERT_EQ(scene.texture_images.size(), 1u);
  EXPECT_EQ(scene.texture_images[0].width, 2);
}

TEST(MtlTextures, MissingMapIsAWarningAndKdIsUsed) {
  TexturedObj obj("map_Kd nowhere.png");
  const Scene scene = load_scene(obj.dir.path() / "scene.json");
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("nowhere.png"), std::string::npos) << scene.warnings[0];
  EXPECT_NE(scene.warnings[0].find("not found"), std::string::npos) << scene.warnings[0];
  const Material& m = scene.materials.back();
  EXPECT_EQ(m.diffuse_texture, kNoTexture);
  expect_color(m.diffuse, Color(0.5));
  // What the integrator sees at a hit: Kd.
  const auto accel = build_accelerator(scene);
  Ray ray{{0.5, 0.5, 3}, {0, 0, -1}};
  const auto hit = accel->intersect(ray);
  ASSERT_TRUE(hit);
  expect_color(evaluate_hit(scene, ray, *hit).reflectance.diffuse, Color(0.5));
}

TEST(MtlTextures, UnreadableMapIsAWarning) {
  TexturedObj obj("map_Kd broken.png");
  obj.dir.write("broken.png", "garbage");
  const Scene scene = load_scene(obj.dir.path() / "scene.json");
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("broken.png"), std::string::npos) << scene.warnings[0];
  EXPECT_EQ(scene.materials.back().diffuse_texture, kNoTexture);
}

TEST(MtlTextures, TexturedMeshRendersTheTexelsThroughUVs) {
  // The quad's left half maps to the red texel, the right half to the blue one
  // (2x1 image, clamp so the edges do not wrap); unlit material: color = R_d.
  TexturedObj obj("map_Kd -clamp on tex.png");
  obj.dir.write("quad.mtl", "newmtl m\nillum 0\nmap_Kd -clamp on tex.png\n");
  const Scene scene = load_scene(obj.dir.path() / "scene.json");
  const auto accel = build_accelerator(scene);
  auto color_at = [&](double x) {
    const Ray ray{{x, 0.5, 3}, {0, 0, -1}};
    const auto hit = accel->intersect(ray);
    EXPECT_TRUE(hit);
    TraceContext ctx{Rng(1), {}};
    return Integrator(scene, *accel).cast_ray(ray, 1, ctx);
  };
  expect_color(color_at(0.1), {1, 0, 0});
  expect_color(color_at(0.9), {0, 0, 1});
  expect_color(color_at(0.5), {0.5, 0, 0.5});  // the bilinear midpoint
}

// --- the scene loader -------------------------------------------------------

constexpr const char* kCamera = R"("camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]})";

// The scene loaded from `dir` with these materials and one sphere per material.
Scene load_with_materials(const TempDir& dir, const std::string& materials) {
  dir.write("scene.json", std::string("{") + kCamera + ",\n\"materials\": " + materials +
                              ",\n\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1}]}");
  return load_scene(dir.path() / "scene.json");
}

TEST(TextureLoader, ImageAndCheckerKeys) {
  TempDir dir;
  fs::create_directories(dir.path() / "sub");
  dir.png("sub/a.png", 1, 1, {255, 255, 255});
  const Scene scene = load_with_materials(dir, R"({
    "a": {"diffuse": {"texture": "sub/a.png", "wrap": "mirror", "scale": [2, 3], "offset": [0.5, -1]}},
    "b": {"diffuse": {"texture": "sub/a.png"}, "specular": {"texture": "./sub/a.png", "scale": 4},
          "ambient": {"checker": {"even": [1, 0, 0], "odd": 0.5, "scale": 8, "offset": [1, 2]}}},
    "c": {"diffuse": [0.1, 0.2, 0.3]}})");
  ASSERT_EQ(scene.textures.size(), 4u);
  ASSERT_EQ(scene.texture_images.size(), 1u);  // one file, read once
  const Material& a = scene.materials[1];
  ASSERT_NE(a.diffuse_texture, kNoTexture);
  const Texture& ta = scene.textures[a.diffuse_texture];
  EXPECT_EQ(ta.kind, TextureKind::image);
  EXPECT_EQ(ta.wrap, TextureWrap::mirror);
  EXPECT_EQ(ta.scale_u, 2);
  EXPECT_EQ(ta.scale_v, 3);
  EXPECT_EQ(ta.offset_u, 0.5);
  EXPECT_EQ(ta.offset_v, -1);
  const Material& b = scene.materials[2];
  EXPECT_TRUE(b.textured());
  EXPECT_EQ(scene.textures[b.specular_texture].scale_v, 4);
  const Texture& checker = scene.textures[b.ambient_texture];
  EXPECT_EQ(checker.kind, TextureKind::checker);
  expect_color(checker.even, {1, 0, 0});
  expect_color(checker.odd, Color(0.5));
  EXPECT_EQ(checker.scale_u, 8);
  EXPECT_EQ(checker.offset_v, 2);
  EXPECT_FALSE(scene.materials[3].textured());
  EXPECT_EQ(scene.materials[3].diffuse_texture, kNoTexture);
}

// Loading must fail at the '@' with a message holding `part`.
void expect_texture_error(const TempDir& dir, const std::string& materials, const std::string& part) {
  SCOPED_TRACE(materials);
  const size_t at = materials.find('@');
  ASSERT_NE(at, std::string::npos);
  const std::string prefix = std::string("{") + kCamera + ",\n\"materials\": ";
  const std::string text = prefix + materials.substr(0, at) + materials.substr(at + 1) +
                           ",\n\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1}]}";
  const int line = 2;  // the materials sit on one line
  const int column = static_cast<int>(std::string("\"materials\": ").size() + at) + 1;
  const fs::path file = dir.write("scene.json", text);
  try {
    load_scene(file);
    ADD_FAILURE() << "loaded";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find(part), std::string::npos) << e.what();
    EXPECT_EQ(e.location().file, file.string());
    EXPECT_EQ(e.location().line, line) << e.what();
    EXPECT_EQ(e.location().column, column) << e.what();
  }
}

TEST(TextureLoader, ErrorsWithPositions) {
  TempDir dir;
  dir.png("a.png", 1, 1, {1, 2, 3});
  dir.write("broken.png", "garbage");
  expect_texture_error(
      dir, R"({"m": {"diffuse": {"texture": @"nope.png"}}})",
      "materials.m.diffuse.texture: texture file \"" + (dir.path() / "nope.png").string() + "\" not found");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": @"broken.png"}}})", "cannot read texture");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": @""}}})", "must name a texture file");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": "a.png", "wrap": @"repaet"}}})",
                       "unknown wrap mode \"repaet\" (did you mean \"repeat\"?)");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": "a.png", @"wrapp": "clamp"}}})",
                       "unknown key \"wrapp\" (did you mean \"wrap\"?)");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": "a.png", "scale": @0}}})", "must not be zero");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": "a.png", "scale": @[1, 2, 3]}}})", "expected [u, v]");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": "a.png", "offset": [1, @"x"]}}})",
                       "materials.m.diffuse.offset[1]: expected a number");
  expect_texture_error(dir, R"({"m": {"specular": @{"wrap": "clamp"}}})", "needs \"texture\"");
  expect_texture_error(dir, R"({"m": {"diffuse": {"texture": "a.png", @"checker": {}}}})", "not both");
  expect_texture_error(dir, R"({"m": {"diffuse": {"checker": @{"even": 1}}}})",
                       "materials.m.diffuse.checker: missing required key \"odd\"");
  expect_texture_error(dir, R"({"m": {"diffuse": {"checker": {"even": 1, "odd": @-1}}}})", ">= 0");
  expect_texture_error(dir, R"({"m": {"diffuse": {"checker": {"even": 1, "odd": 0}, @"scale": 2}}})",
                       "put \"scale\" inside \"checker\"");
  expect_texture_error(dir, R"({"m": {"ambient": @"a.png"}})", "{\"texture\": \"a.png\"}");
}

TEST(TextureLoader, TriangleUVErrors) {
  const std::string head = std::string("{") + kCamera +
                           ",\n\"objects\": [{\"type\": \"triangle\", "
                           "\"vertices\": [[0,0,0],[1,0,0],[0,1,0]], \"uv\": ";
  try {
    parse_scene(head + "[[0,0],[1,0]]}]}", "s.json");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("objects[0].uv: expected three [u, v] pairs"), std::string::npos) << e.what();
    EXPECT_EQ(e.location().line, 2);
  }
  try {
    parse_scene(head + "[[0,0],[1,0],[0,1,2]]}]}", "s.json");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("objects[0].uv[2]: expected [u, v]"), std::string::npos) << e.what();
  }
}

// --- rendering and explain ----------------------------------------------------

// An orthographic camera looking straight down at a textured floor: pixel
// (i, j) of the 4x4 image sees the floor at x = (i + 0.5)/2 - 1,
// z = (j + 0.5)/2 - 1, so (u, v) = (x, -z) by the plane frame of +y.
struct TexturedFloor {
  TempDir dir;
  Scene scene;
  TexturedFloor() {
    // 2x2 image: top row red, green; bottom row blue, white (8-bit sRGB bytes).
    dir.png("floor.png", 2, 2, {200, 0, 0, 0, 100, 0, 0, 0, 50, 255, 255, 255});
    dir.write("scene.json", R"({
      "render": {"width": 4, "height": 4},
      "camera": {"type": "orthographic", "position": [0, 10, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "view_height": 2},
      "materials": {"floor": {
        "ambient": [0.1, 0.2, 0.3],
        "diffuse": {"texture": "floor.png"},
        "specular": {"checker": {"even": 0.25, "odd": 0.75, "scale": 2}},
        "shininess": 10}},
      "lights": [{"type": "ambient", "color": [0.5, 0.5, 0.5]},
                 {"type": "directional", "direction": [0, -1, 0], "color": [1, 0.8, 0.6]}],
      "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}]})");
    scene = load_scene(dir.path() / "scene.json");
  }
};

TEST(TextureRender, PixelEqualsTheFormulaWithTheTexturesValues) {
  TexturedFloor floor;
  const auto accel = build_accelerator(floor.scene);
  const Image image = render_image(floor.scene, *accel);
  // Pixel (2, 1): x = 0.25, z = -0.25, so uv = (0.25, 0.25): the center of the
  // bottom-left texel (blue byte 50); the checker cell (0, 0) is even.
  // Light straight down, camera straight down: n.l = 1 and r.v = 1.
  const Color rd(0, 0, srgb_to_linear(50));
  const Color rs(0.25);
  const Color ra(0.1, 0.2, 0.3);
  const Color want = ra * Color(0.5) + rd * Color(1, 0.8, 0.6) + rs * Color(1, 0.8, 0.6);
  const float* p = image.pixel(2, 1);
  expect_color({p[0], p[1], p[2]}, want, "pixel (2, 1)");
  // Pixel (3, 0): x = 0.75, z = -0.75: uv (0.75, 0.75), the top-right texel
  // (green byte 100); the checker cell (1, 1) is even.
  const Color rd2(0, srgb_to_linear(100), 0);
  const Color want2 = ra * Color(0.5) + rd2 * Color(1, 0.8, 0.6) + rs * Color(1, 0.8, 0.6);
  const float* q = image.pixel(3, 0);
  expect_color({q[0], q[1], q[2]}, want2, "pixel (3, 0)");
  // Pixel (0, 1): x = -0.75 -> u wraps to 0.25 (repeat); checker cell (-2, 0): even.
  const Color rd3(0, 0, srgb_to_linear(50));
  const float* r = image.pixel(0, 1);
  expect_color({r[0], r[1], r[2]}, ra * Color(0.5) + rd3 * Color(1, 0.8, 0.6) + rs * Color(1, 0.8, 0.6),
               "pixel (0, 1)");
  // Pixel (1, 1): x = -0.25, uv (0.75 after wrapping, 0.25): white; checker cell (-1, 0): odd.
  const float* s = image.pixel(1, 1);
  expect_color({s[0], s[1], s[2]}, ra * Color(0.5) + Color(1) * Color(1, 0.8, 0.6) + Color(0.75) * Color(1, 0.8, 0.6),
               "pixel (1, 1)");
}

TEST(TextureRender, ConstantTexturesRenderLikeTheirColor) {
  // A checker whose two colors equal the plain color goes through the texture
  // path and must give exactly the same image, bit for bit.
  const std::string head = R"({"render": {"width": 24, "height": 16},
    "camera": {"position": [0, 2, 6], "look_at": [0, 0, 0]},
    "lights": [{"type": "point", "position": [3, 4, 5]}, {"type": "ambient", "color": 0.1}],
    "objects": [{"type": "sphere", "center": [0, 0.5, 0], "radius": 1, "material": "m"},
                {"type": "box", "min": [-3, -1, -3], "max": [3, -0.5, 3], "material": "m"}],
    "materials": {"m": {"reflectivity": 0.2, "shininess": 20, )";
  const Scene plain =
      parse_scene(head + R"("ambient": [0.2, 0.1, 0], "diffuse": [0.3, 0.6, 0.9], "specular": 0.5}}})", "p.json");
  const Scene textured = parse_scene(head + R"("ambient": {"checker": {"even": [0.2, 0.1, 0], "odd": [0.2, 0.1, 0]}},
                "diffuse": {"checker": {"even": [0.3, 0.6, 0.9], "odd": [0.3, 0.6, 0.9], "scale": 3}},
                "specular": {"checker": {"even": 0.5, "odd": 0.5}}}}})",
                                     "t.json");
  ASSERT_TRUE(textured.materials[1].textured());
  const Image a = render_image(plain, *build_accelerator(plain));
  const Image b = render_image(textured, *build_accelerator(textured));
  EXPECT_EQ(a.rgb, b.rgb);
}

TEST(TextureRender, ExplainShowsTheLookup) {
  TexturedFloor floor;
  const auto accel = build_accelerator(floor.scene);
  const PixelExplanation e = explain_pixel(floor.scene, *accel, 2, 1);
  EXPECT_TRUE(e.ray.surface.textured);
  EXPECT_NEAR(e.ray.surface.uv.u, 0.25, kTol);
  EXPECT_NEAR(e.ray.surface.uv.v, 0.25, kTol);
  const std::string json = explanation_json(floor.scene, e);
  EXPECT_NE(json.find("\"uv\""), std::string::npos);
  EXPECT_NE(json.find("\"reflectance\": \"diffuse\""), std::string::npos) << json;
  EXPECT_NE(json.find("floor.png"), std::string::npos);
  const std::string text = explanation_text(floor.scene, e);
  EXPECT_NE(text.find("texture diffuse at uv (0.25, 0.25): (0, 0, 0.0318"), std::string::npos) << text;
  EXPECT_NE(text.find("texture specular at uv (0.25, 0.25): (0.25, 0.25, 0.25) from checker"), std::string::npos)
      << text;
}

}  // namespace
}  // namespace glint
