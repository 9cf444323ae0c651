#include "glint/render/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "glint/accel/packet_slots.h"
#include "glint/render/camera.h"
#include "glint/render/filter.h"
#include "glint/render/stratified.h"

namespace glint {

int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

Rng pixel_rng(int x, int y) {
  return Rng(mix_seed(static_cast<uint64_t>(x), static_cast<uint64_t>(y), 0x676c696e74ULL));
}

namespace {

// One pixel's sums: the image's and, when passes are asked for, every pass's,
// each added with the same sample weights.
struct PixelSums {
  Color color;
  std::array<Color, kPassCount> passes{};
};

// Adds one camera sample of weight `w` to `sums`. The pass path's color is
// CameraSample::color, bit for bit cast_ray's.
// `known_hit`, when given, is the ray's first hit, already found.
template <bool kWithPasses>
void add_camera_sample(const Integrator& integrator, const Ray& ray, double w, TraceContext& ctx, PixelSums& sums,
                       const std::optional<Hit>* known_hit = nullptr) {
  ctx.stats.camera++;
  if constexpr (!kWithPasses) {
    sums.color +=
        w * (known_hit ? integrator.cast_ray_with_hit(ray, *known_hit, 1, ctx) : integrator.cast_ray(ray, 1, ctx));
  } else {
    const CameraSample s =
        known_hit ? integrator.cast_camera_ray_with_hit(ray, *known_hit, ctx) : integrator.cast_camera_ray(ray, ctx);
    sums.color += w * s.color;
    auto add = [&](Pass p, const Color& c) { sums.passes[static_cast<size_t>(p)] += w * c; };
    add(Pass::ambient, s.terms.ambient);
    add(Pass::diffuse, s.terms.diffuse);
    add(Pass::specular, s.terms.specular);
    add(Pass::reflection, s.terms.reflection);
    add(Pass::transmission, s.terms.transmission);
    add(Pass::normal, s.normal);
    add(Pass::depth, Color(s.depth));
    add(Pass::albedo, s.albedo);
  }
}

// What every pixel of one render shares: the camera and the filter's table.
struct PixelContext {
  const Integrator& integrator;
  const Scene& scene;
  CameraFrame frame;
  std::optional<FilterSampler> filter;  // none for the box filter
};

Ray center_ray(const PixelContext& pc, int x, int y) {
  return generate_camera_ray(pc.frame, (x + 0.5) / pc.scene.render.width, (y + 0.5) / pc.scene.render.height);
}

// A pixel's lens points (empty for a pinhole): one jittered point per cell of
// a stratified grid over the disk's square (concentric map), handed to the
// pixel's samples in an order shuffled per pixel, so that where a sample
// crosses the lens is independent of where it crosses the pixel. Drawn from
// the pixel's own random numbers: the same for any thread count.
const std::vector<LensPoint>& lens_points(const CameraFrame& frame, int spp, Rng& rng) {
  thread_local std::vector<LensPoint> points;
  points.clear();
  if (!(frame.aperture > 0.0)) return points;
  const auto [nx, ny] = stratified_grid(spp);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      points.push_back(concentric_disk((i + rng.next_double()) / nx, (j + rng.next_double()) / ny));
  for (size_t k = points.size(); k > 1; --k) std::swap(points[k - 1], points[rng.next_u32() % k]);
  return points;
}

// The pixel's `spp` samples, summed into `sums`; returns the divisor that
// turns the sums into the pixel's values.
template <bool kWithPasses>
double sum_pixel_samples(const PixelContext& pc, int x, int y, int spp, TraceContext& ctx, PixelSums& sums,
                         const std::optional<Hit>* center_hit = nullptr) {
  const int w = pc.scene.render.width, h = pc.scene.render.height;
  ctx.rng = pixel_rng(x, y);
  if (spp == 1) {  // the contract's center ray, whatever the filter
    add_camera_sample<kWithPasses>(pc.integrator, center_ray(pc, x, y), 1.0, ctx, sums, center_hit);
    return 1.0;
  }
  // Sample positions inside a pixel: spp 1 is the exact center (above);
  // N > 1 is one jittered point per cell of the stratified grid.
  const auto [nx, ny] = stratified_grid(spp);
  const std::vector<LensPoint>& lens = lens_points(pc.frame, spp, ctx.rng);
  const auto lens_point = [&](int k) { return lens.empty() ? LensPoint{} : lens[static_cast<size_t>(k)]; };
  if (!pc.filter) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const double u = (x + (i + ctx.rng.next_double()) / nx) / w;
        const double v = (y + (j + ctx.rng.next_double()) / ny) / h;
        add_camera_sample<kWithPasses>(pc.integrator, generate_camera_ray(pc.frame, u, v, lens_point(j * nx + i)),
                                       1.0, ctx, sums);
      }
    }
    return spp;
  }
  // The same stratified grid, mapped through the filter's inverse CDF.
  double weight_sum = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double su = (i + ctx.rng.next_double()) / nx;
      const double sv = (j + ctx.rng.next_double()) / ny;
      const FilterSample fs = pc.filter->sample(su, sv);
      const double u = (x + 0.5 + fs.dx) / w, v = (y + 0.5 + fs.dy) / h;
      add_camera_sample<kWithPasses>(pc.integrator, generate_camera_ray(pc.frame, u, v, lens_point(j * nx + i)),
                                     fs.weight, ctx, sums);
      weight_sum += fs.weight;
    }
  }
  // pbrt-v4's normalization (sum of weights), so a flat region stays flat.
  // Mitchell's signed weights could cancel exactly: then the plain mean.
  return weight_sum != 0.0 ? weight_sum : spp;
}

