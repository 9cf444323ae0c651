// glint: the command line. Parses options, then runs the library's pipeline
// load_scene -> build_accelerator -> render_image -> write_image, printing
// progress and statistics on stderr. All errors end as one `error:` line.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/image/image.h"
#include "glint/io/scene_loader.h"
#include "glint/render/renderer.h"

namespace {

struct RenderArgs {
  std::string scene_path, output_path;
  std::optional<int> width, height, spp, max_depth, threads;
  std::optional<std::string> shading_model;
  bool quiet = false;
};

std::string format_count(uint64_t n) {
  char buf[32];
  if (n >= 10'000'000) std::snprintf(buf, sizeof buf, "%.1fM", n / 1e6);
  else if (n >= 10'000) std::snprintf(buf, sizeof buf, "%.1fk", n / 1e3);
  else std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(n));
  return buf;
}

// A one-line bar redrawn in place; only when stderr is a terminal.
class ProgressBar {
 public:
  void update(double fraction) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int width = 30, filled = static_cast<int>(fraction * width);
    std::string bar(filled, '#');
    bar.resize(width, '.');
    char eta[32] = "";
    if (fraction > 0.02 && fraction < 1.0)
      std::snprintf(eta, sizeof eta, " ETA %.0fs", elapsed * (1.0 - fraction) / fraction);
    std::fprintf(stderr, "\r[%s] %3.0f%%%s   ", bar.c_str(), fraction * 100.0, eta);
    if (fraction >= 1.0) std::fprintf(stderr, "\r%*s\r", width + 24, "");
    std::fflush(stderr);
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

int run_render(const RenderArgs& args) {
  using namespace glint;
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path output(args.output_path);
  if (!image_format_for_path(output))
    throw Error(args.output_path + ": unsupported output format (supported: " +
                std::string(supported_image_extensions()) + ")");
  const std::filesystem::path out_dir = output.has_parent_path() ? output.parent_path() : ".";
  if (!std::filesystem::is_directory(out_dir))
    throw Error(args.output_path + ": output folder " + out_dir.string() + " does not exist");

  Scene scene = load_scene(args.scene_path);
  RenderSettings& r = scene.render;
  if (args.width) r.width = *args.width;
  if (args.height) r.height = *args.height;
  if (args.spp) r.samples_per_pixel = *args.spp;
  if (args.max_depth) r.max_depth = *args.max_depth;
  if (args.shading_model) r.shading_model = *args.shading_model == "phong" ? ShadingModel::phong : ShadingModel::blinn_phong;
  if (args.width || args.height) check_image_size(r.width, r.height, SourceLocation{});

  const auto accel = build_accelerator(scene, AcceleratorOptions{args.threads.value_or(0)});
  RenderOptions options;
  options.threads = args.threads.value_or(0);
  ProgressBar bar;
  if (!args.quiet && isatty(STDERR_FILENO)) options.progress = [&bar](double f) { bar.update(f); };
  RenderStats stats;
  const Image image = render_image(scene, *accel, options, &stats);
  write_image(image, output);

  if (!args.quiet) {
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const RayStats& rays = stats.rays;
    std::fprintf(stderr,
                 "glint: %s: %dx%d, %d spp, %d threads: render %.3f s (total %.3f s); rays: %s camera, "
                 "%s shadow, %s reflection, %s refraction; %.2f Mrays/s\n",
                 args.output_path.c_str(), r.width, r.height, r.samples_per_pixel, stats.threads,
                 stats.seconds, total, format_count(rays.camera).c_str(), format_count(rays.shadow).c_str(),
                 format_count(rays.reflection).c_str(), format_count(rays.refraction).c_str(),
                 stats.seconds > 0 ? rays.total() / stats.seconds / 1e6 : 0.0);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"glint: a Whitted-style ray tracer for the Phong and Blinn-Phong reflection models"};
  app.require_subcommand(1);
  RenderArgs args;
  CLI::App* render = app.add_subcommand("render", "render a scene file to an image");
  render->add_option("scene", args.scene_path, "scene file (JSON)")->required();
  render->add_option("-o,--output", args.output_path, "output image: .png .jpg .ppm .pfm .exr")->required();
  render->add_option("--width", args.width, "image width in pixels")->check(CLI::Range(1, 1 << 20));
  render->add_option("--height", args.height, "image height in pixels")->check(CLI::Range(1, 1 << 20));
  render->add_option("--spp", args.spp, "samples per pixel")->check(CLI::Range(1, glint::kMaxSamplesPerPixel));
  render->add_option("--max-depth", args.max_depth, "longest ray path (camera ray = 1)")
      ->check(CLI::Range(1, glint::kMaxDepthLimit));
  render->add_option("--shading-model", args.shading_model, "phong or blinn-phong")
      ->check(CLI::IsMember({"phong", "blinn-phong"}));
  render->add_option("--threads", args.threads, "worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  render->add_flag("-q,--quiet", args.quiet, "no progress bar and no statistics");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    if (what.empty()) what = e.get_name();
    std::fprintf(stderr, "error: %s\n", what.c_str());
    return 2;
  }

  try {
    if (render->parsed()) return run_render(args);
  } catch (const glint::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
