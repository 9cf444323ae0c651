// render_image: the film loop. Splits the image into tiles that worker threads
// take in turn; every pixel seeds its own random numbers from its coordinates,
// so the image is bit-identical whatever the thread count.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/render/integrator.h"
#include "glint/render/passes.h"
#include "glint/render/tile_size.h"

namespace glint {

struct RenderOptions {
  int threads = 0;  // 0: all cores
  int tile_size = kTileSize;
  // Called on the calling thread about ten times a second with the fraction done.
  std::function<void(double fraction)> progress;
  // When set and true, workers stop taking tiles and abandon the ones they are
  // on (checked once per row); finished tiles stay finished.
  const std::atomic<bool>* cancel = nullptr;
  // When set, called as rows of the image become final (every tile across
  // them finished its last stage) with the number of final rows from the
  // top: increasing, one call at a time (first for the tiles a resumed
  // render already had, then from the worker threads), up to the height
  // once the render is complete. It runs under a lock the workers share:
  // it must be quick and must not throw. A PngStream compresses the rows
  // meanwhile.
  std::function<void(int rows)> rows_final;
};

// Which tiles of an image are finished: the unit of interrupt and resume.
// With adaptive sampling a tile is finished in two stages: the first pass,
// then the refinement of its chosen pixels.
struct TileProgress {
  int tile_size = kTileSize;
  int tiles_x = 0, tiles_y = 0;
  std::vector<uint8_t> done;  // tiles_x * tiles_y flags, row-major: the stages finished (0, 1, 2)
  uint8_t stages = 1;         // 2 with adaptive sampling (render_tiles sets it)
  // Adaptive sampling: per pixel (row-major), 1 = refined. Empty until the
  // whole first pass is done, then decided once from it.
  std::vector<uint8_t> refine;

  TileProgress() = default;
  TileProgress(int width, int height, int tile);
  size_t count_done() const;  // tiles with every stage finished
  bool complete() const { return count_done() == done.size(); }
};

struct RenderStats {
  RayStats rays;
  size_t refined_pixels = 0;  // adaptive sampling: pixels rendered again at its max
  double seconds = 0;         // wall time of the pixel loop
  int threads = 1;
};

Image render_image(const Scene& scene, const Accelerator& accel, const RenderOptions& options = {},
                   RenderStats* stats = nullptr);

// Renders the tiles of `image` not yet marked in `progress` (tile size taken
// from it), marking each one as it completes. Returns progress.complete().
// A resumed render gives the same bytes as an uninterrupted one: pixels
// depend only on their coordinates. With `passes`, fills its images too
// (same samples, same weights; the image itself is unchanged by it).
bool render_tiles(const Scene& scene, const Accelerator& accel, Image& image, TileProgress& progress,
                  const RenderOptions& options = {}, RenderStats* stats = nullptr, PassImages* passes = nullptr);

// Adaptive sampling's choice, from a complete first-pass image: a pixel is
// refined when one of its (up to) 8 neighbours differs from it by more than
// `threshold` in some channel (linear values; NaN counts as different).
std::vector<uint8_t> find_pixels_to_refine(const Image& image, double threshold);

// Paints the pixels of tiles with no finished stage with the background color
// (a tile whose refinement was interrupted keeps its first-pass pixels).
void fill_unfinished_tiles(Image& image, const TileProgress& progress, const Color& background);

// Renders whole tiles as render_tiles' first pass does, with one camera
// frame and filter table for all of them and camera packets at 1 spp: the
// same bits. For callers that hand out tiles themselves (render_tile_stream).
class TileRenderer {
 public:
  TileRenderer(const Integrator& integrator, const Scene& scene, const Accelerator& accel);
  ~TileRenderer();
  TileRenderer(const TileRenderer&) = delete;
  TileRenderer& operator=(const TileRenderer&) = delete;
  // Pixels [x0, x1) x [y0, y1) of `image` (scene.render's size). Thread-safe.
  void render(int x0, int y0, int x1, int y1, TraceContext& ctx, Image& image) const;

 private:
  struct Context;
  const Accelerator& accel_;
  std::unique_ptr<Context> context_;
};

int resolve_thread_count(int requested);

// The random numbers of pixel (x, y): seeded from its coordinates alone.
Rng pixel_rng(int x, int y);

}  // namespace glint