// Weight 1 and a division by spp: the box filter's average, as it always was
// (x * 1.0 and x / 1.0 are exact, so spp 1 is the center ray's color itself).
Color render_pixel_with(const PixelContext& pc, int x, int y, int spp, TraceContext& ctx,
                        const std::optional<Hit>* center_hit = nullptr) {
  PixelSums sums;
  const double divisor = sum_pixel_samples<false>(pc, x, y, spp, ctx, sums, center_hit);
  return sums.color / divisor;
}

void store(Image& image, int x, int y, const Color& c) {
  float* px = image.pixel(x, y);
  px[0] = static_cast<float>(c.x);
  px[1] = static_cast<float>(c.y);
  px[2] = static_cast<float>(c.z);
}

// The pixel and its passes, stored.
void render_pixel_into(const PixelContext& pc, int x, int y, int spp, TraceContext& ctx, Image& image,
                       PassImages* passes, const std::optional<Hit>* center_hit = nullptr) {
  if (!passes || passes->empty()) {
    store(image, x, y, render_pixel_with(pc, x, y, spp, ctx, center_hit));
    return;
  }
  PixelSums sums;
  const double divisor = sum_pixel_samples<true>(pc, x, y, spp, ctx, sums, center_hit);
  store(image, x, y, sums.color / divisor);
  for (size_t i = 0; i < passes->passes.size(); ++i)
    store(passes->images[i], x, y, sums.passes[static_cast<size_t>(passes->passes[i])] / divisor);
}

PixelContext make_pixel_context(const Integrator& integrator, const Scene& scene) {
  PixelContext pc{integrator, scene, make_camera_frame(scene.camera, scene.render.width, scene.render.height), {}};
  if (scene.render.pixel_filter.type != FilterType::box) pc.filter.emplace(scene.render.pixel_filter);
  return pc;
}

// Rows of a camera packet: its 16 rays are 4 x 4 pixels (a square's rays
// diverge less than a row's, so the packet meets fewer nodes).
inline constexpr int kPacketRows = 4;

