// render_image: the film loop. Splits the image into tiles that worker threads
// take in turn; every pixel seeds its own random numbers from its coordinates,
// so the image is bit-identical whatever the thread count.
#pragma once

#include <functional>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/render/integrator.h"

namespace glint {

struct RenderOptions {
  int threads = 0;      // 0: all cores
  int tile_size = 16;
  // Called on the calling thread about ten times a second with the fraction done.
  std::function<void(double fraction)> progress;
};

struct RenderStats {
  RayStats rays;
  double seconds = 0;  // wall time of the pixel loop
  int threads = 1;
};

// Sample positions inside a pixel: spp 1 is the exact center; N > 1 is one
// jittered point per cell of an nx x ny grid with nx * ny == N.
void stratified_grid(int samples, int& nx, int& ny);

Image render_image(const Scene& scene, const Accelerator& accel, const RenderOptions& options = {},
                   RenderStats* stats = nullptr);

// Color of one pixel (all its samples averaged): what render_image stores.
Color render_pixel(const Integrator& integrator, const Scene& scene, int x, int y, TraceContext& ctx);

int resolve_thread_count(int requested);

// The random numbers of pixel (x, y): seeded from its coordinates alone.
Rng pixel_rng(int x, int y);

}  // namespace glint
