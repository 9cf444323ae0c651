// The public Renderer: a snapshot of a Scene with its accelerator, and the
// film loop, passes and explain behind plain types.
#include "glint/render.h"

#include <chrono>
#include <optional>

#include "glint/accel/accelerator.h"
#include "glint/api/scene_state.h"
#include "glint/image/image.h"
#include "glint/io/image_file.h"
#include "glint/io/scene_loader.h"
#include "glint/render/explain.h"
#include "glint/render/passes.h"
#include "glint/render/renderer.h"
#include "glint/scene/animation.h"
#include "glint/version.h"

namespace glint {
const char* version() { return GLINT_VERSION_STRING; }
}  // namespace glint

namespace glint::api {

namespace {

Image to_public(glint::Image&& image) { return {image.width, image.height, std::move(image.rgb)}; }

glint::Image to_internal(const Image& image) {
  if (image.width < 0 || image.height < 0 ||
      image.rgb.size() != 3 * static_cast<size_t>(image.width) * static_cast<size_t>(image.height))
    throw Error("image: rgb holds " + std::to_string(image.rgb.size()) + " floats, not 3 x " +
                std::to_string(image.width) + " x " + std::to_string(image.height));
  glint::Image out;
  out.width = image.width;
  out.height = image.height;
  out.rgb = image.rgb;
  return out;
}

}  // namespace

void write_image(const Image& image, const std::filesystem::path& path, const WriteOptions& options) {
  glint::WriteOptions o;
  o.exposure = options.exposure;
  o.tonemap = static_cast<glint::ToneMap>(options.tonemap);
  glint::write_image(to_internal(image), path, o);
}

std::vector<unsigned char> encode_image(const Image& image, std::string_view format, const WriteOptions& options,
                                        std::string_view pass) {
  std::string name = "x";
  if (format.empty() || format[0] != '.') name.push_back('.');
  name.append(format);
  const auto f = glint::image_format_for_path(name);
  if (!f) throw Error("unknown image format \"" + std::string(format) + "\"");
  glint::WriteOptions o;
  o.exposure = options.exposure;
  o.tonemap = static_cast<glint::ToneMap>(options.tonemap);
  glint::Image internal = to_internal(image);
  if (!pass.empty()) {
    const auto p = pass_from_name(pass);
    if (!p) throw Error("unknown pass \"" + std::string(pass) + "\"");
    if (glint::is_8bit_format(*f)) {
      // As the CLI writes a pass file (write_outputs, render/frame_job.cpp): data passes remapped, no curve.
      o.data = *p == Pass::normal || *p == Pass::depth;
      internal = pass_image_for_8bit(*p, internal);
    }
  }
  return glint::encode_image(internal, *f, o);
}

Image read_image(const std::filesystem::path& path) { return to_public(glint::read_image(path)); }

bool embree_available() { return glint::embree_available(); }

struct Renderer::State {
  Scene scene;  // as last given: what render() draws
  // The snapshot the accelerator was built on (it holds references into it);
  // its geometry equals that of `scene` (or of `posed`).
  std::shared_ptr<const glint::Scene> built_on;
  // An animated scene as last given, posed at the frame: what render() and
  // explain draw (camera, materials and lights of the latest edit).
  std::shared_ptr<const glint::Scene> posed;
  std::unique_ptr<Accelerator> accel;
  size_t geometry_key = 0;
  PrepareOptions options;
  double build_seconds = 0;
  int builds = 0;

  explicit State(const Scene& s, const PrepareOptions& o) : scene(s), options(o) { build(); }

  bool animated() const { return frame_count(*scene.state()->scene) > 1; }