// The first pass over pixels [x0, x1) of rows [y0, y1) (at most kPacketRows
// of them). One center ray per pixel: the first hits of blocks of up to 4 x 4
// neighbouring pixels are traced as a packet (the same hits as ray by ray),
// then each pixel is shaded as usual.
void render_first_pass_rows(const PixelContext& pc, const Accelerator& accel, int y0, int y1, int x0, int x1,
                            TraceContext& ctx, Image& image, PassImages* passes) {
  const int spp = pc.scene.render.samples_per_pixel;
  if (spp != 1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) render_pixel_into(pc, x, y, spp, ctx, image, passes);
    return;
  }
  constexpr int kColumns = kPacketSize / kPacketRows;
  for (int bx = x0; bx < x1; bx += kColumns) {
    const int columns = std::min(kColumns, x1 - bx);
    int n = 0;
    PacketSlots<Ray> rays;
    int px[kPacketSize], py[kPacketSize];
    for (int y = y0; y < y1; ++y)
      for (int x = bx; x < bx + columns; ++x) {
        // Field by field: `rays[n] = center_ray(...)` went through a
        // temporary on the stack, stored in halves and loaded 64 bytes at
        // once, which stalls (store forwarding).
        const Ray ray = center_ray(pc, x, y);
        rays[n].origin = ray.origin;
        rays[n].direction = ray.direction;
        rays[n].t_min = ray.t_min;
        rays[n].t_max = ray.t_max;
        px[n] = x;
        py[n++] = y;
      }
    PacketHits<> hits(n);
    accel.intersect_packet(rays.data(), n, hits.data());
    if ((!passes || passes->empty()) && pc.integrator.shades_packets()) {
      // Shaded together (their shadow rays as packets); each pixel stored
      // as render_pixel_with stores it: the one sample's sum, divided by 1.
      PacketSlots<Color> colors;  // each set by cast_camera_packet
      pc.integrator.cast_camera_packet(rays.data(), hits.data(), n, ctx, colors.data());
      for (int i = 0; i < n; ++i) {
        ctx.stats.camera++;
        PixelSums sums;
        sums.color += 1.0 * colors[i];
        store(image, px[i], py[i], sums.color / 1.0);
      }
      continue;
    }
    for (int i = 0; i < n; ++i) render_pixel_into(pc, px[i], py[i], 1, ctx, image, passes, &hits[i]);
  }
}

}  // namespace

struct TileRenderer::Context {
  PixelContext pc;
};

TileRenderer::TileRenderer(const Integrator& integrator, const Scene& scene, const Accelerator& accel)
    : accel_(accel), context_(std::make_unique<Context>(Context{make_pixel_context(integrator, scene)})) {}

TileRenderer::~TileRenderer() = default;

void TileRenderer::render(int x0, int y0, int x1, int y1, TraceContext& ctx, Image& image) const {
  for (int y = y0; y < y1; y += kPacketRows)
    render_first_pass_rows(context_->pc, accel_, y, std::min(y + kPacketRows, y1), x0, x1, ctx, image, nullptr);
}

TileProgress::TileProgress(int width, int height, int tile)
    : tile_size(tile),
      tiles_x((width + tile - 1) / tile),
      tiles_y((height + tile - 1) / tile),
      done(static_cast<size_t>(tiles_x) * static_cast<size_t>(tiles_y), 0) {}

size_t TileProgress::count_done() const { return static_cast<size_t>(std::count(done.begin(), done.end(), stages)); }

Image render_image(const Scene& scene, const Accelerator& accel, const RenderOptions& options, RenderStats* stats) {
  Image image(scene.render.width, scene.render.height);
  TileProgress progress(scene.render.width, scene.render.height, std::max(1, options.tile_size));
  render_tiles(scene, accel, image, progress, options, stats);
  return image;
}

