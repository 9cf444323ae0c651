#include "glint/render/tile_stream.h"

#include <algorithm>
#include <mutex>
#include <thread>
#include <vector>

#include "glint/render/renderer.h"

namespace glint {

RayStats render_tile_stream(const Scene& scene, const Accelerator& accel, Image& image, const TileStream& stream,
                            int threads) {
  const int w = scene.render.width, h = scene.render.height, tile = stream.tile_size;
  const int tiles_x = (w + tile - 1) / tile;
  const Integrator integrator(scene, accel);
  const TileRenderer renderer(integrator, scene, accel);  // what render_tiles does with a tile
  std::mutex stats_mutex;
  RayStats total;
  auto worker = [&] {
    TraceContext ctx{Rng(0), {}};
    for (int t = stream.next(); t >= 0; t = stream.next()) {
      const int x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
      renderer.render(x0, y0, std::min(x0 + tile, w), std::min(y0 + tile, h), ctx, image);
      if (stream.done) stream.done(t);
    }
    std::lock_guard lock(stats_mutex);
    total += ctx.stats;
  };
  std::vector<std::thread> pool;
  for (int i = 0; i < std::max(1, threads); ++i) pool.emplace_back(worker);
  for (std::thread& t : pool) t.join();
  return total;
}

}  // namespace glint
