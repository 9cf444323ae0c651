// glint render: a scene to an image, or an animation's frames
// (docs/cli.md#render); under mpirun, distributed over the ranks
// (docs/distributed.md). The options become a FrameJob and the library
// renders the frames (render/frame_job.h: resume, partial images; under
// mpirun render/distributed_job.h); this file turns signals into its cancel
// flag, prints progress and statistics, and ends a failed MPI job.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/accel/huge_pages.h"
#include "glint/error.h"
#include "glint/image/image.h"
#include "glint/io/file_io.h"
#include "glint/io/image_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/frame_job.h"
#include "glint/render/frames.h"
#include "glint/render/passes.h"
#ifdef GLINT_HAVE_MPI
#include "glint/render/distributed_job.h"
#endif
#include "glint/render/renderer.h"
#include "glint/render/resume.h"
#include "glint/scene/animation.h"
#include "options.h"

namespace glint::cli {

namespace {

// Thrown (not a glint::Error) when a signal stopped the render.
struct Interrupted {
  std::string what;
};

struct RenderArgs {
  std::string scene_path, output_path;
  std::optional<int> width, height, spp, max_depth, threads;
  std::optional<std::string> shading_model;
  std::string accel = "bvh";
  bool quiet = false;
  bool resume = false;
  std::optional<std::string> passes;
  bool passes_layered = false;
  std::optional<double> exposure;
  std::optional<std::string> tonemap;
  std::optional<std::string> pixel_filter;
  std::optional<int> adaptive_max_spp;
  std::optional<double> adaptive_threshold;
  std::optional<std::string> frames;  // "N" or "A-B"
  bool skip_existing = false;
  std::optional<double> rank_timeout;     // under MPI
  std::optional<std::string> stats_json;  // --stats-json FILE
};

AccelBackend backend_named(const std::string& name) {
  return name == "embree" ? AccelBackend::embree : AccelBackend::bvh;
}

// Set by SIGINT/SIGTERM: the render stops, writes what it has and a resume
// file. A second signal kills at once (SA_RESETHAND).
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_interrupt(int signal) {
  g_signal.store(signal);
  g_interrupted.store(true);
}

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

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

// The command line's settings over the scene's.
void apply_overrides(const RenderArgs& args, const Camera& camera, RenderSettings& r) {
  if (args.width) r.width = image_width(camera, *args.width);
  if (args.height) r.height = *args.height;
  if (args.spp) r.samples_per_pixel = *args.spp;
  if (args.max_depth) r.max_depth = *args.max_depth;
  if (args.shading_model)
    r.shading_model = *args.shading_model == "phong" ? ShadingModel::phong : ShadingModel::blinn_phong;
  if (args.width || args.height) check_image_size(r.width, r.height, SourceLocation{});
  if (args.pixel_filter) {
    // A named filter with its default parameters, replacing the scene's.
    r.pixel_filter = PixelFilter{};
    if (*args.pixel_filter == "gaussian") r.pixel_filter = {FilterType::gaussian, kGaussianRadius};
    if (*args.pixel_filter == "mitchell") r.pixel_filter = {FilterType::mitchell, kMitchellRadius};
  }
  if (args.adaptive_max_spp || args.adaptive_threshold) {
    AdaptiveSampling a = r.adaptive.value_or(AdaptiveSampling{});
    if (args.adaptive_max_spp) a.max_samples_per_pixel = *args.adaptive_max_spp;
    if (args.adaptive_threshold) a.threshold = *args.adaptive_threshold;
    r.adaptive = a;
  }
  if (r.adaptive && r.adaptive->max_samples_per_pixel < r.samples_per_pixel)
    throw Error("adaptive sampling: the most samples per pixel (" + std::to_string(r.adaptive->max_samples_per_pixel) +
                ") is below samples_per_pixel (" + std::to_string(r.samples_per_pixel) + ")");
}

// How 8-bit outputs encode the image and its color passes.
WriteOptions light_options(const RenderArgs& args) {
  WriteOptions light;
  if (args.exposure) light.exposure = *args.exposure;
  if (args.tonemap)
    light.tonemap = *args.tonemap == "reinhard" ? ToneMap::reinhard
                    : *args.tonemap == "aces"   ? ToneMap::aces
                                                : ToneMap::clamp;
  return light;
}

// The files of a frame as the options ask (--passes, --passes-layered,
// --exposure, --tonemap); the path is each frame's. Checked against the output.
OutputFiles output_files(const RenderArgs& args) {
  OutputFiles out;
  out.path = args.output_path;
  if (args.passes) out.passes = parse_pass_list(*args.passes);
  out.layered = args.passes_layered;
  if (args.passes_layered && !args.passes) out.passes = parse_pass_list("all");
  out.light = light_options(args);
  out.check();
  return out;
}

// One frame's render as the options ask; stopped by SIGINT and SIGTERM.
FrameJob frame_job(const RenderArgs& args) {
  FrameJob job;
  job.output = output_files(args);
  job.resume = args.resume;
  job.accel = AcceleratorOptions{args.threads.value_or(0), backend_named(args.accel)};
  job.render.threads = args.threads.value_or(0);
  job.render.cancel = &g_interrupted;
  return job;
}

// How long each phase of one render took, in seconds.
struct PhaseSeconds {
  double load = 0, build = 0, render = 0, write = 0, total = 0;
};

// --stats-json: the ray counts the SPD tables use and the phase times, as one
// JSON object (docs/nff.md).
void write_stats_json(const std::string& path, const RenderArgs& args, const std::string& output,
                      const RenderSettings& r, const RenderStats& stats, const PhaseSeconds& t) {
  using Json = nlohmann::ordered_json;
  const RayStats& rays = stats.rays;
  const Json doc = {
      {"scene", args.scene_path},
      {"output", output},
      {"width", r.width},
      {"height", r.height},
      {"samples_per_pixel", r.samples_per_pixel},
      {"max_depth", r.max_depth},
      {"threads", stats.threads},
      {"accel", args.accel},
      {"rays",
       {{"camera", rays.camera},
        {"camera_hits", rays.camera_hits},
        {"reflection", rays.reflection},
        {"refraction", rays.refraction},
        {"shadow", rays.shadow},
        {"total", rays.total()}}},
      {"seconds", {{"load", t.load}, {"build", t.build}, {"render", t.render}, {"write", t.write}, {"total", t.total}}},
  };
  const std::string text = doc.dump(2) + "\n";
  write_file_atomically(path, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()), Flush::no);
}

// The statistics line of a finished frame (and adaptive sampling's).
void print_frame_stats(const RenderArgs& args, const std::string& output, const RenderSettings& r,
                       const FrameReport& report, const PhaseSeconds& t) {
  const RenderStats& stats = report.stats;
  const RayStats& rays = stats.rays;
  std::fprintf(stderr,
               "glint: %s: %dx%d, %d spp, %d thread%s, %s: render %.3f s (total %.3f s: load %.3f, build %.3f, "
               "write %.3f); rays: %s camera, %s shadow, %s reflection, %s refraction; %s camera rays hit; "
               "%.2f Mrays/s\n",
               output.c_str(), r.width, r.height, r.samples_per_pixel, stats.threads, stats.threads == 1 ? "" : "s",
               args.accel.c_str(), t.render, t.total, t.load, t.build, t.write, format_count(rays.camera).c_str(),
               format_count(rays.shadow).c_str(), format_count(rays.reflection).c_str(),
               format_count(rays.refraction).c_str(), format_count(rays.camera_hits).c_str(),
               stats.seconds > 0 ? rays.total() / stats.seconds / 1e6 : 0.0);
  if (r.adaptive)
    std::fprintf(stderr, "glint: adaptive: %zu of %zu pixels (%.1f%%) rendered again at %d spp\n", stats.refined_pixels,
                 report.pixels,
                 report.pixels == 0 ? 0.0 : 100.0 * static_cast<double>(stats.refined_pixels) / report.pixels,
                 r.adaptive->max_samples_per_pixel);
}

std::string interrupted_message(const std::string& output, const FrameReport& report) {
  return "interrupted: " + std::to_string(report.tiles_done) + " of " + std::to_string(report.tiles_total) +
         " tiles in " + output + "; finish with the same command and --resume";
}

// Before the (possibly long) load: the output's format and folder, the
// passes and the --stats-json folder do not depend on the frame number.
void check_before_load(const RenderArgs& args) {
  check_output_path(frame_output_path(args.output_path, 0).value_or(args.output_path));
  if (args.stats_json) {
    const std::filesystem::path stats(*args.stats_json);
    const std::filesystem::path dir = stats.has_parent_path() ? stats.parent_path() : ".";
    if (!std::filesystem::is_directory(dir))
      throw Error(*args.stats_json + ": --stats-json folder " + dir.string() + " does not exist");
  }
  output_files(args);
}

// The scene, its warnings printed, and the scene file's bytes: with
// everything the scene loaded from other files, they make the digest of its
// inputs for resume keys (taken only when a resume file is read or written).
Scene load_for_render(const RenderArgs& args, std::vector<unsigned char>& description) {
  Scene scene = load_scene(args.scene_path);
  if (!args.quiet) {
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const std::string first_output = frame_output_path(args.output_path, 0).value_or(args.output_path);
    if (!is_8bit_format(*image_format_for_path(first_output)) && (args.exposure || args.tonemap))
      std::fprintf(stderr,
                   "warning: %s holds linear values: --exposure and --tonemap apply to 8-bit outputs "
                   "(.png .jpg .ppm) only and are ignored\n",
                   args.output_path.c_str());
  }
  description = read_file(args.scene_path);
  return scene;
}

int run_render_local(const RenderArgs& args) {
  using Clock = std::chrono::steady_clock;
  auto start = Clock::now();  // of the frame, for its "total": the program's start for the first
  // From the start: a signal while the scene loads stops the render before
  // its first tile (and still leaves a resume file), rather than killing glint.
  install_interrupt_handlers();
  check_before_load(args);
  // From the load through every frame's build: the mesh file's bytes, freed
  // after parsing, serve the build's first big buffer (accel/huge_pages.h).
  const BufferRecycling recycling;
  std::vector<unsigned char> description;
  Scene scene = load_for_render(args, description);
  const std::vector<FrameOutput> plan = plan_frames(scene, args.output_path, args.frames);
  apply_overrides(args, scene.camera, scene.render);
  if (args.stats_json && plan.size() > 1)
    throw Error("--stats-json describes one image: render one frame at a time (--frames N) to get each one's");

  FrameJob job = frame_job(args);
  std::optional<ProgressBar> bar;
  if (!args.quiet && isatty(STDERR_FILENO)) job.render.progress = [&bar](double f) { bar->update(f); };
  FrameEvents events;
  events.skipped = [&](const FrameOutput& out) {
    if (!args.quiet) std::fprintf(stderr, "glint: %s exists: skipped\n", out.path.c_str());
  };
  events.starting = [&](const FrameOutput& out) {
    bar.emplace();
    if (args.resume && !args.quiet && !std::filesystem::exists(resume_path_for(out.path)))
      std::fprintf(stderr, "glint: no resume file %s: rendering from the start\n", resume_path_for(out.path).c_str());
  };
  std::string interrupted;
  events.finished = [&](const FrameOutput& out, const FrameReport& report) {
    const double total = std::chrono::duration<double>(Clock::now() - start).count();
    start = Clock::now();
    if (!report.complete) {
      if (job.render.progress) std::fprintf(stderr, "\n");
      interrupted = interrupted_message(out.path, report);
      return;
    }
    // "load": the rest of the total (reading the scene and its meshes; for
    // later animation frames, moving the scene to the frame).
    const PhaseSeconds t{total - report.build_seconds - report.stats.seconds - report.write_seconds,
                         report.build_seconds, report.stats.seconds, report.write_seconds, total};
    if (args.stats_json) write_stats_json(*args.stats_json, args, out.path, scene.render, report.stats, t);
    if (!args.quiet) print_frame_stats(args, out.path, scene.render, report, t);
  };
  const auto digest = [&] { return scene_inputs_digest(description, scene); };
  if (!render_frames(scene, digest, plan, args.skip_existing, job, events)) throw Interrupted{interrupted};
  return 0;
}

#ifdef GLINT_HAVE_MPI
int run_render_mpi(const RenderArgs& args);
#endif

int run_render(const RenderArgs& args) {
#ifdef GLINT_HAVE_MPI
  if (mpi::launched([](const char* name) { return std::getenv(name); })) return run_render_mpi(args);
#endif
  return run_render_local(args);
}

#ifdef GLINT_HAVE_MPI
// --- distributed: under mpirun / srun (GLINT_MPI) --------------------------
// The library runs the job (render/distributed_job.h); this prints what it
// reports, and ends the job when it fails on the way.

void print_distributed_stats(const std::string& output, const RenderSettings& r, const mpi::DistributedStats& stats,
                             int ranks, int threads, double total) {
  std::string split;
  for (size_t k = 0; k < stats.tiles_by_rank.size(); ++k) {
    if (k) split += '/';
    split += std::to_string(stats.tiles_by_rank[k]);
  }
  std::fprintf(stderr,
               "glint: %s: %dx%d, %d spp, %d ranks x %d thread%s: render %.3f s (total %.3f s); tiles by rank %s; "
               "%llu bytes sent (%llu of pixels); %.2f Mrays/s\n",
               output.c_str(), r.width, r.height, r.samples_per_pixel, ranks, threads, threads == 1 ? "" : "s",
               stats.seconds, total, split.c_str(), static_cast<unsigned long long>(stats.bytes_sent),
               static_cast<unsigned long long>(stats.pixel_bytes),
               stats.seconds > 0 ? stats.rays.total() / stats.seconds / 1e6 : 0.0);
  std::string cpu;
  for (size_t k = 0; k < stats.cpu_by_rank.size(); ++k) {
    char text[96];
    std::snprintf(text, sizeof text, "%srank %zu %.3f s (MPI thread %.3f s)", k ? ", " : "", k, stats.cpu_by_rank[k],
                  stats.main_cpu_by_rank[k]);
    cpu += text;
  }
  std::fprintf(stderr, "glint: CPU in the render: %s\n", cpu.c_str());
}

// What every rank prepares: the scene loaded by each rank itself.
mpi::Prepared prepare_on_rank(const RenderArgs& args) {
  if (args.stats_json) throw Error("--stats-json describes a single-process render: run it without mpirun");
  mpi::Prepared p;
  p.scene = load_scene(args.scene_path);
  p.inputs_digest = scene_inputs_digest(read_file(args.scene_path), p.scene);
  p.plan = plan_frames(p.scene, args.output_path, args.frames);
  apply_overrides(args, p.scene.camera, p.scene.render);
  for (const FrameOutput& out : p.plan) {
    check_output_path(out.path);
    check_image_fits(out.path, p.scene.render);  // a frame split in tiles over ranks is written after its render
  }
  p.job = frame_job(args);
  return p;
}

int run_render_distributed(const RenderArgs& args, const mpi::Session& session) {
  const auto start = std::chrono::steady_clock::now();  // of the command, for the tiles' "total"
  mpi::DistributedOptions options;
  options.skip_existing = args.skip_existing;
  options.rank_timeout = args.rank_timeout.value_or(mpi::kDefaultRankTimeout);
  options.faults = mpi::test_faults([](const char* name) { return std::getenv(name); });  // tests/mpi only
  mpi::DistributedEvents events;
  if (!args.quiet) {
    events.prepared = [](const Scene& scene) {
      for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    };
    events.skipped = [](const FrameOutput& out) {
      std::fprintf(stderr, "glint: %s exists: skipped\n", out.path.c_str());
    };
    events.frame_finished = [&](const FrameOutput& out, const RenderSettings& r, const FrameReport& report,
                                double total) {
      const PhaseSeconds t{total - report.build_seconds - report.stats.seconds - report.write_seconds,
                           report.build_seconds, report.stats.seconds, report.write_seconds, total};
      print_frame_stats(args, out.path, r, report, t);
    };
    events.tiles_finished = [&](const FrameOutput& out, const RenderSettings& r, const mpi::DistributedStats& stats,
                                int threads) {
      print_distributed_stats(out.path, r, stats, session.size, threads,
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    };
  }
  const mpi::DistributedOutcome outcome = mpi::render_distributed(
      session, [&] { return prepare_on_rank(args); }, options, events);
  if (outcome.done) return 0;
  if (!outcome.error.empty()) print_error(outcome.error);
  return 1;
}

int run_render_mpi(const RenderArgs& args) {
  // Outlives the catch below: its MPI_Finalize would wait for the ranks a
  // failed job leaves waiting.
  std::optional<mpi::Session> session;
  try {
    session.emplace();
    if (session->size == 1) return run_render_local(args);  // exactly the single-process render (resume and all)
    return run_render_distributed(args, *session);
  } catch (const mpi::JobFailure& e) {
    std::fprintf(stderr, "error: rank %d: %s\n", e.rank(), e.what());
    std::fflush(stderr);
    mpi::abort_job(1);  // every rank ends, this one included
    std::_Exit(1);      // should MPI_Abort return
  }
}
#endif

}  // namespace

Command add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* render = app.add_subcommand("render", "render a scene file to an image");
  render->add_option("scene", args->scene_path, "scene file (JSON or NFF)")->required();
  render->add_option("-o,--output", args->output_path, "output image: .png .jpg .ppm .pfm .exr .hdr")->required();
  render->add_option("--width", args->width, "image width in pixels")->check(whole_number_in(1, 1 << 20));
  render->add_option("--height", args->height, "image height in pixels")->check(whole_number_in(1, 1 << 20));
  render->add_option("--spp", args->spp, "samples per pixel")->check(whole_number_in(1, kMaxSamplesPerPixel));
  render->add_option("--max-depth", args->max_depth, "longest ray path (camera ray = 1)")
      ->check(whole_number_in(1, kMaxDepthLimit));
  render->add_option("--shading-model", args->shading_model, "phong or blinn-phong")
      ->check(one_of({"phong", "blinn-phong"}, "shading model"));
  render->add_option("--threads", args->threads, "worker threads (default: all cores)")
      ->check(whole_number_in(1, 1024));
  render->add_option("--accel", args->accel, "ray tracing kernel: bvh (ours, the default) or embree (Intel Embree)")
      ->check(one_of({"bvh", "embree"}, "accelerator"));
  render->add_flag("-q,--quiet", args->quiet, "no progress bar and no statistics");
  render->add_flag("--resume", args->resume, "finish an interrupted render from OUT.glint-resume");
  render->add_option("--frames", args->frames, "animation frames to render: N or A-B (default: all)");
  render->add_flag("--skip-existing", args->skip_existing,
                   "do not render frames whose output exists (and is complete)");
  render
      ->add_option("--rank-timeout", args->rank_timeout,
                   "under MPI: end the job when a rank holding work sends nothing for this many seconds "
                   "(a hung rank; default 60)")
      ->check(number_in(0.1, 1e6));
  render->add_option("--exposure", args->exposure, "8-bit outputs: multiply linear values by 2^EV first")
      ->check(number_in(-64, 64));
  render->add_option("--tonemap", args->tonemap, "8-bit outputs: clamp (default), reinhard or aces")
      ->check(one_of({"clamp", "reinhard", "aces"}, "tone map"));
  render->add_option("--pixel-filter", args->pixel_filter, "box (default), gaussian or mitchell")
      ->check(one_of({"box", "gaussian", "mitchell"}, "pixel filter"));
  render
      ->add_option("--adaptive-max-spp", args->adaptive_max_spp,
                   "adaptive sampling: re-render pixels that differ from a neighbour at this many samples")
      ->check(whole_number_in(1, kMaxSamplesPerPixel));
  render
      ->add_option("--adaptive-threshold", args->adaptive_threshold,
                   "adaptive sampling: largest neighbour difference (linear, any channel) left alone (default 0.05)")
      ->check(number_in(0, 1e30));
  render->add_option("--passes", args->passes,
                     "extra images beside the output (OUT.<pass>.<ext>): comma-separated ambient, diffuse, specular, "
                     "reflection, transmission, normal, depth, albedo, or all");
  render->add_flag("--passes-layered", args->passes_layered,
                   "write the passes as layers of the one .exr output instead (all passes unless --passes)");
  render->add_option("--stats-json", args->stats_json,
                     "also write the ray counts (camera, camera hits, shadow, reflection, refraction) and the time "
                     "of each phase to this JSON file");

  return {render, [args] {
            try {
              return run_render(*args);
            } catch (const Interrupted& e) {
              print_error(e.what);
              return 128 + g_signal.load();
            }
          }};
}

}  // namespace glint::cli