std::vector<uint8_t> find_pixels_to_refine(const Image& image, double threshold) {
  const int w = image.width, h = image.height;
  std::vector<uint8_t> refine(static_cast<size_t>(w) * static_cast<size_t>(h), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float* p = image.pixel(x, y);
      bool differs = false;
      for (int dy = -1; dy <= 1 && !differs; ++dy) {
        for (int dx = -1; dx <= 1 && !differs; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const float* q = image.pixel(nx, ny);
          for (int c = 0; c < 3; ++c)
            // Written so that NaN counts as different.
            if (!(std::abs(static_cast<double>(p[c]) - q[c]) <= threshold)) differs = true;
        }
      }
      refine[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] = differs;
    }
  }
  return refine;
}

namespace {

// Runs `render_tile(t, ctx)` for every tile index in `todo` on a pool of
// threads; the tile returns whether it finished (false: cancelled part-way).
// Reports progress as (already + finished) / all tiles.
template <class RenderTile>
void run_tiles(const std::vector<int>& todo, int threads, const RenderOptions& options, double already, double all,
               RayStats& total, RenderTile render_tile) {
  const int todo_count = static_cast<int>(todo.size());
  auto cancelled = [&] { return options.cancel && options.cancel->load(std::memory_order_relaxed); };
  std::atomic<int> next{0};
  std::atomic<int> finished{0};  // tiles taken off the list: rendered or abandoned
  std::mutex stats_mutex;
  std::condition_variable all_done;
  auto worker = [&] {
    TraceContext ctx{Rng(0), {}};
    for (int i = next++; i < todo_count; i = next++) {
      render_tile(todo[static_cast<size_t>(i)], ctx);
      if (++finished == todo_count) {
        std::lock_guard lock(stats_mutex);
        all_done.notify_all();
      }
    }
    std::lock_guard lock(stats_mutex);
    total += ctx.stats;
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(threads));
  for (int i = 0; i < threads; ++i) pool.emplace_back(worker);
  if (options.progress) {
    std::unique_lock lock(stats_mutex);
    while (!all_done.wait_for(lock, std::chrono::milliseconds(100),
                              [&] { return finished.load() == todo_count || cancelled(); })) {
      options.progress((already + finished.load()) / all);
    }
    lock.unlock();
  }
  for (std::thread& t : pool) t.join();
}

}  // namespace

