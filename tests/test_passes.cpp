// Passes (AOVs): the five color passes sum to the image on every pixel (hits,
// misses, reflection, refraction, area lights, unlit materials, several
// samples per pixel); the image is unchanged by asking for passes; normal,
// depth and albedo hold the first hit's facts; passes are the same for any
// thread count and survive an interrupted-then-resumed render.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/render/passes.h"
#include "glint/render/renderer.h"
#include "glint/render/resume.h"

namespace glint {
namespace {

std::vector<Pass> all_passes() { return parse_pass_list("all"); }

struct Rendered {
  Image image;
  PassImages passes;
};

Rendered render_with_passes(const Scene& scene, int threads = 0) {
  const auto accel = build_accelerator(scene);
  Rendered r{Image(scene.render.width, scene.render.height),
             PassImages(all_passes(), scene.render.width, scene.render.height)};
  TileProgress tiles(scene.render.width, scene.render.height, 16);
  RenderOptions options;
  options.threads = threads;
  EXPECT_TRUE(render_tiles(scene, *accel, r.image, tiles, options, nullptr, &r.passes));
  return r;
}

const Image& pass_image(const Rendered& r, Pass p) {
  const auto it = std::find(r.passes.passes.begin(), r.passes.passes.end(), p);
  return r.passes.images[static_cast<size_t>(it - r.passes.passes.begin())];
}

// Largest |sum of the five color passes (as stored, float) - image| relative
// to max(1, |image|), over all pixels and channels: what an outside checker sees.
double worst_sum_error(const Rendered& r) {
  double worst = 0;
  for (size_t i = 0; i < r.image.rgb.size(); ++i) {
    double sum = 0;
    for (int p = 0; p < kColorPassCount; ++p) sum += pass_image(r, static_cast<Pass>(p)).rgb[i];
    const double beauty = r.image.rgb[i];
    worst = std::max(worst, std::abs(sum - beauty) / std::max(1.0, std::abs(beauty)));
  }
  return worst;
}

Scene scene_file(const std::string& relative, int w, int h, int spp) {
  Scene scene = load_scene(std::string(GLINT_SOURCE_DIR) + "/" + relative);
  scene.render.width = w;
  scene.render.height = h;
  scene.render.samples_per_pixel = spp;
  return scene;
}

// An area light, a mirror, a glass ball, an unlit sphere and background all in view.
Scene mixed_scene(int spp) {
  Scene scene;
  scene.render.width = 48;
  scene.render.height = 32;
  scene.render.samples_per_pixel = spp;
  scene.render.background = {0.2, 0.3, 0.5};
  scene.camera.position = {0, 1.5, 6};
  scene.camera.look_at = {0, 0.5, 0};
  Material mirror;
  mirror.diffuse = Color(0.2);
  mirror.reflectivity = Color(0.6);
  Material glass;
  glass.diffuse = Color(0.05);
  glass.specular = Color(0.7);
  glass.transparency = 0.9;
  glass.fresnel = true;
  Material unlit;
  unlit.diffuse = {0.9, 0.4, 0.1};
  unlit.unlit = true;
  Material shiny;
  shiny.ambient = Color(0.1);
  shiny.diffuse = {0.2, 0.7, 0.3};
  shiny.specular = Color(0.8);
  const uint32_t m_mirror = add_material(scene, mirror), m_glass = add_material(scene, glass);
  const uint32_t m_unlit = add_material(scene, unlit), m_shiny = add_material(scene, shiny);
  add_sphere(scene, Sphere{{-1.2, 0.6, 0}, 0.6}, m_shiny);
  add_sphere(scene, Sphere{{0.2, 0.5, 0.8}, 0.5}, m_glass);
  add_sphere(scene, Sphere{{1.4, 0.5, -0.5}, 0.5}, m_unlit);
  add_triangle(scene, Triangle{{-3, 0, -2}, {3, 0, -2}, {0, 0, 3}}, m_mirror);
  Light ambient;
  ambient.type = LightType::ambient;
  ambient.ambient = Color(0.3);
  Light area;
  area.type = LightType::area;
  area.corner = {-1, 4, -1};
  area.edge_u = {2, 0, 0};
  area.edge_v = {0, 0, 2};
  area.samples = 9;
  scene.lights = {ambient, area};
  return scene;
}

TEST(Passes, ColorPassesSumToTheImageOnEveryPixel) {
  const std::vector<std::pair<std::string, Scene>> scenes = {
      {"showcase spp 1", scene_file("scenes/showcase.json", 80, 45, 1)},
      {"showcase spp 5", scene_file("scenes/showcase.json", 80, 45, 5)},
      {"refraction spp 4", scene_file("scenes/figures/refraction.json", 60, 40, 4)},
      {"mirrors", scene_file("scenes/figures/mirrors.json", 60, 40, 2)},
      {"mixed spp 1", mixed_scene(1)},
      {"mixed spp 6", mixed_scene(6)},
  };
  for (const auto& [name, scene] : scenes) {
    const Rendered r = render_with_passes(scene);
    EXPECT_LE(worst_sum_error(r), 1e-6) << name;
    // The scene really exercises every part somewhere.
    for (int p = 0; p < kColorPassCount; ++p) {
      if (name.rfind("mixed", 0) != 0) continue;
      const Image& img = pass_image(r, static_cast<Pass>(p));
      EXPECT_GT(*std::max_element(img.rgb.begin(), img.rgb.end()), 0.0f) << name << " " << p;
    }
  }
}

TEST(Passes, TheCheckCanFail) {
  Rendered r = render_with_passes(mixed_scene(1));
  Image& diffuse = r.passes.images[1];
  ASSERT_EQ(r.passes.passes[1], Pass::diffuse);
  diffuse.rgb[diffuse.rgb.size() / 2] += 1e-3f;
  EXPECT_GT(worst_sum_error(r), 1e-4);
}

TEST(Passes, ImageIsBitIdenticalWithOrWithoutPasses) {
  for (int spp : {1, 4}) {
    const Scene scene = mixed_scene(spp);
    const auto accel = build_accelerator(scene);
    EXPECT_EQ(render_with_passes(scene).image.rgb, render_image(scene, *accel).rgb) << spp;
  }
}

TEST(Passes, MissesPutTheBackgroundInAmbientAndZeroElsewhere) {
  const Scene scene = mixed_scene(1);
  const Rendered r = render_with_passes(scene);
  // The top-left pixel looks over everything at the sky.
  const float* ambient = pass_image(r, Pass::ambient).pixel(0, 0);
  EXPECT_EQ(ambient[0], 0.2f);
  EXPECT_EQ(ambient[2], 0.5f);
  for (Pass p :
       {Pass::diffuse, Pass::specular, Pass::reflection, Pass::transmission, Pass::normal, Pass::depth, Pass::albedo}) {
    const float* v = pass_image(r, p).pixel(0, 0);
    EXPECT_EQ(v[0], 0.0f) << pass_name(p);
    EXPECT_EQ(v[1], 0.0f) << pass_name(p);
  }
}

TEST(Passes, UnlitMaterialsGoToAmbient) {
  Scene scene = mixed_scene(1);
  scene.render.width = scene.render.height = 1;
  scene.camera.position = {1.4, 0.5, 3};  // straight at the unlit sphere
  scene.camera.look_at = {1.4, 0.5, -0.5};
  const Rendered r = render_with_passes(scene);
  EXPECT_FLOAT_EQ(pass_image(r, Pass::ambient).pixel(0, 0)[0], 0.9f);
  EXPECT_EQ(pass_image(r, Pass::diffuse).pixel(0, 0)[0], 0.0f);
  EXPECT_FLOAT_EQ(r.image.pixel(0, 0)[0], 0.9f);
}

TEST(Passes, NormalDepthAndAlbedoOfAKnownHit) {
  // Looking straight down -z at a wall z = -2 from z = 3: the center pixel's
  // ray hits at distance 5 with normal +z; seen from behind, the normal flips.
  Scene scene;
  scene.render.width = scene.render.height = 3;
  scene.camera.position = {0, 0, 3};
  scene.camera.look_at = {0, 0, 0};
  Material wall;
  wall.diffuse = {0.25, 0.5, 0.75};
  add_plane(scene, Plane{{0, 0, -2}, {0, 0, -1}}, add_material(scene, wall));
  const Rendered r = render_with_passes(scene);
  const float* n = pass_image(r, Pass::normal).pixel(1, 1);
  EXPECT_FLOAT_EQ(n[0], 0.0f);
  EXPECT_FLOAT_EQ(n[2], 1.0f);  // turned toward the camera (as shaded)
  EXPECT_FLOAT_EQ(pass_image(r, Pass::depth).pixel(1, 1)[0], 5.0f);
  EXPECT_FLOAT_EQ(pass_image(r, Pass::depth).pixel(1, 1)[2], 5.0f);
  const float* albedo = pass_image(r, Pass::albedo).pixel(1, 1);
  EXPECT_FLOAT_EQ(albedo[0], 0.25f);
  EXPECT_FLOAT_EQ(albedo[2], 0.75f);
  // A corner pixel: a longer, oblique ray (depth = distance along the ray, not z).
  EXPECT_GT(pass_image(r, Pass::depth).pixel(0, 0)[0], 5.0f);
}

TEST(Passes, SameForAnyThreadCount) {
  const Scene scene = mixed_scene(4);
  const Rendered one = render_with_passes(scene, 1), two = render_with_passes(scene, 2),
                 seven = render_with_passes(scene, 7);
  for (size_t i = 0; i < one.passes.images.size(); ++i) {
    EXPECT_EQ(one.passes.images[i].rgb, two.passes.images[i].rgb) << i;
    EXPECT_EQ(one.passes.images[i].rgb, seven.passes.images[i].rgb) << i;
  }
}

TEST(Passes, ResumedRenderGivesTheSamePasses) {
  const Scene scene = mixed_scene(2);
  const auto accel = build_accelerator(scene);
  const Rendered whole = render_with_passes(scene);
  const int w = scene.render.width, h = scene.render.height;
  Image image(w, h);
  PassImages passes(all_passes(), w, h);
  TileProgress first(w, h, 16), rest(w, h, 16);
  for (size_t t = 0; t < first.done.size(); ++t) first.done[t] = t % 2 != 0;
  ASSERT_TRUE(render_tiles(scene, *accel, image, first, {}, nullptr, &passes));
  // Through a resume file, as the CLI does it.
  for (size_t t = 0; t < rest.done.size(); ++t) rest.done[t] = t % 2 == 0;
  const auto path = std::filesystem::temp_directory_path() / ("glint-passes-" + std::to_string(::getpid()));
  write_resume_file(path, ResumeState{1, rest, image, passes});
  auto state = read_resume_file(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(state);
  ASSERT_EQ(state->passes.passes, all_passes());
  EXPECT_TRUE(render_tiles(scene, *accel, state->image, state->progress, {}, nullptr, &state->passes));
  EXPECT_EQ(state->image.rgb, whole.image.rgb);
  for (size_t i = 0; i < whole.passes.images.size(); ++i)
    EXPECT_EQ(state->passes.images[i].rgb, whole.passes.images[i].rgb) << i;
}

TEST(Passes, ListParsingAndFileNames) {
  EXPECT_EQ(parse_pass_list("diffuse,normal,diffuse"), (std::vector<Pass>{Pass::diffuse, Pass::normal}));
  EXPECT_EQ(parse_pass_list("all").size(), 8u);
  try {
    parse_pass_list("diffuse,speculr");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean \"specular\""), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_pass_list(""), Error);
  EXPECT_EQ(pass_file_name("out/x.pfm", Pass::diffuse), "out/x.diffuse.pfm");
  EXPECT_EQ(pass_file_name("render.final.exr", Pass::depth), "render.final.depth.exr");
}

TEST(Passes, EightBitEncodingOfNormalAndDepth) {
  Image normal(2, 1), depth(2, 1);
  normal.rgb = {0, 0, 0, 0, -1, 1};
  depth.rgb = {2, 2, 4, 4, 4, 4};
  const Image n8 = pass_image_for_8bit(Pass::normal, normal);
  EXPECT_EQ(n8.rgb, (std::vector<float>{0, 0, 0, 0.5f, 0, 1}));
  const Image d8 = pass_image_for_8bit(Pass::depth, depth);
  EXPECT_EQ(d8.rgb, (std::vector<float>{0.5f, 0.5f, 1, 1, 1, 1}));
}

}  // namespace
}  // namespace glint
