// glint::api::Renderer: a Scene prepared for rendering (its acceleration
// structure built), and what a render gives back: the image, its passes and
// the statistics. Plain data only: no SIMD types, no third-party types, no
// layout that depends on compiler flags.
//
// Ownership: a Renderer keeps its own snapshot of the Scene it was given;
// the Scene may be edited or destroyed afterwards.
//
// Threads: render() and explain_*() are const and may run on several threads
// at once on one Renderer (each render uses its own worker threads too);
// update() must not run while another thread renders with the same Renderer.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "glint/scene.h"

namespace glint::api {

// Linear RGB floats, row 0 at the top: rgb[3 * (y * width + x) + c].
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

// How 8-bit outputs (.png .jpg .ppm) encode linear values; float outputs
// (.pfm .exr .hdr) always hold the exact values.
enum class ToneMap { clamp, reinhard, aces };
struct WriteOptions {
  double exposure = 0;  // EV: values are multiplied by 2^exposure first
  ToneMap tonemap = ToneMap::clamp;
};

// By the extension: .png .jpg .ppm .pfm .exr .hdr. Atomic: an existing file
// is replaced only by a complete new one. Throws glint::Error.
void write_image(const Image& image, const std::filesystem::path& path, const WriteOptions& options = {});
// The bytes write_image would write, in memory; the format by its extension
// ("png", ".png", "pfm", ...). For servers and pipes. With a pass name
// ("normal", "depth", ...), `image` is that pass and the bytes are those of
// the file `glint render --passes` writes for it (8-bit normals and depths
// are remapped as data, docs/cli.md). Throws glint::Error.
std::vector<unsigned char> encode_image(const Image& image, std::string_view format, const WriteOptions& options = {},
                                        std::string_view pass = {});
// Any of those formats, as linear floats (8-bit ones sRGB-decoded).
Image read_image(const std::filesystem::path& path);

enum class Accel { bvh, embree };
// True when this build of glint has the Embree backend.
bool embree_available();

struct PrepareOptions {
  int threads = 0;  // threads that build the acceleration structure; 0: all cores
  Accel accel = Accel::bvh;
  // An animated scene (its "animation") is rendered as it is at this frame,
  // as `glint render --frames N` renders it; a still scene has frame 0 only.
  // As for a still scene, update() rebuilds the acceleration structure only
  // when the objects or the animation change.
  int frame = 0;
};

struct RenderOptions {
  int threads = 0;  // 0: all cores; the image is bit-identical for any count
  // Passes to fill besides the image, by name: "ambient", "diffuse",
  // "specular", "reflection", "transmission", "normal", "depth", "albedo".
  std::vector<std::string> passes;
  // Only pixels [x0, x1) x [y0, y1) are rendered (the rest stay 0), when
  // x1 > x0 and y1 > y0; the pixels are those of the whole image.
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  // A preview at another size or sample count: when width and height are
  // > 0 the scene's view is rendered at width x height pixels instead
  // (the camera's aspect follows the new size); samples_per_pixel > 0
  // replaces the scene's (adaptive sampling is then off). Either copies the
  // scene's description for the render; the acceleration structure is kept.
  int width = 0, height = 0;
  int samples_per_pixel = 0;
  // Called on the calling thread with the fraction done: once with 0 before
  // any pixel, about ten times a second while rendering, and with 1 at the end
  // (unless cancelled).
  std::function<void(double)> progress;
  // When it becomes true the render stops within a row of pixels;
  // RenderResult::complete is then false.
  const std::atomic<bool>* cancel = nullptr;
};

struct RenderStats {
  uint64_t camera_rays = 0, shadow_rays = 0, reflection_rays = 0, refraction_rays = 0;
  double build_seconds = 0;   // acceleration structure, at the Renderer's last (re)build
  double render_seconds = 0;  // the pixel loop of this render
  int threads = 1;
  int builds = 0;  // acceleration structures this Renderer has built (edits of
                   // materials, lights, camera or settings do not add one)
};

struct RenderResult {
  Image image;
  std::map<std::string, Image> passes;  // by pass name; depth in all three channels
  RenderStats stats;
  bool complete = true;  // false when cancelled
};

class Renderer {
 public:
  explicit Renderer(const Scene& scene, const PrepareOptions& options = {});
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // Renders the scene as it is now: a new camera, materials, lights or
  // settings reuse the acceleration structure; new geometry rebuilds it.
  void update(const Scene& scene);
  const Scene& scene() const;

  RenderResult render(const RenderOptions& options = {}) const;

  // The ray tree behind pixel (x, y) at one sample through its center, as
  // `glint explain` prints it: JSON (docs/scene-format.md) or text. With
  // width and height > 0, pixel (x, y) of the view rendered at that size, as
  // `glint explain --width --height` (and RenderOptions::width, height).
  std::string explain_json(int x, int y, int width = 0, int height = 0) const;
  std::string explain_text(int x, int y, int width = 0, int height = 0) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// One call: load nothing, prepare, render, return.
RenderResult render(const Scene& scene, const RenderOptions& options = {});

}  // namespace glint::api
