// Rendering a scene into image files, frame by frame, as `glint render` does
// and an embedder may (glint/frames.h wraps it): which frames and each one's
// file (`--frames 3-7`, `out_%04d.png`), resuming from a resume file whose
// key covers every input, the passes beside the image, and on cancel the
// partial image (finished tiles, background elsewhere) with a resume file
// that finishes it bit-identically. Never prints: callers report, from the
// FrameReport each frame gives.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/io/image_file.h"
#include "glint/render/passes.h"
#include "glint/render/renderer.h"
#include "glint/scene/scene.h"

namespace glint {

// A frame to render and the file it goes to.
struct FrameOutput {
  int frame = 0;
  std::string path;
};

// The frames of `range` ("N" or "A-B"; every frame when empty) with each
// one's output: `pattern` with its one %d or %0Nd replaced by the frame
// number (docs/cli.md#animation), or `pattern` itself for a single frame.
// Throws glint::Error for a bad range or several frames with no number in
// the pattern.
std::vector<FrameOutput> plan_frames(const Scene& scene, const std::string& pattern,
                                     const std::optional<std::string>& range = std::nullopt);

// A frame is done when its image exists and no interrupted render left a
// resume file beside it (that image would be partial).
bool frame_done(const std::filesystem::path& output);

// Throws glint::Error unless `path` names a supported image format in a
// folder that exists.
void check_output_path(const std::string& path);

// Throws glint::Error("<path>: cannot write: ...") when `path`'s format
// cannot hold an image of the render's size (a JPEG is at most 65535 pixels
// a side): checked before a render, not after it.
void check_image_fits(const std::string& path, const RenderSettings& render);

// Where and how one frame's images are written.
struct OutputFiles {
  std::string path;          // the image; each pass beside it, OUT.<pass>.<ext>
  std::vector<Pass> passes;  // extra images to fill and write
  bool layered = false;      // the passes as layers of the one .exr image instead
  WriteOptions light;        // 8-bit outputs: exposure and tone map

  // Throws glint::Error when `layered` is asked of an output that is not .exr.
  void check() const;
};

// The image and its passes: each pass beside the output in its format, or
// (layered) all of them as channels of the one EXR output. Each file atomic.
void write_outputs(const Image& image, const PassImages& passes, const OutputFiles& output);

struct FrameJob {
  OutputFiles output;
  // Finish from the resume file beside the output when there is one (one
  // with another key, size or passes is refused); otherwise from the start.
  bool resume = false;
  AcceleratorOptions accel;
  RenderOptions render;  // threads, progress, cancel
};

struct FrameReport {
  bool complete = true;  // false: cancelled; the partial image and a resume file were written
  bool resumed = false;  // started from a resume file
  size_t tiles_done = 0, tiles_total = 0;
  size_t pixels = 0;  // width * height (adaptive sampling refines some of them)
  RenderStats stats;  // of this run (a resumed render counts only the tiles it rendered)
  double build_seconds = 0, write_seconds = 0;
  // The PNG was compressed band by band while the render ran (a PNG without
  // passes): write_seconds is then the file's write alone.
  bool png_streamed = false;
};

// Renders `scene` (one frame's, settings final) into job.output. `key()`
// gives resume_key(...) of the scene and frame: the resume file is read
// against it and written with it. It is asked only then (a digest of a mesh
// of a million triangles costs about 8 ms, which a render that neither
// resumes nor stops does not need). Throws glint::Error for a resume file made for other
// inputs, settings or passes ("delete it"), and for I/O problems. A complete
// render removes the resume file.
FrameReport render_frame_to_files(const Scene& scene, const std::function<uint64_t()>& key, const FrameJob& job);

// What render_frames tells its caller as it goes.
struct FrameEvents {
  std::function<void(const FrameOutput&)> skipped;                       // skip_existing: its output was done
  std::function<void(const FrameOutput&)> starting;                      // before its scene is posed and built
  std::function<void(const FrameOutput&, const FrameReport&)> finished;  // complete or not
};

// The frames of `plan` in order, each as render_frame_to_files renders it
// (job.output.path replaced by the frame's), an animated scene posed at each
// frame; with `skip_existing`, frames already done are skipped. Stops after a
// frame that did not complete (cancelled) and returns false; true when every
// frame is done. `inputs_digest()` gives scene_inputs_digest(...) of
// `scene`; asked at most once, when a frame's resume key is needed.
bool render_frames(const Scene& scene, const std::function<uint64_t()>& inputs_digest,
                   const std::vector<FrameOutput>& plan, bool skip_existing, const FrameJob& job,
                   const FrameEvents& events = {});

}  // namespace glint
