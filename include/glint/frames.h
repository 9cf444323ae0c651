// glint::api::render_frames: a scene into image files, as `glint render`
// writes them: every frame of an animation (or some) by an output pattern,
// passes beside the image, and renders that can be cancelled and resumed.
//
// Resume: a cancelled frame leaves its finished tiles in its output (the
// rest background) and `OUTPUT.glint-resume` beside it; rendering again with
// `resume` finishes only the missing tiles, bit-identical to an
// uninterrupted render. The resume file's key covers the scene's canonical
// JSON (its document, as to_json() gives it), what the scene loaded from
// every file it names (meshes with the .mtl and buffers they name, texture
// images), the render settings and the frame: after any edit that changes a
// pixel's inputs, a resume is refused with a glint::Error rather than
// finishing into a mixed image. The key is computed from the Scene as it was
// loaded, so load the scene again after editing one of its files.
//
// Threads: render_frames may run on several threads at once for different
// outputs; two calls must not write the same output.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "glint/render.h"
#include "glint/scene.h"

namespace glint::api {

struct FramesOptions {
  // The image file (.png .jpg .ppm .pfm .exr .hdr). For more than one frame
  // it holds the frame number as one %d or %0Nd: "out_%04d.png".
  std::filesystem::path output;
  std::string frames;          // "N" or "A-B" (inclusive); empty: every frame (a still scene has frame 0)
  bool skip_existing = false;  // skip frames whose output exists and has no resume file beside it
  bool resume = false;         // finish from each output's resume file where there is one
  // Passes written beside each image as OUTPUT.<pass>.<ext> ("diffuse",
  // "depth", ...), or with passes_layered as layers of the one .exr output.
  std::vector<std::string> passes;
  bool passes_layered = false;
  WriteOptions write;  // 8-bit outputs: exposure and tone map
  int threads = 0;     // 0: all cores
  Accel accel = Accel::bvh;
  // As RenderOptions: the fraction of the current frame done, on the calling thread.
  std::function<void(double)> progress;
  // When it becomes true the current frame stops within a row of pixels and
  // keeps its partial image and resume file; no further frame starts.
  const std::atomic<bool>* cancel = nullptr;
};

// One frame's outcome, given as each frame ends.
struct FrameReport {
  int frame = 0;
  std::filesystem::path output;
  bool skipped = false;  // skip_existing: it was already done
  bool resumed = false;  // finished from its resume file
  bool complete = true;  // false: cancelled (partial image and resume file written)
  size_t tiles_done = 0, tiles_total = 0;
  RenderStats stats;  // of this call's work on the frame
};

// Renders the frames of `options` into their files, in order, calling
// `on_frame` after each (skipped ones too). Returns true when every frame is
// complete, false when cancelled. Throws glint::Error for a bad output name,
// frame range or pass, a resume file made for other inputs or settings
// (delete it to start over), and I/O problems.
bool render_frames(const Scene& scene, const FramesOptions& options,
                   const std::function<void(const FrameReport&)>& on_frame = {});

// The key a resume file of `scene` at `frame` holds (see above).
uint64_t resume_key(const Scene& scene, int frame = 0);
// Where a render of `output` keeps its resume file: `OUTPUT.glint-resume`.
std::filesystem::path resume_file_for(const std::filesystem::path& output);

}  // namespace glint::api