  void build() {
    const auto start = std::chrono::steady_clock::now();
    AcceleratorOptions ao;
    ao.threads = options.threads;
    ao.backend = options.accel == Accel::embree ? AccelBackend::embree : AccelBackend::bvh;
    const int frames = frame_count(*scene.state()->scene);
    if (options.frame < 0 || options.frame >= frames)
      throw Error("frame " + std::to_string(options.frame) + " is not in the scene (it has " + std::to_string(frames) +
                  (frames == 1 ? " frame)" : " frames)"));
    // An animated scene is posed at the frame: camera and objects moved.
    if (frames > 1) pose();
    built_on = frames > 1 ? posed : scene.state()->scene;
    accel = build_accelerator(*built_on, ao);
    geometry_key = scene.geometry_key();
    build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++builds;
  }
  void pose() { posed = std::make_shared<const glint::Scene>(scene_at_frame(*scene.state()->scene, options.frame)); }
  // What render() and explain draw: the scene, or the posed frame of an
  // animated one.
  const glint::Scene& internal() const { return animated() ? *posed : *scene.state()->scene; }
};

Renderer::Renderer(const Scene& scene, const PrepareOptions& options)
    : state_(std::make_unique<State>(scene, options)) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::update(const Scene& scene) {
  state_->scene = scene;
  if (scene.geometry_key() != state_->geometry_key) {
    state_->build();
  } else if (state_->animated()) {
    // Same objects and animation: the frame's geometry is the one the
    // accelerator holds; only the camera, materials and lights are posed anew.
    state_->pose();
  }
}

const Scene& Renderer::scene() const { return state_->scene; }

RenderResult Renderer::render(const RenderOptions& options) const {
  // A preview size or sample count renders a copy of the description with
  // those settings over the same accelerator (its geometry is unchanged).
  std::optional<glint::Scene> preview;
  const bool resized = options.width > 0 && options.height > 0;
  if (resized || options.samples_per_pixel > 0) {
    preview = state_->internal();
    if (resized) {
      check_image_size(options.width, options.height, SourceLocation{"render options", 0, 0});
      preview->render.width = options.width;
      preview->render.height = options.height;
    }
    if (options.samples_per_pixel > 0) {
      if (options.samples_per_pixel > kMaxSamplesPerPixel)
        throw Error("samples_per_pixel: at most " + std::to_string(kMaxSamplesPerPixel));
      preview->render.samples_per_pixel = options.samples_per_pixel;
      preview->render.adaptive.reset();
    }
  }
  const glint::Scene& scene = preview ? *preview : state_->internal();
  const int w = scene.render.width, h = scene.render.height;
  std::vector<Pass> passes;
  for (const std::string& name : options.passes) {
    const auto pass = pass_from_name(name);
    if (!pass) throw Error("unknown pass \"" + name + "\"");
    passes.push_back(*pass);
  }
  PassImages pass_images(passes, w, h);
  glint::Image image(w, h);
  TileProgress progress(w, h, kTileSize);
  const bool region = options.x1 > options.x0 && options.y1 > options.y0;
  if (region) {
    if (options.x0 < 0 || options.y0 < 0 || options.x1 > w || options.y1 > h)
      throw Error("render region outside the " + std::to_string(w) + "x" + std::to_string(h) + " image");
    if (scene.render.adaptive) throw Error("a render region cannot use adaptive sampling (it needs the whole image)");
    for (size_t t = 0; t < progress.done.size(); ++t) {
      const int tx0 = static_cast<int>(t % progress.tiles_x) * kTileSize;
      const int ty0 = static_cast<int>(t / progress.tiles_x) * kTileSize;
      const bool inside =
          tx0 < options.x1 && tx0 + kTileSize > options.x0 && ty0 < options.y1 && ty0 + kTileSize > options.y0;
      if (!inside) progress.done[t] = 1;
    }
  }
  glint::RenderOptions ro;
  ro.threads = options.threads;
  ro.tile_size = kTileSize;
  ro.progress = options.progress;
  ro.cancel = options.cancel;
  glint::RenderStats stats;
  RenderResult result;
  // Once before any pixel, so a caller can cancel (or learn of a cancel, as
  // a binding checking for Ctrl-C does) even in a render too short for a tick.
  if (options.progress) options.progress(0.0);
  result.complete =
      render_tiles(scene, *state_->accel, image, progress, ro, &stats, passes.empty() ? nullptr : &pass_images);
  if (region) {
    // Pixels of edge tiles outside the region were rendered with their tile.
    auto clear_outside = [&](glint::Image& img) {
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (x < options.x0 || x >= options.x1 || y < options.y0 || y >= options.y1) {
            float* p = img.pixel(x, y);
            p[0] = p[1] = p[2] = 0;
          }
    };
    clear_outside(image);
    for (glint::Image& img : pass_images.images) clear_outside(img);
  }
  result.image = to_public(std::move(image));
  for (size_t i = 0; i < pass_images.passes.size(); ++i)
    result.passes.emplace(std::string(pass_name(pass_images.passes[i])), to_public(std::move(pass_images.images[i])));
  result.stats.camera_rays = stats.rays.camera;
  result.stats.shadow_rays = stats.rays.shadow;
  result.stats.reflection_rays = stats.rays.reflection;
  result.stats.refraction_rays = stats.rays.refraction;
  result.stats.render_seconds = stats.seconds;
  result.stats.threads = stats.threads;
  result.stats.build_seconds = state_->build_seconds;
  result.stats.builds = state_->builds;
  return result;
}

namespace {

// The scene at another size for a render or an explanation, as the CLI's
// --width / --height: the camera's aspect follows, an NFF view's fov_y too.
const glint::Scene& at_size(const glint::Scene& scene, int width, int height, std::optional<glint::Scene>& sized) {
  if (width <= 0 || height <= 0) return scene;
  check_image_size(width, height, SourceLocation{"render options", 0, 0});
  sized = scene;
  sized->render.width = width;
  sized->render.height = height;
  return *sized;
}

}  // namespace

std::string Renderer::explain_json(int x, int y, int width, int height) const {
  std::optional<glint::Scene> sized;
  const glint::Scene& scene = at_size(state_->internal(), width, height, sized);
  return explanation_json(scene, explain_pixel(scene, *state_->accel, x, y));
}

std::string Renderer::explain_text(int x, int y, int width, int height) const {
  std::optional<glint::Scene> sized;
  const glint::Scene& scene = at_size(state_->internal(), width, height, sized);
  return explanation_text(scene, explain_pixel(scene, *state_->accel, x, y));
}

RenderResult render(const Scene& scene, const RenderOptions& options) {
  PrepareOptions prepare;
  prepare.threads = options.threads;
  return Renderer(scene, prepare).render(options);
}

}  // namespace glint::api
