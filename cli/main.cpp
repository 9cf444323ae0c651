// glint: the command line. Parses options, then runs the library's pipeline
// load_scene -> build_accelerator -> render_image -> write_image, printing
// progress and statistics on stderr. All errors end as one `error:` line.
#include <signal.h>
#include <unistd.h>

#include <atomic>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <nlohmann/json.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/image/image.h"
#include "glint/io/memory_limit.h"
#include "glint/io/nff_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/explain.h"
#include "glint/render/frames.h"
#include "glint/render/passes.h"
#ifdef GLINT_HAVE_MPI
#include "glint/render/distributed.h"
#endif
#include "glint/render/renderer.h"
#include "glint/render/resume.h"
#include "glint/util/strings.h"
#include "glint/io/file_io.h"
#include "glint/io/image_file.h"
#ifdef GLINT_HAVE_SERVE
#include "glint/serve/serve.h"
#endif

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
  std::optional<double> rank_timeout;  // under MPI
  std::optional<std::string> stats_json;  // --stats-json FILE
};

glint::AccelBackend backend_named(const std::string& name) {
  return name == "embree" ? glint::AccelBackend::embree : glint::AccelBackend::bvh;
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

// Prints `error: <what>` as exactly one line, whatever `what` holds (a file
// name from the command line may contain a line break).
void print_error(const std::string& what) {
  std::string line;
  for (char c : what) {
    if (c == '\n') line += "\\n";
    else if (c == '\r') line += "\\r";
    else line += c;
  }
  std::fprintf(stderr, "error: %s\n", line.c_str());
}

// A whole number in [lo, hi]; CLI11's Range alone calls "abc" out of range.
CLI::Validator whole_number_in(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        long long value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec == std::errc::invalid_argument || ptr != end)
          return "expected a whole number, got \"" + text + "\"";
        if (ec == std::errc::result_out_of_range || value < lo || value > hi)
          return "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + " (got " + text + ")";
        return {};
      },
      "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

// A finite number in [lo, hi] (CLI11's Range lets NaN through).
CLI::Validator number_in(double lo, double hi) {
  auto text_of = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  return CLI::Validator(
      [lo, hi, text_of](std::string& text) -> std::string {
        double value = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, value);
        if (text.empty() || ec == std::errc::invalid_argument || ptr != end || !std::isfinite(value))
          return "expected a number, got \"" + text + "\"";
        if (ec == std::errc::result_out_of_range || value < lo || value > hi)
          return "must be between " + text_of(lo) + " and " + text_of(hi) + " (got " + text + ")";
        return {};
      },
      "NUMBER in [" + text_of(lo) + ", " + text_of(hi) + "]");
}

// One of `names`, with a did-you-mean hint for near misses.
CLI::Validator one_of(std::vector<std::string_view> names, std::string what) {
  std::string list;
  for (std::string_view n : names) {
    if (!list.empty()) list += '|';
    list += n;
  }
  return CLI::Validator(
      [names, what](std::string& text) -> std::string {
        if (std::find(names.begin(), names.end(), text) != names.end()) return {};
        std::string msg = "unknown " + what + " \"" + text + "\"";
        const std::string hint = glint::closest_match(text, names);
        if (!hint.empty()) return msg + " (did you mean \"" + hint + "\"?)";
        msg += " (expected one of";
        for (size_t i = 0; i < names.size(); ++i) msg += (i ? ", \"" : " \"") + std::string(names[i]) + "\"";
        return msg + ")";
      },
      list);
}

struct ExplainArgs {
  std::string scene_path;
  std::vector<int> pixel;
  bool json = false;
  std::optional<int> width, height, max_depth;
  std::optional<std::string> shading_model;
  int frame = 0;  // of an animation
};

int run_explain(const ExplainArgs& args) {
  using namespace glint;
  const Scene loaded = load_scene(args.scene_path);
  if (args.frame >= frame_count(loaded))
    throw Error("--frame " + std::to_string(args.frame) + ": the scene has frames 0-" +
                std::to_string(frame_count(loaded) - 1));
  Scene scene = scene_at_frame(loaded, args.frame);
  RenderSettings& r = scene.render;
  if (args.width) r.width = *args.width;
  if (args.height) r.height = *args.height;
  if (args.max_depth) r.max_depth = *args.max_depth;
  if (args.shading_model) r.shading_model = *args.shading_model == "phong" ? ShadingModel::phong : ShadingModel::blinn_phong;
  r.samples_per_pixel = 1;  // explain follows the pixel's center ray
  r.adaptive.reset();       // (of a render at one sample per pixel, so never refined)
  const auto accel = build_accelerator(scene);  // render's default kernel: the numbers match its pixels
  const PixelExplanation e = explain_pixel(scene, *accel, args.pixel.at(0), args.pixel.at(1));
  const std::string text = args.json ? explanation_json(scene, e) : explanation_text(scene, e);
  std::fwrite(text.data(), 1, text.size(), stdout);
  return 0;
}