bool render_tiles(const Scene& scene, const Accelerator& accel, Image& image, TileProgress& progress,
                  const RenderOptions& options, RenderStats* stats, PassImages* passes) {
  const auto start = std::chrono::steady_clock::now();
  const int w = scene.render.width, h = scene.render.height;
  const Integrator integrator(scene, accel);
  const PixelContext pc = make_pixel_context(integrator, scene);
  const std::optional<AdaptiveSampling>& adaptive = scene.render.adaptive;
  const uint8_t stages = adaptive ? 2 : 1;
  progress.stages = stages;
  auto cancelled = [&] { return options.cancel && options.cancel->load(std::memory_order_relaxed); };

  const int tile = progress.tile_size;
  auto tile_rect = [&](int t, int& x0, int& y0, int& x1, int& y1) {
    x0 = (t % progress.tiles_x) * tile;
    y0 = (t / progress.tiles_x) * tile;
    x1 = std::min(x0 + tile, w);
    y1 = std::min(y0 + tile, h);
  };
  // Tiles still at `stage` - 1 (stage 1: the first pass; 2: adaptive refinement).
  auto tiles_before = [&](uint8_t stage) {
    std::vector<int> todo;
    for (size_t t = 0; t < progress.done.size(); ++t)
      if (progress.done[t] == stage - 1) todo.push_back(static_cast<int>(t));
    return todo;
  };
  const double all = static_cast<double>(std::max<size_t>(1, progress.done.size() * stages));
  auto stages_done = [&] {
    double n = 0;
    for (uint8_t d : progress.done) n += d;
    return n;
  };
  int threads_used = 1;
  RayStats total;

  // For options.rows_final: the tiles of each band (a row of tiles) still
  // short of their last stage, and the bands from the top all final.
  std::mutex bands_mutex;
  std::vector<int> band_tiles_left(options.rows_final ? static_cast<size_t>(progress.tiles_y) : 0, 0);
  int bands_final = 0;
  auto announce_final_bands = [&] {  // under bands_mutex once the workers run
    const int before = bands_final;
    while (bands_final < progress.tiles_y && band_tiles_left[static_cast<size_t>(bands_final)] == 0) ++bands_final;
    if (bands_final > before) options.rows_final(std::min(h, bands_final * tile));
  };
  if (options.rows_final) {
    for (size_t t = 0; t < progress.done.size(); ++t)
      if (progress.done[t] < stages) ++band_tiles_left[t / static_cast<size_t>(progress.tiles_x)];
    announce_final_bands();
  }
  auto tile_final = [&](int t) {
    if (!options.rows_final) return;
    const std::lock_guard lock(bands_mutex);
    --band_tiles_left[static_cast<size_t>(t / progress.tiles_x)];
    announce_final_bands();
  };

  // Each stage renders whole rows of a tile, `rows` at a time, and checks
  // for a cancel between them; each worker writes only its own tiles' flags
  // and pixels.
  auto run_stage = [&](uint8_t stage, int rows, auto render_rows) {
    const std::vector<int> todo = tiles_before(stage);
    const int threads =
        std::max(1, std::min(resolve_thread_count(options.threads), std::max(1, static_cast<int>(todo.size()))));
    threads_used = std::max(threads_used, threads);
    run_tiles(todo, threads, options, stages_done(), all, total, [&](int t, TraceContext& ctx) {
      int x0, y0, x1, y1;
      tile_rect(t, x0, y0, x1, y1);
      bool complete = !cancelled();
      for (int y = y0; y < y1 && complete; y += rows) {
        const int y_end = std::min(y + rows, y1);
        render_rows(y, y_end, x0, x1, ctx);
        complete = !cancelled() || y_end == y1;
      }
      if (complete) {
        progress.done[static_cast<size_t>(t)] = stage;
        if (stage == stages) tile_final(t);
      }
    });
  };

  run_stage(1, kPacketRows, [&](int y0, int y1, int x0, int x1, TraceContext& ctx) {
    render_first_pass_rows(pc, accel, y0, y1, x0, x1, ctx, image, passes);
  });
  if (adaptive && !cancelled() &&
      std::all_of(progress.done.begin(), progress.done.end(), [](uint8_t d) { return d >= 1; })) {
    // Decided once, from the complete first pass (kept in resume files), so
    // the choice never depends on which tiles happened to be finished.
    if (progress.refine.empty()) progress.refine = find_pixels_to_refine(image, adaptive->threshold);
    const int more = adaptive->max_samples_per_pixel;
    run_stage(2, 1, [&](int y, int, int x0, int x1, TraceContext& ctx) {
      for (int x = x0; x < x1; ++x)
        if (progress.refine[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)])
          render_pixel_into(pc, x, y, more, ctx, image, passes);
    });
  }
  if (options.progress && !cancelled()) options.progress(1.0);

  if (stats) {
    stats->rays = total;
    stats->threads = threads_used;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats->refined_pixels = static_cast<size_t>(std::count(progress.refine.begin(), progress.refine.end(), uint8_t{1}));
  }
  return progress.complete();
}

void fill_unfinished_tiles(Image& image, const TileProgress& progress, const Color& background) {
  const int tile = progress.tile_size;
  for (size_t t = 0; t < progress.done.size(); ++t) {
    if (progress.done[t]) continue;
    const int x0 = static_cast<int>(t % progress.tiles_x) * tile, y0 = static_cast<int>(t / progress.tiles_x) * tile;
    for (int y = y0; y < std::min(y0 + tile, image.height); ++y)
      for (int x = x0; x < std::min(x0 + tile, image.width); ++x) {
        float* px = image.pixel(x, y);
        px[0] = static_cast<float>(background.x);
        px[1] = static_cast<float>(background.y);
        px[2] = static_cast<float>(background.z);
      }
  }
}

}  // namespace glint
