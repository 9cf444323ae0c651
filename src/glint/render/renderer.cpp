#include "glint/render/renderer.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cmath>
#include <mutex>
#include <thread>

#include "glint/render/camera.h"

namespace glint {

int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

Rng pixel_rng(int x, int y) {
  return Rng(mix_seed(static_cast<uint64_t>(x), static_cast<uint64_t>(y), 0x676c696e74ULL));
}

void stratified_grid(int samples, int& nx, int& ny) {
  nx = static_cast<int>(std::sqrt(static_cast<double>(samples)));
  while (samples % nx != 0) --nx;
  ny = samples / nx;
}

namespace {

Color render_pixel_with(const Integrator& integrator, const Scene& scene, const CameraFrame& frame,
                        int x, int y, TraceContext& ctx) {
  const int w = scene.render.width, h = scene.render.height;
  const int spp = scene.render.samples_per_pixel;
  ctx.rng = pixel_rng(x, y);
  if (spp == 1) {
    ctx.stats.camera++;
    const Ray ray = generate_camera_ray(frame, (x + 0.5) / w, (y + 0.5) / h);
    return integrator.cast_ray(ray, 1, ctx);
  }
  int nx, ny;
  stratified_grid(spp, nx, ny);
  Color sum(0.0);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double u = (x + (i + ctx.rng.next_double()) / nx) / w;
      const double v = (y + (j + ctx.rng.next_double()) / ny) / h;
      ctx.stats.camera++;
      sum += integrator.cast_ray(generate_camera_ray(frame, u, v), 1, ctx);
    }
  }
  return sum / spp;
}

}  // namespace

Color render_pixel(const Integrator& integrator, const Scene& scene, int x, int y, TraceContext& ctx) {
  const CameraFrame frame = make_camera_frame(scene.camera, scene.render.width, scene.render.height);
  return render_pixel_with(integrator, scene, frame, x, y, ctx);
}

Image render_image(const Scene& scene, const Accelerator& accel, const RenderOptions& options,
                   RenderStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  const int w = scene.render.width, h = scene.render.height;
  Image image(w, h);
  const Integrator integrator(scene, accel);
  const CameraFrame frame = make_camera_frame(scene.camera, w, h);

  const int tile = std::max(1, options.tile_size);
  const int tiles_x = (w + tile - 1) / tile, tiles_y = (h + tile - 1) / tile;
  const int tile_count = tiles_x * tiles_y;
  const int threads = std::max(1, std::min(resolve_thread_count(options.threads), tile_count));

  std::atomic<int> next_tile{0};
  std::atomic<int> tiles_done{0};
  std::mutex stats_mutex;
  std::condition_variable all_done;
  RayStats total;
  auto worker = [&] {
    TraceContext ctx{Rng(0), {}};
    for (int t = next_tile++; t < tile_count; t = next_tile++) {
      const int x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
      const int x1 = std::min(x0 + tile, w), y1 = std::min(y0 + tile, h);
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const Color c = render_pixel_with(integrator, scene, frame, x, y, ctx);
          float* px = image.pixel(x, y);
          px[0] = static_cast<float>(c.x);
          px[1] = static_cast<float>(c.y);
          px[2] = static_cast<float>(c.z);
        }
      }
      if (++tiles_done == tile_count) {
        std::lock_guard lock(stats_mutex);
        all_done.notify_all();
      }
    }
    std::lock_guard lock(stats_mutex);
    total += ctx.stats;
  };

  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  if (options.progress) {
    std::unique_lock lock(stats_mutex);
    while (!all_done.wait_for(lock, std::chrono::milliseconds(100),
                              [&] { return tiles_done.load() == tile_count; })) {
      options.progress(static_cast<double>(tiles_done.load()) / tile_count);
    }
    lock.unlock();
    options.progress(1.0);
  }
  for (std::thread& t : pool) t.join();

  if (stats) {
    stats->rays = total;
    stats->threads = threads;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return image;
}

}  // namespace glint
