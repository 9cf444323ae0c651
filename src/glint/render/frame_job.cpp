#include "glint/render/frame_job.h"

#include <chrono>
#include <optional>
#include <system_error>
#include <utility>

#include "glint/error.h"
#include "glint/render/frames.h"
#include "glint/render/resume.h"
#include "glint/scene/animation.h"

namespace glint {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The EXR channel names of a pass: color-like passes R, G, B; the normal X, Y, Z;
// depth one channel Z.
void add_pass_channels(std::vector<ExrChannel>& channels, Pass pass, const Image& image) {
  const std::string layer(pass_name(pass));
  if (pass == Pass::depth) {
    channels.push_back({layer + ".Z", &image, 0});
    return;
  }
  const char* names = pass == Pass::normal ? "XYZ" : "RGB";
  for (int c = 0; c < 3; ++c) channels.push_back({layer + "." + names[c], &image, c});
}

// The images a frame starts from: a resume file's (checked against the
// frame's key, size and passes), or empty ones.
struct FrameStart {
  Image image;
  TileProgress tiles;
  PassImages passes;
  bool resumed = false;
};

FrameStart start_frame(const RenderSettings& r, const std::function<uint64_t()>& key, const FrameJob& job,
                       const std::filesystem::path& resume_path) {
  FrameStart start;
  if (job.resume) {
    if (auto state = read_resume_file(resume_path)) {
      if (state->key != key() || state->image.width != r.width || state->image.height != r.height)
        throw Error(resume_path.string() +
                    ": made for a different scene, different scene files (meshes, "
                    "textures) or different settings; delete it to render from the start");
      if (state->passes.passes != job.output.passes)
        throw Error(resume_path.string() +
                    ": made with other --passes; resume with the same passes, "
                    "or delete it to render from the start");
      start.image = std::move(state->image);
      start.tiles = std::move(state->progress);
      start.passes = std::move(state->passes);
      start.resumed = true;
      return start;
    }
  }
  start.image = Image(r.width, r.height);
  start.tiles = TileProgress(r.width, r.height, kTileSize);
  start.passes = PassImages(job.output.passes, r.width, r.height);
  return start;
}

// A cancelled frame: its finished tiles (the rest background, in the
// passes background in ambient and 0 elsewhere, as a missed pixel) written
// as the output, and what a resume needs to finish it bit-identically.
void write_partial(const FrameStart& f, const Color& background, uint64_t key, const OutputFiles& output,
                   const std::filesystem::path& resume_path) {
  write_resume_file(resume_path, ResumeState{key, f.tiles, f.image, f.passes});
  Image partial = f.image;
  fill_unfinished_tiles(partial, f.tiles, background);
  PassImages partial_passes = f.passes;
  for (size_t i = 0; i < f.passes.passes.size(); ++i)
    fill_unfinished_tiles(partial_passes.images[i], f.tiles,
                          f.passes.passes[i] == Pass::ambient ? background : Color(0.0));
  write_outputs(partial, partial_passes, output);
}

}  // namespace

std::vector<FrameOutput> plan_frames(const Scene& scene, const std::string& pattern,
                                     const std::optional<std::string>& range) {
  std::vector<int> frames;
  if (range) frames = parse_frame_range(*range, frame_count(scene));
  else
    for (int f = 0; f < frame_count(scene); ++f) frames.push_back(f);
  std::vector<FrameOutput> plan;
  for (int f : frames) plan.push_back({f, frame_output_path(pattern, f).value_or(pattern)});
  if (plan.size() > 1 && plan[0].path == pattern)
    throw Error(pattern + ": " + std::to_string(plan.size()) +
                " frames need a frame number in the output name, exactly one %d or %0Nd (e.g. out_%04d.png)");
  return plan;
}

bool frame_done(const std::filesystem::path& output) {
  std::error_code ec;
  return std::filesystem::exists(output, ec) && !std::filesystem::exists(resume_path_for(output), ec);
}

void check_output_path(const std::string& path) {
  const std::filesystem::path output(path);
  if (!image_format_for_path(output))
    throw Error(path + ": unsupported output format (supported: " + std::string(supported_image_extensions()) + ")");
  const std::filesystem::path out_dir = output.has_parent_path() ? output.parent_path() : ".";
  if (!std::filesystem::is_directory(out_dir))
    throw Error(path + ": output folder " + out_dir.string() + " does not exist");
}