// An NFF scene as glint JSON (docs/nff.md): checked by loading it first, so a
// file written is one that loads; written atomically like every output.
int run_convert(const std::string& input, const std::string& output) {
  using namespace glint;
  if (!is_nff_path(input)) throw Error(input + ": convert reads NFF scenes (.nff)");
  std::string ext = std::filesystem::path(output).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".json") throw Error(output + ": convert writes glint JSON: the output must end in .json");
  const std::filesystem::path out(output);
  const std::filesystem::path out_dir = out.has_parent_path() ? out.parent_path() : ".";
  if (!std::filesystem::is_directory(out_dir))
    throw Error(output + ": output folder " + out_dir.string() + " does not exist");
  load_scene(input);  // every error the loader finds, at its NFF line
  const std::string text = nff_json_text(read_nff_file(input)).text;
  write_file_atomically(out, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
  return 0;
}

// Every error of the scene, one line each; exit 1 if there was any.
int run_validate(const std::string& scene_path, bool quiet) {
  const std::vector<glint::Error> errors = glint::validate_scene(scene_path);
  for (const glint::Error& e : errors) print_error(e.what());
  if (errors.empty() && !quiet) std::printf("%s: valid\n", scene_path.c_str());
  return errors.empty() ? 0 : 1;
}

double texture_bytes(const glint::Scene& scene) {
  double bytes = static_cast<double>(scene.textures.capacity() * sizeof(glint::Texture));
  for (const glint::TextureImage& image : scene.texture_images)
    bytes += static_cast<double>(image.texels.capacity() * sizeof(glint::Vec3f));
  return bytes;
}

// Each mesh file's arrays once, however many objects instance it.
double mesh_bytes(const glint::Scene& scene) {
  double bytes = static_cast<double>(scene.meshes.capacity() * sizeof(glint::Mesh));
  for (const glint::Mesh& m : scene.meshes)
    bytes += static_cast<double>(m.positions.capacity() * sizeof(glint::Vec3f) +
                                 m.indices.capacity() * sizeof(uint32_t) +
                                 m.corner_normals.capacity() * sizeof(glint::Vec3f) +
                                 m.triangle_material.capacity() * sizeof(uint32_t) +
                                 m.corner_uvs.capacity() * sizeof(glint::UVf));
  return bytes;
}

double polygon_bytes(const glint::Scene& scene) {
  double bytes = static_cast<double>(scene.polygons.capacity() * sizeof(glint::Polygon));
  for (const glint::Polygon& p : scene.polygons)
    bytes += static_cast<double>((p.vertices.capacity() + p.normals.capacity()) * sizeof(glint::Vec3) +
                                 p.triangles.capacity() * sizeof(p.triangles[0]));
  return bytes;
}

