// render_tile_stream, the engine of distributed rendering: tiles taken in
// whatever order a source hands them out give the very pixels of
// render_image (checked here without MPI, so also in builds without it).
#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"
#include "glint/render/tile_stream.h"

namespace glint {
namespace {

// Shuffled tiles on 3 threads; the image must be render_image's, bit for bit.
void check_any_order(Scene scene) {
  scene.render.width = 83;  // partial tiles on both edges
  scene.render.height = 37;
  const auto accel = build_accelerator(scene);
  const Image whole = render_image(scene, *accel);

  const int tiles = ((83 + 15) / 16) * ((37 + 15) / 16);
  std::vector<int> order(tiles);
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  std::mutex m;
  size_t next = 0;
  std::multiset<int> done;
  TileStream stream;
  stream.next = [&] {
    std::lock_guard lock(m);
    return next < order.size() ? order[next++] : -1;
  };
  stream.done = [&](int t) {
    std::lock_guard lock(m);
    done.insert(t);
  };
  Image image(83, 37);
  const RayStats rays = render_tile_stream(scene, *accel, image, stream, 3);
  EXPECT_EQ(image.rgb, whole.rgb);
  EXPECT_EQ(done.size(), static_cast<size_t>(tiles));
  EXPECT_EQ(std::set<int>(done.begin(), done.end()).size(), static_cast<size_t>(tiles)) << "a tile twice";
  EXPECT_EQ(rays.camera, 83u * 37u * static_cast<unsigned>(scene.render.samples_per_pixel));
}

Scene showcase() { return load_scene(std::string(GLINT_SOURCE_DIR) + "/scenes/showcase.json"); }

TEST(TileStream, AnyTileOrderGivesTheImageOfRenderImage) {
  Scene scene = showcase();
  scene.render.samples_per_pixel = 2;
  check_any_order(scene);
}

TEST(TileStream, OneSampleTracesCameraPacketsAsRenderImageDoes) {
  Scene scene = showcase();
  scene.render.samples_per_pixel = 1;
  check_any_order(scene);
}

TEST(TileStream, PixelFiltersGiveTheImageOfRenderImage) {
  Scene scene = showcase();
  scene.render.samples_per_pixel = 4;
  scene.render.pixel_filter.type = FilterType::gaussian;
  scene.render.pixel_filter.radius = kGaussianRadius;
  check_any_order(scene);
  scene.render.pixel_filter.type = FilterType::mitchell;
  scene.render.pixel_filter.radius = kMitchellRadius;
  check_any_order(scene);
}

}  // namespace
}  // namespace glint