void check_image_fits(const std::string& path, const RenderSettings& render) {
  const std::optional<ImageFormat> format = image_format_for_path(path);
  if (!format) return;  // check_output_path's error
  if (auto reason = image_size_limit_reason(*format, render.width, render.height))
    throw Error(path + ": cannot write: " + *reason);
}

void OutputFiles::check() const {
  if (layered && image_format_for_path(path) != ImageFormat::exr)
    throw Error(path + ": --passes-layered writes one multi-layer EXR: the output must be .exr");
}

void write_outputs(const Image& image, const PassImages& passes, const OutputFiles& output) {
  if (output.layered) {
    std::vector<ExrChannel> channels = {{"R", &image, 0}, {"G", &image, 1}, {"B", &image, 2}};
    for (size_t i = 0; i < passes.passes.size(); ++i) add_pass_channels(channels, passes.passes[i], passes.images[i]);
    write_exr_channels(channels, output.path);
    return;
  }
  const bool eight_bit = is_8bit_format(*image_format_for_path(output.path));
  for (size_t i = 0; i < passes.passes.size(); ++i) {
    const Pass pass = passes.passes[i];
    const std::string path = pass_file_name(output.path, pass);
    if (!eight_bit) {
      write_image(passes.images[i], path);
    } else {
      WriteOptions options = output.light;
      options.data = pass == Pass::normal || pass == Pass::depth;
      write_image(pass_image_for_8bit(pass, passes.images[i]), path, options);
    }
  }
  write_image(image, output.path, output.light);
}

FrameReport render_frame_to_files(const Scene& scene, const std::function<uint64_t()>& key, const FrameJob& job) {
  check_output_path(job.output.path);
  job.output.check();
  const RenderSettings& r = scene.render;
  check_image_fits(job.output.path, r);
  const std::filesystem::path resume_path = resume_path_for(job.output.path);
  FrameStart f = start_frame(r, key, job, resume_path);

  FrameReport report;
  report.resumed = f.resumed;
  report.pixels = static_cast<size_t>(r.width) * static_cast<size_t>(r.height);
  const auto build_start = Clock::now();
  const auto accel = build_accelerator(scene, job.accel);
  report.build_seconds = seconds_since(build_start);
  // A PNG alone is compressed while the render runs, band by band as the
  // tiles finish (a 1080p PNG's compression is a fifth of a small scene's
  // time); other outputs are written after it.
  std::optional<PngStream> png;
  RenderOptions render = job.render;
  if (image_format_for_path(job.output.path) == ImageFormat::png && f.passes.passes.empty()) {
    png.emplace(f.image, job.output.light);
    render.rows_final = [&png, caller = job.render.rows_final](int rows) {
      png->rows_final(rows);
      if (caller) caller(rows);
    };
  }
  report.complete = render_tiles(scene, *accel, f.image, f.tiles, render, &report.stats, &f.passes);
  report.tiles_done = f.tiles.count_done();
  report.tiles_total = f.tiles.done.size();
  if (!report.complete) {
    png.reset();
    write_partial(f, r.background, key(), job.output, resume_path);
    return report;
  }
  const auto write_start = Clock::now();
  report.png_streamed = png.has_value();
  if (png) png->write(job.output.path);  // what write_outputs writes for a PNG without passes
  else write_outputs(f.image, f.passes, job.output);
  report.write_seconds = seconds_since(write_start);
  std::error_code ignored;
  std::filesystem::remove(resume_path, ignored);  // finished: any resume file is stale
  return report;
}

bool render_frames(const Scene& scene, const std::function<uint64_t()>& inputs_digest,
                   const std::vector<FrameOutput>& plan, bool skip_existing, const FrameJob& job,
                   const FrameEvents& events) {
  const bool animated = scene.animation.frames > 0;
  std::optional<uint64_t> digest;
  auto inputs = [&] {
    if (!digest) digest = inputs_digest();
    return *digest;
  };
  for (const FrameOutput& out : plan) {
    if (skip_existing && frame_done(out.path)) {
      if (events.skipped) events.skipped(out);
      continue;
    }
    if (events.starting) events.starting(out);
    FrameJob frame_job = job;
    frame_job.output.path = out.path;
    FrameReport report;
    if (animated) {
      const Scene posed = scene_at_frame(scene, out.frame);
      report = render_frame_to_files(
          posed, [&] { return resume_key(inputs(), posed.render, out.frame); }, frame_job);
    } else {
      report = render_frame_to_files(
          scene, [&] { return resume_key(inputs(), scene.render, out.frame); }, frame_job);
    }
    if (events.finished) events.finished(out, report);
    if (!report.complete) return false;
  }
  return true;
}

}  // namespace glint