// What the scene holds and what rendering it will take in memory.
int run_info(const std::string& scene_path) {
  using namespace glint;
  const Scene scene = load_scene(scene_path);
  const auto accel = build_accelerator(scene);
  const RenderSettings& r = scene.render;
  size_t by_type[kShapeTypeCount] = {};
  Bounds3 bounds;
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    by_type[static_cast<int>(scene.objects[i].type)]++;
    if (scene.objects[i].type != ShapeType::plane) bounds.extend(object_bounds(scene, i));
  }
  size_t lights_by_type[5] = {0, 0, 0, 0, 0};
  for (const Light& l : scene.lights) lights_by_type[static_cast<int>(l.type)]++;
  const double scene_bytes = scene.objects.capacity() * sizeof(Object) + scene.spheres.capacity() * sizeof(Sphere) +
                             scene.planes.capacity() * sizeof(Plane) + scene.triangles.capacity() * sizeof(Triangle) +
                             scene.boxes.capacity() * sizeof(Box) + scene.transforms.capacity() * sizeof(Transform) +
                             scene.materials.capacity() * sizeof(Material) + scene.lights.capacity() * sizeof(Light) +
                             scene.cones.capacity() * sizeof(Cone) + scene.disks.capacity() * sizeof(Disk) +
                             polygon_bytes(scene) + mesh_bytes(scene) + texture_bytes(scene);
  size_t mesh_triangles = 0;  // of the mesh objects (an instance counts its mesh again)
  for (const Object& o : scene.objects)
    if (o.type == ShapeType::mesh) mesh_triangles += scene.meshes[o.shape].triangle_count();
  const double image_bytes = 12.0 * r.width * r.height;
  std::printf("scene      %s\n", scene_path.c_str());
  const char* filters[] = {"box", "gaussian", "mitchell"};
  std::string sampling = std::to_string(r.samples_per_pixel) + " spp";
  if (r.adaptive) sampling += " (adaptive up to " + std::to_string(r.adaptive->max_samples_per_pixel) + ")";
  std::printf("image      %dx%d, %s, %s filter, max depth %d, %s\n", r.width, r.height, sampling.c_str(),
              filters[static_cast<int>(r.pixel_filter.type)], r.max_depth,
              r.shading_model == ShadingModel::phong ? "phong" : "blinn-phong");
  const auto count = [&](ShapeType t) { return by_type[static_cast<int>(t)]; };
  std::printf("objects    %zu: %zu spheres, %zu planes, %zu triangles, %zu boxes, %zu meshes (%zu triangles), "
              "%zu cylinders, %zu cones, %zu disks, %zu polygons\n",
              scene.objects.size(), count(ShapeType::sphere), count(ShapeType::plane), count(ShapeType::triangle),
              count(ShapeType::box), count(ShapeType::mesh), mesh_triangles, count(ShapeType::cylinder),
              count(ShapeType::cone), count(ShapeType::disk), count(ShapeType::polygon));
  std::printf("lights     %zu: %zu ambient, %zu point, %zu directional, %zu spot, %zu area\n", scene.lights.size(),
              lights_by_type[0], lights_by_type[1], lights_by_type[2], lights_by_type[3], lights_by_type[4]);
  std::printf("materials  %zu (and the default)\n", scene.materials.size() - 1);
  if (!scene.textures.empty())
    std::printf("textures   %zu, %zu image files\n", scene.textures.size(), scene.texture_images.size());
  if (scene.animation.frames > 0)
    std::printf("animation  %d frames at %g fps, %zu animated object%s%s\n", scene.animation.frames,
                scene.animation.fps, scene.animation.objects.size(), scene.animation.objects.size() == 1 ? "" : "s",
                scene.animation.camera.position.empty() && scene.animation.camera.look_at.empty() &&
                        scene.animation.camera.up.empty() && scene.animation.camera.fov_y.empty()
                    ? ""
                    : ", animated camera");
  if (!bounds.empty())
    std::printf("bounds     (%g, %g, %g) to (%g, %g, %g), planes excluded\n", bounds.lo.x, bounds.lo.y, bounds.lo.z,
                bounds.hi.x, bounds.hi.y, bounds.hi.z);
  const double accel_bytes = static_cast<double>(accel->memory_bytes());
  std::printf("memory     scene %s + BVH %s + image %s = %s\n", format_bytes(scene_bytes).c_str(),
              format_bytes(accel_bytes).c_str(), format_bytes(image_bytes).c_str(),
              format_bytes(scene_bytes + accel_bytes + image_bytes).c_str());
  return 0;
}

// The EXR channel names of a pass: color-like passes R, G, B; the normal X, Y, Z;
// depth one channel Z.
void add_pass_channels(std::vector<glint::ExrChannel>& channels, glint::Pass pass, const glint::Image& image) {
  const std::string layer(glint::pass_name(pass));
  if (pass == glint::Pass::depth) {
    channels.push_back({layer + ".Z", &image, 0});
    return;
  }
  const char* names = pass == glint::Pass::normal ? "XYZ" : "RGB";
  for (int c = 0; c < 3; ++c) channels.push_back({layer + "." + names[c], &image, c});
}

// The main image and its passes: each pass beside the output in its format,
// or (layered) all of them as channels of the one EXR output.
void write_outputs(const glint::Image& image, const glint::PassImages& passes, const std::string& output,
                   bool layered, const glint::WriteOptions& light) {
  using namespace glint;
  if (layered) {
    std::vector<ExrChannel> channels = {{"R", &image, 0}, {"G", &image, 1}, {"B", &image, 2}};
    for (size_t i = 0; i < passes.passes.size(); ++i) add_pass_channels(channels, passes.passes[i], passes.images[i]);
    write_exr_channels(channels, output);
    return;
  }
  const bool eight_bit = is_8bit_format(*image_format_for_path(output));
  for (size_t i = 0; i < passes.passes.size(); ++i) {
    const Pass pass = passes.passes[i];
    const std::string path = pass_file_name(output, pass);
    if (!eight_bit) {
      write_image(passes.images[i], path);
    } else {
      WriteOptions options = light;
      options.data = pass == Pass::normal || pass == Pass::depth;
      write_image(pass_image_for_8bit(pass, passes.images[i]), path, options);
    }
  }
  write_image(image, output, light);
}

void check_output_path(const std::string& path) {
  using namespace glint;
  const std::filesystem::path output(path);
  if (!image_format_for_path(output))
    throw Error(path + ": unsupported output format (supported: " + std::string(supported_image_extensions()) + ")");
  const std::filesystem::path out_dir = output.has_parent_path() ? output.parent_path() : ".";
  if (!std::filesystem::is_directory(out_dir))
    throw Error(path + ": output folder " + out_dir.string() + " does not exist");
}

