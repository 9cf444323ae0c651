// Adaptive sampling: the choice of pixels (neighbour differences against the
// threshold), a render where flat regions keep their first-pass samples and
// edges get the maximum, each pixel equal to the same pixel of a plain render
// at its sample count, and determinism across threads and resumes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "glint/accel/accelerator.h"
#include "glint/render/renderer.h"
#include "glint/render/resume.h"

namespace glint {
namespace {

size_t count_refined(const Image& image, double threshold) {
  const std::vector<uint8_t> refine = find_pixels_to_refine(image, threshold);
  return static_cast<size_t>(std::count(refine.begin(), refine.end(), uint8_t{1}));
}

TEST(Adaptive, RefinesPixelsThatDifferFromANeighbourByMoreThanTheThreshold) {
  Image image(6, 4);
  std::fill(image.rgb.begin(), image.rgb.end(), 0.5f);
  EXPECT_EQ(count_refined(image, 0.0), 0u);
  // A vertical edge between columns 2 and 3 (green channel only): both sides,
  // and nothing else, are refined.
  for (int y = 0; y < 4; ++y)
    for (int x = 3; x < 6; ++x) image.pixel(x, y)[1] = 0.75f;
  const auto refine = find_pixels_to_refine(image, 0.05);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) EXPECT_EQ(refine[static_cast<size_t>(y * 6 + x)], x == 2 || x == 3) << x << "," << y;
  // A difference equal to the threshold is left alone; above it is not.
  EXPECT_EQ(count_refined(image, 0.25), 0u);  // 0.75 - 0.5 is exact
  EXPECT_EQ(count_refined(image, 0.2499), 8u);
  // Diagonal neighbours count; NaN counts as different.
  Image dot(3, 3);
  dot.pixel(2, 2)[0] = 1.0f;
  EXPECT_EQ(find_pixels_to_refine(dot, 0.5)[0], 0);
  EXPECT_EQ(find_pixels_to_refine(dot, 0.5)[4], 1);  // (1,1) touches (2,2) diagonally
  dot.pixel(0, 0)[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(find_pixels_to_refine(dot, 0.5)[1], 1);
}

// A lit sphere on a flat background, ambient light only: flat colors, so the
// only differences between neighbours are at the silhouette.
Scene edge_scene(int spp) {
  Scene scene;
  scene.render.width = 40;
  scene.render.height = 30;
  scene.render.samples_per_pixel = spp;
  scene.render.background = {0.1, 0.2, 0.3};
  scene.camera.type = CameraType::orthographic;
  scene.camera.position = {0, 0, 5};
  scene.camera.look_at = {0, 0, 0};
  scene.camera.view_height = 3;
  Material m;
  m.ambient = {0.9, 0.6, 0.2};
  add_sphere(scene, Sphere{{0, 0, 0}, 0.8}, add_material(scene, m));
  Light ambient;
  ambient.type = LightType::ambient;
  ambient.ambient = Color(1.0);
  scene.lights = {ambient};
  return scene;
}

Image render_adaptive(const Scene& scene, int threads, RenderStats* stats = nullptr, TileProgress* out = nullptr) {
  const auto accel = build_accelerator(scene);
  Image image(scene.render.width, scene.render.height);
  TileProgress tiles(scene.render.width, scene.render.height, 16);
  RenderOptions options;
  options.threads = threads;
  EXPECT_TRUE(render_tiles(scene, *accel, image, tiles, options, stats));
  if (out) *out = tiles;
  return image;
}

TEST(Adaptive, FlatRegionsKeepTheirSamplesEdgesGetTheMaximum) {
  Scene scene = edge_scene(4);
  scene.render.adaptive = AdaptiveSampling{32, 0.01};
  RenderStats stats;
  TileProgress tiles;
  const Image adaptive = render_adaptive(scene, 0, &stats, &tiles);
  const auto accel = build_accelerator(scene);
  Scene low = edge_scene(4), high = edge_scene(32);
  const Image at_4 = render_image(low, *accel), at_32 = render_image(high, *accel);

  const int w = scene.render.width;
  size_t refined = 0;
  for (int y = 0; y < scene.render.height; ++y) {
    for (int x = 0; x < w; ++x) {
      const bool r = tiles.refine[static_cast<size_t>(y * w + x)];
      refined += r;
      const Image& want = r ? at_32 : at_4;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(adaptive.pixel(x, y)[c], want.pixel(x, y)[c]) << x << "," << y;
    }
  }
  EXPECT_EQ(refined, stats.refined_pixels);
  // The corners are flat background, the center flat sphere: not refined.
  EXPECT_EQ(tiles.refine[0], 0);
  EXPECT_EQ(tiles.refine[static_cast<size_t>(15 * w + 20)], 0);
  // The silhouette's pixels are: along the middle row, some pixel left of the
  // sphere's edge is refined, and refinement is a thin ring (a few % of the image).
  bool edge_refined = false;
  for (int x = 0; x < 20; ++x) edge_refined |= tiles.refine[static_cast<size_t>(15 * w + x)] != 0;
  EXPECT_TRUE(edge_refined);
  EXPECT_GT(refined, 20u);
  EXPECT_LT(refined, static_cast<size_t>(w * scene.render.height / 4));
  // And the refined pixels really changed: 32 samples give other values than 4.
  EXPECT_NE(adaptive.rgb, at_4.rgb);
}

TEST(Adaptive, SameImageForAnyThreadCountAndAfterResumes) {
  Scene scene = edge_scene(2);
  scene.render.width = 70;  // several tiles, partial ones at the edges
  scene.render.height = 37;
  scene.render.adaptive = AdaptiveSampling{12, 0.01};
  TileProgress done;
  const Image one = render_adaptive(scene, 1, nullptr, &done);
  EXPECT_EQ(one.rgb, render_adaptive(scene, 2).rgb);
  EXPECT_EQ(one.rgb, render_adaptive(scene, 7).rgb);
  const auto accel = build_accelerator(scene);
  const int w = scene.render.width, h = scene.render.height;

  // Interrupted in the first pass: half the tiles have their first-pass pixels.
  Scene first_pass = scene;
  first_pass.render.adaptive.reset();
  const Image stage1 = render_image(first_pass, *accel);
  {
    Image image(w, h);
    TileProgress tiles(w, h, 16);
    for (size_t t = 0; t < tiles.done.size(); ++t) {
      if (t % 2) continue;
      tiles.done[t] = 1;
      const int x0 = static_cast<int>(t % tiles.tiles_x) * 16, y0 = static_cast<int>(t / tiles.tiles_x) * 16;
      for (int y = y0; y < std::min(y0 + 16, h); ++y)
        for (int x = x0; x < std::min(x0 + 16, w); ++x) std::copy_n(stage1.pixel(x, y), 3, image.pixel(x, y));
    }
    EXPECT_TRUE(render_tiles(scene, *accel, image, tiles));
    EXPECT_EQ(image.rgb, one.rgb);
  }
  // Interrupted in the refinement, through a resume file: half the tiles
  // refined, the others still first-pass (one of them part-way, as a cancel
  // between rows leaves it).
  {
    Image image = one;
    TileProgress tiles = done;
    for (size_t t = 0; t < tiles.done.size(); ++t) {
      if (t % 2) continue;
      tiles.done[t] = 1;
      const int x0 = static_cast<int>(t % tiles.tiles_x) * 16, y0 = static_cast<int>(t / tiles.tiles_x) * 16;
      const int rows = t == 0 ? 5 : 16;  // tile 0 keeps its first 5 refined rows
      for (int y = y0 + (t == 0 ? rows : 0); y < std::min(y0 + 16, h); ++y)
        for (int x = x0; x < std::min(x0 + 16, w); ++x) std::copy_n(stage1.pixel(x, y), 3, image.pixel(x, y));
    }
    ASSERT_NE(image.rgb, one.rgb);
    const auto path = std::filesystem::temp_directory_path() / ("glint-adaptive-" + std::to_string(::getpid()));
    write_resume_file(path, ResumeState{7, tiles, image, {}});
    auto state = read_resume_file(path);
    std::filesystem::remove(path);
    ASSERT_TRUE(state);
    EXPECT_EQ(state->progress.refine, done.refine);
    EXPECT_EQ(state->progress.done, tiles.done);
    EXPECT_TRUE(render_tiles(scene, *accel, state->image, state->progress));
    EXPECT_EQ(state->image.rgb, one.rgb);
  }
}

}  // namespace
}  // namespace glint