// The command line's settings over the scene's.
void apply_overrides(const RenderArgs& args, glint::RenderSettings& r) {
  using namespace glint;
  if (args.width) r.width = *args.width;
  if (args.height) r.height = *args.height;
  if (args.spp) r.samples_per_pixel = *args.spp;
  if (args.max_depth) r.max_depth = *args.max_depth;
  if (args.shading_model) r.shading_model = *args.shading_model == "phong" ? ShadingModel::phong : ShadingModel::blinn_phong;
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

// The passes asked for (--passes, --passes-layered), checked against the output.
std::vector<glint::Pass> requested_passes(const RenderArgs& args) {
  using namespace glint;
  std::vector<Pass> pass_list;
  if (args.passes) pass_list = parse_pass_list(*args.passes);
  if (args.passes_layered) {
    if (image_format_for_path(args.output_path) != ImageFormat::exr)
      throw Error(args.output_path + ": --passes-layered writes one multi-layer EXR: the output must be .exr");
    if (!args.passes) pass_list = parse_pass_list("all");
  }
  return pass_list;
}

// How 8-bit outputs encode the image and its color passes.
glint::WriteOptions light_options(const RenderArgs& args) {
  using namespace glint;
  WriteOptions light;
  if (args.exposure) light.exposure = *args.exposure;
  if (args.tonemap)
    light.tonemap = *args.tonemap == "reinhard" ? ToneMap::reinhard
                    : *args.tonemap == "aces"   ? ToneMap::aces
                                                : ToneMap::clamp;
  return light;
}

// How long each phase of one render took, in seconds.
struct PhaseSeconds {
  double load = 0, build = 0, render = 0, write = 0, total = 0;
};

// --stats-json: the ray counts the SPD tables use and the phase times, as one
// JSON object (docs/nff.md).
void write_stats_json(const std::string& path, const RenderArgs& args, const glint::RenderSettings& r,
                      const glint::RenderStats& stats, const PhaseSeconds& t) {
  using Json = nlohmann::ordered_json;
  const glint::RayStats& rays = stats.rays;
  const Json doc = {
      {"scene", args.scene_path},
      {"output", args.output_path},
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
  glint::write_file_atomically(path, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
}

// Renders one image: `scene` is the frame's scene, args.output_path its file;
// the stats line's total counts from `start`.
int render_frame(const RenderArgs& args, glint::Scene scene, int frame,
                 std::chrono::steady_clock::time_point start) {
  using namespace glint;
  const std::filesystem::path output(args.output_path);
  check_output_path(args.output_path);
  const std::vector<Pass> pass_list = requested_passes(args);
  const WriteOptions light = light_options(args);
  RenderSettings& r = scene.render;
  apply_overrides(args, r);

  // The resume key covers the scene file and the settings that shape pixels.
  const std::filesystem::path resume_path = resume_path_for(output);
  uint64_t key = resume_key(read_file(args.scene_path), r);
  if (scene.animation.frames > 0) key ^= 0x9e3779b97f4a7c15ULL * static_cast<uint64_t>(frame + 1);  // one per frame
  Image image;
  TileProgress tiles;
  PassImages passes;
  if (args.resume) {
    if (auto state = read_resume_file(resume_path)) {
      if (state->key != key || state->image.width != r.width || state->image.height != r.height)
        throw Error(resume_path.string() + ": made for a different scene or different settings; "
                    "delete it to render from the start");
      if (state->passes.passes != pass_list)
        throw Error(resume_path.string() + ": made with other --passes; resume with the same passes, "
                    "or delete it to render from the start");
      image = std::move(state->image);
      tiles = std::move(state->progress);
      passes = std::move(state->passes);
    } else if (!args.quiet) {
      std::fprintf(stderr, "glint: no resume file %s: rendering from the start\n", resume_path.c_str());
    }
  }
  if (tiles.done.empty()) {
    image = Image(r.width, r.height);
    tiles = TileProgress(r.width, r.height, kTileSize);
    passes = PassImages(pass_list, r.width, r.height);
  }

  using Clock = std::chrono::steady_clock;
  const auto build_start = Clock::now();
  const auto accel = build_accelerator(scene, AcceleratorOptions{args.threads.value_or(0), backend_named(args.accel)});
  const auto build_end = Clock::now();
  RenderOptions options;
  options.threads = args.threads.value_or(0);
  options.cancel = &g_interrupted;
  ProgressBar bar;
  if (!args.quiet && isatty(STDERR_FILENO)) options.progress = [&bar](double f) { bar.update(f); };
  RenderStats stats;
  install_interrupt_handlers();
  const bool complete = render_tiles(scene, *accel, image, tiles, options, &stats, &passes);
  if (!complete) {
    // Interrupted: keep the finished tiles (the rest is background) and what
    // --resume needs to finish the job bit-identically.
    write_resume_file(resume_path, ResumeState{key, tiles, image, passes});
    Image partial = image;
    fill_unfinished_tiles(partial, tiles, r.background);
    PassImages partial_passes = passes;
    for (size_t i = 0; i < passes.passes.size(); ++i)  // a missed pixel: background in ambient, 0 elsewhere
      fill_unfinished_tiles(partial_passes.images[i], tiles,
                            passes.passes[i] == Pass::ambient ? r.background : Color(0.0));
    write_outputs(partial, partial_passes, args.output_path, args.passes_layered, light);
    if (options.progress) std::fprintf(stderr, "\n");
    throw Interrupted{"interrupted: " + std::to_string(tiles.count_done()) + " of " +
                      std::to_string(tiles.done.size()) + " tiles in " + args.output_path +
                      "; finish with the same command and --resume"};
  }
  const auto write_start = Clock::now();
  write_outputs(image, passes, args.output_path, args.passes_layered, light);
  const auto write_end = Clock::now();
  std::error_code ignored;
  std::filesystem::remove(resume_path, ignored);  // finished: any resume file is stale

  auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  if (args.stats_json)
    write_stats_json(*args.stats_json, args, r, stats,
                     PhaseSeconds{seconds(start, build_start), seconds(build_start, build_end), stats.seconds,
                                  seconds(write_start, write_end), seconds(start, Clock::now())});
  if (!args.quiet) {
    const double total = seconds(start, Clock::now());
    const RayStats& rays = stats.rays;
    // "load": from the start to the accelerator build (reading the scene and
    // its meshes; for later animation frames, moving the scene to the frame).
    std::fprintf(stderr,
                 "glint: %s: %dx%d, %d spp, %d thread%s, %s: render %.3f s (total %.3f s: load %.3f, build %.3f, "
                 "write %.3f); rays: %s camera, %s shadow, %s reflection, %s refraction; %s camera rays hit; "
                 "%.2f Mrays/s\n",
                 args.output_path.c_str(), r.width, r.height, r.samples_per_pixel, stats.threads,
                 stats.threads == 1 ? "" : "s",
                 args.accel.c_str(),
                 stats.seconds, total, seconds(start, build_start), seconds(build_start, build_end),
                 seconds(write_start, write_end), format_count(rays.camera).c_str(), format_count(rays.shadow).c_str(),
                 format_count(rays.reflection).c_str(), format_count(rays.refraction).c_str(),
                 format_count(rays.camera_hits).c_str(),
                 stats.seconds > 0 ? rays.total() / stats.seconds / 1e6 : 0.0);
    if (r.adaptive)
      std::fprintf(stderr, "glint: adaptive: %zu of %zu pixels (%.1f%%) rendered again at %d spp\n",
                   stats.refined_pixels, tiles.refine.size(),
                   tiles.refine.empty() ? 0.0 : 100.0 * static_cast<double>(stats.refined_pixels) / tiles.refine.size(),
                   r.adaptive->max_samples_per_pixel);
  }
  return 0;
}

// --- frames: animations, --frames, --skip-existing ------------------------
// The frames to render and each one's output name; errors before any render.
std::vector<std::pair<int, std::string>> plan_frames(const RenderArgs& args, const glint::Scene& scene) {
  using namespace glint;
  std::vector<int> frames;
  if (args.frames) frames = parse_frame_range(*args.frames, frame_count(scene));
  else
    for (int f = 0; f < frame_count(scene); ++f) frames.push_back(f);
  std::vector<std::pair<int, std::string>> plan;
  for (int f : frames) plan.emplace_back(f, frame_output_path(args.output_path, f).value_or(args.output_path));
  if (plan.size() > 1 && plan[0].second == args.output_path)
    throw Error(args.output_path + ": " + std::to_string(plan.size()) +
                " frames need a frame number in the output name, exactly one %d or %0Nd (e.g. out_%04d.png)");
  return plan;
}

// A frame is done when its image exists and no interrupted render left a
// resume file beside it (that image would be partial).
bool frame_done(const std::string& output) {
  std::error_code ec;
  return std::filesystem::exists(output, ec) && !std::filesystem::exists(glint::resume_path_for(output), ec);
}

int run_render_local(const RenderArgs& args);
#ifdef GLINT_HAVE_MPI
int run_render_mpi(const RenderArgs& args);
#endif

int run_render(const RenderArgs& args) {
  using namespace glint;
#ifdef GLINT_HAVE_MPI
  if (glint::mpi::launched([](const char* name) { return std::getenv(name); })) return run_render_mpi(args);
#endif
  return run_render_local(args);
}

int run_render_local(const RenderArgs& args) {
  using namespace glint;
  auto start = std::chrono::steady_clock::now();
  // From the start: a signal while the scene loads stops the render before
  // its first tile (and still leaves a resume file), rather than killing glint.
  install_interrupt_handlers();
  // Before the (possibly long) load: the output's format and folder and the
  // passes do not depend on the frame number.
  const std::string first_output = frame_output_path(args.output_path, 0).value_or(args.output_path);
  check_output_path(first_output);
  if (args.stats_json) {
    const std::filesystem::path stats(*args.stats_json);
    const std::filesystem::path dir = stats.has_parent_path() ? stats.parent_path() : ".";
    if (!std::filesystem::is_directory(dir))
      throw Error(*args.stats_json + ": --stats-json folder " + dir.string() + " does not exist");
  }
  requested_passes(args);
  Scene scene = load_scene(args.scene_path);
  if (!args.quiet) {
    for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!is_8bit_format(*image_format_for_path(first_output)) && (args.exposure || args.tonemap))
      std::fprintf(stderr, "warning: %s holds linear values: --exposure and --tonemap apply to 8-bit outputs "
                   "(.png .jpg .ppm) only and are ignored\n", args.output_path.c_str());
  }
  const bool animated = scene.animation.frames > 0;
  const std::vector<std::pair<int, std::string>> plan = plan_frames(args, scene);
  if (args.stats_json && plan.size() > 1)
    throw Error("--stats-json describes one image: render one frame at a time (--frames N) to get each one's");
  for (const auto& [frame, output] : plan) {
    if (args.skip_existing && frame_done(output)) {
      if (!args.quiet) std::fprintf(stderr, "glint: %s exists: skipped\n", output.c_str());
      continue;
    }
    RenderArgs frame_args = args;
    frame_args.output_path = output;
    // A still scene has one frame: hand it over rather than copy it (meshes can be large).
    render_frame(frame_args, animated ? scene_at_frame(scene, frame) : std::move(scene), frame, start);
    start = std::chrono::steady_clock::now();
  }
  return 0;
}

#ifdef GLINT_HAVE_MPI
// --- distributed: under mpirun / srun (GLINT_MPI) --------------------------
// Every rank loads the scene itself; they agree it loaded everywhere before
// any work is handed out, so a bad scene ends every rank with no hang.
// More frames than ranks: whole frames go to ranks (each writes its own);
// otherwise each frame's tiles are spread over all ranks and rank 0 writes it.
int run_render_distributed(const RenderArgs& args, const glint::mpi::Session& session);

int run_render_mpi(const RenderArgs& args) {
  const glint::mpi::Session session;
  if (session.size == 1) {
    // One rank: exactly the single-process render (interrupt, resume and all).
    RenderArgs local = args;
    return run_render_local(local);
  }
  return run_render_distributed(args, session);
}

int run_render_distributed(const RenderArgs& args, const glint::mpi::Session& session) {
  using namespace glint;
  const auto start = std::chrono::steady_clock::now();
  std::optional<Scene> scene;
  std::vector<std::pair<int, std::string>> plan;
  std::string error;
  try {
    if (args.stats_json) throw Error("--stats-json describes a single-process render: run it without mpirun");
    scene = load_scene(args.scene_path);
    apply_overrides(args, scene->render);
    plan = plan_frames(args, *scene);
    for (const auto& [frame, output] : plan) check_output_path(output);
  } catch (const std::exception& e) {
    error = e.what();
  }
  const double rank_timeout = args.rank_timeout.value_or(mpi::kDefaultRankTimeout);
  const auto faults = mpi::test_faults([](const char* name) { return std::getenv(name); });  // tests/mpi only
  const std::vector<int> failed = mpi::failed_ranks(error.empty());
  if (!failed.empty()) {
    // Rank 0 speaks for all when it failed too (the same file, the same error).
    if (!error.empty() && (session.rank == 0 || failed.front() != 0))
      print_error(session.rank == 0 ? error : "rank " + std::to_string(session.rank) + ": " + error);
    return 1;
  }
  if (session.rank == 0 && !args.quiet)
    for (const std::string& w : scene->warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

  // Rank 0 alone decides which frames are missing, so ranks on file systems
  // that disagree cannot deadlock over different lists.
  std::vector<int> todo;
  if (session.rank == 0)
    for (size_t i = 0; i < plan.size(); ++i) {
      if (args.skip_existing && frame_done(plan[i].second)) {
        if (!args.quiet) std::fprintf(stderr, "glint: %s exists: skipped\n", plan[i].second.c_str());
        continue;
      }
      todo.push_back(static_cast<int>(i));
    }
  mpi::broadcast(todo);

  if (static_cast<int>(todo.size()) > session.size) {
    mpi::run_items(
        static_cast<int>(todo.size()),
        [&](int item) {
          const auto& [frame, output] = plan[todo[item]];
          RenderArgs frame_args = args;
          frame_args.output_path = output;
          try {
            render_frame(frame_args, scene_at_frame(*scene, frame), frame, std::chrono::steady_clock::now());
          } catch (const Interrupted& e) {
            throw Error(e.what);  // a signal (mpirun ending the job): the frame kept a resume file
          }
        },
        rank_timeout, [&](int item) { return std::to_string(plan[todo[item]].first); }, faults);
    return 0;
  }
  if (args.passes || args.passes_layered || scene->render.adaptive) {
    // Tiles of one image come from every rank as image pixels only.
    if (session.rank == 0) print_error("--passes and adaptive sampling work when frames go to ranks (more frames "
                                       "than ranks); for a frame split in tiles over ranks, render without them");
    return 1;
  }
  if (args.resume) {
    // Tiles of one image come from every rank: there is no one resume file.
    if (session.rank == 0) print_error("--resume works when frames go to ranks (more frames than ranks); "
                                       "for a frame split in tiles over ranks, render it again");
    return 1;
  }
  const int threads = resolve_thread_count(args.threads.value_or(0));
  for (int item : todo) {
    const auto& [frame, output] = plan[item];
    Scene moved;
    const Scene& frame_scene = scene->animation.frames > 0 ? (moved = scene_at_frame(*scene, frame)) : *scene;
    const auto accel = build_accelerator(frame_scene, AcceleratorOptions{threads, backend_named(args.accel)});
    mpi::DistributedStats stats;
    const Image image = mpi::render_image(frame_scene, *accel, threads, kTileSize, &stats, rank_timeout, faults);
    if (session.rank != 0) continue;
    write_image(image, output, light_options(args));
    if (args.quiet) continue;
    const RenderSettings& r = frame_scene.render;
    std::string split;
    for (size_t k = 0; k < stats.tiles_by_rank.size(); ++k) split += (k ? "/" : "") + std::to_string(stats.tiles_by_rank[k]);
    std::fprintf(stderr,
                 "glint: %s: %dx%d, %d spp, %d ranks x %d thread%s: render %.3f s (total %.3f s); tiles by rank %s; "
                 "%llu bytes sent (%llu of pixels); %.2f Mrays/s\n",
                 output.c_str(), r.width, r.height, r.samples_per_pixel, session.size, threads, threads == 1 ? "" : "s",
                 stats.seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                 split.c_str(), static_cast<unsigned long long>(stats.bytes_sent),
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
  return 0;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"glint: a Whitted-style ray tracer for the Phong and Blinn-Phong reflection models"};
  app.require_subcommand(1);
  RenderArgs args;
  CLI::App* render = app.add_subcommand("render", "render a scene file to an image");
  render->add_option("scene", args.scene_path, "scene file (JSON or NFF)")->required();
  render->add_option("-o,--output", args.output_path, "output image: .png .jpg .ppm .pfm .exr .hdr")->required();
  render->add_option("--width", args.width, "image width in pixels")->check(whole_number_in(1, 1 << 20));
  render->add_option("--height", args.height, "image height in pixels")->check(whole_number_in(1, 1 << 20));
  render->add_option("--spp", args.spp, "samples per pixel")->check(whole_number_in(1, glint::kMaxSamplesPerPixel));
  render->add_option("--max-depth", args.max_depth, "longest ray path (camera ray = 1)")
      ->check(whole_number_in(1, glint::kMaxDepthLimit));
  render->add_option("--shading-model", args.shading_model, "phong or blinn-phong")
      ->check(one_of({"phong", "blinn-phong"}, "shading model"));
  render->add_option("--threads", args.threads, "worker threads (default: all cores)")
      ->check(whole_number_in(1, 1024));
  render->add_option("--accel", args.accel, "ray tracing kernel: bvh (ours, the default) or embree (Intel Embree)")
      ->check(one_of({"bvh", "embree"}, "accelerator"));
  render->add_flag("-q,--quiet", args.quiet, "no progress bar and no statistics");
  render->add_flag("--resume", args.resume, "finish an interrupted render from OUT.glint-resume");
  render->add_option("--frames", args.frames, "animation frames to render: N or A-B (default: all)");
  render->add_flag("--skip-existing", args.skip_existing, "do not render frames whose output exists (and is complete)");
  render->add_option("--rank-timeout", args.rank_timeout,
                     "under MPI: end the job when a rank holding work sends nothing for this many seconds "
                     "(a hung rank; default 60)")
      ->check(number_in(0.1, 1e6));
  render->add_option("--exposure", args.exposure, "8-bit outputs: multiply linear values by 2^EV first")
      ->check(number_in(-64, 64));
  render->add_option("--tonemap", args.tonemap, "8-bit outputs: clamp (default), reinhard or aces")
      ->check(one_of({"clamp", "reinhard", "aces"}, "tone map"));
  render->add_option("--pixel-filter", args.pixel_filter, "box (default), gaussian or mitchell")
      ->check(one_of({"box", "gaussian", "mitchell"}, "pixel filter"));
  render->add_option("--adaptive-max-spp", args.adaptive_max_spp,
                     "adaptive sampling: re-render pixels that differ from a neighbour at this many samples")
      ->check(whole_number_in(1, glint::kMaxSamplesPerPixel));
  render->add_option("--adaptive-threshold", args.adaptive_threshold,
                     "adaptive sampling: largest neighbour difference (linear, any channel) left alone (default 0.05)")
      ->check(number_in(0, 1e30));
  render->add_option("--passes", args.passes,
                     "extra images beside the output (OUT.<pass>.<ext>): comma-separated ambient, diffuse, specular, "
                     "reflection, transmission, normal, depth, albedo, or all");
  render->add_flag("--passes-layered", args.passes_layered,
                   "write the passes as layers of the one .exr output instead (all passes unless --passes)");
  render->add_option("--stats-json", args.stats_json,
                     "also write the ray counts (camera, camera hits, shadow, reflection, refraction) and the time "
                     "of each phase to this JSON file");

  std::string convert_input, convert_output;
  CLI::App* convert = app.add_subcommand("convert", "convert an NFF scene to glint JSON");
  convert->add_option("scene", convert_input, "scene file (.nff)")->required();
  convert->add_option("-o,--output", convert_output, "output scene: .json")->required();

  std::string validate_path, info_path;
  bool validate_quiet = false;
  CLI::App* validate = app.add_subcommand("validate", "check a scene file without rendering; list every error");
  validate->add_option("scene", validate_path, "scene file (JSON or NFF)")->required();
  validate->add_flag("-q,--quiet", validate_quiet, "print nothing when the scene is valid");
  CLI::App* info = app.add_subcommand("info", "what a scene holds: counts, bounds, memory");
  info->add_option("scene", info_path, "scene file (JSON or NFF)")->required();

  ExplainArgs explain_args;
  CLI::App* explain = app.add_subcommand("explain", "explain one pixel: its whole ray tree, term by term");
  explain->add_option("scene", explain_args.scene_path, "scene file (JSON or NFF)")->required();
  explain->add_option("--pixel", explain_args.pixel, "pixel X Y (0 0 is the top-left)")->required()->expected(2);
  explain->add_flag("--json", explain_args.json, "print one JSON object (the format of docs/scene-format.md)");
  explain->add_option("--frame", explain_args.frame, "frame of an animated scene (default 0)")
      ->check(whole_number_in(0, glint::kMaxFrames - 1));
  explain->add_option("--width", explain_args.width, "image width in pixels")->check(whole_number_in(1, 1 << 20));
  explain->add_option("--height", explain_args.height, "image height in pixels")->check(whole_number_in(1, 1 << 20));
  explain->add_option("--max-depth", explain_args.max_depth, "longest ray path (camera ray = 1)")
      ->check(whole_number_in(1, glint::kMaxDepthLimit));
  explain->add_option("--shading-model", explain_args.shading_model, "phong or blinn-phong")
      ->check(one_of({"phong", "blinn-phong"}, "shading model"));

#ifdef GLINT_HAVE_SERVE
  glint::serve::ServeOptions serve_options;
  CLI::App* serve = app.add_subcommand("serve", "live preview in the browser: edit, render and explain (docs/preview.md)");
  serve->add_option("scene", serve_options.scene_path, "scene file (JSON)")->required();
  serve->add_option("--port", serve_options.port, "TCP port (0: any free port; the address is printed)")
      ->check(whole_number_in(0, 65535));
  serve->add_option("--host", serve_options.host, "address to listen on (default 127.0.0.1: this machine only)");
  serve->add_option("--threads", serve_options.threads, "render threads (default: all cores)")
      ->check(whole_number_in(1, 1024));
#endif

  // CLI11 words a missing or unknown command as "A subcommand is required": be precise.
  if (argc <= 1) {
    print_error("no command given (usage: glint render SCENE.json -o OUT.png; see glint --help)");
    return 2;
  }
  if (argv[1][0] != '-') {
    std::vector<std::string_view> commands;
    for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
      commands.push_back(sub->get_name());
    const std::string_view word = argv[1];
    if (std::find(commands.begin(), commands.end(), word) == commands.end()) {
      std::string msg = "unknown command \"" + std::string(word) + "\"";
      const std::string hint = glint::closest_match(word, commands);
      if (!hint.empty()) msg += " (did you mean \"" + hint + "\"?)";
      else {
        msg += " (expected";
        for (size_t i = 0; i < commands.size(); ++i) msg += (i ? ", \"" : " \"") + std::string(commands[i]) + "\"";
        msg += ")";
      }
      print_error(msg);
      return 2;
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    if (what.empty()) what = e.get_name();
    print_error(what);
    return 2;
  }

  try {
    if (render->parsed()) return run_render(args);
    if (explain->parsed()) return run_explain(explain_args);
    if (validate->parsed()) return run_validate(validate_path, validate_quiet);
    if (info->parsed()) return run_info(info_path);
    if (convert->parsed()) return run_convert(convert_input, convert_output);
#ifdef GLINT_HAVE_SERVE
    if (serve->parsed()) return glint::serve::run(serve_options);
#endif
  } catch (const Interrupted& e) {
    print_error(e.what);
    return 128 + g_signal.load();
  } catch (const glint::Error& e) {
    print_error(e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    print_error("out of memory");
    return 1;
  } catch (const std::exception& e) {
    print_error(e.what());
    return 1;
  }
  return 0;
}
