// The public render_frames: the frame loop of render/frame_job.h over a
// Scene's snapshot, with its key over the canonical JSON.
#include "glint/frames.h"

#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include "glint/api/scene_state.h"
#include "glint/error.h"
#include "glint/render/frame_job.h"
#include "glint/render/resume.h"
#include "glint/scene/animation.h"

namespace glint::api {

namespace {

// Every number as a double: 18 and 18.0 are one value to the loader.
void numbers_as_doubles(nlohmann::json& j) {
  if (j.is_number_integer()) j = j.get<double>();
  else if (j.is_structured())
    for (auto& child : j) numbers_as_doubles(child);
}

// The scene's description is its document: a Scene from a file, from text
// or built in code has one, and an edit changes it. Canonical: compact, keys
// sorted, numbers as doubles, so only a change of content changes the key.
uint64_t inputs_digest(const Scene& scene) {
  nlohmann::json canonical = nlohmann::json::parse(scene.to_json(-1));  // nlohmann::json sorts keys
  numbers_as_doubles(canonical);
  const std::string json = canonical.dump();
  return scene_inputs_digest(std::span(reinterpret_cast<const unsigned char*>(json.data()), json.size()),
                             *scene.state()->scene);
}

glint::FrameJob frame_job(const FramesOptions& o) {
  glint::FrameJob job;
  job.output.path = o.output.string();
  for (const std::string& name : o.passes) {
    const auto pass = pass_from_name(name);
    if (!pass) throw Error("unknown pass \"" + name + "\"");
    job.output.passes.push_back(*pass);
  }
  if (o.passes_layered && o.passes.empty()) job.output.passes = parse_pass_list("all");
  job.output.layered = o.passes_layered;
  job.output.light.exposure = o.write.exposure;
  job.output.light.tonemap = static_cast<glint::ToneMap>(o.write.tonemap);
  job.resume = o.resume;
  job.accel.threads = o.threads;
  job.accel.backend = o.accel == Accel::embree ? AccelBackend::embree : AccelBackend::bvh;
  job.render.threads = o.threads;
  job.render.progress = o.progress;
  job.render.cancel = o.cancel;
  return job;
}

RenderStats public_stats(const glint::FrameReport& r) {
  RenderStats s;
  s.camera_rays = r.stats.rays.camera;
  s.shadow_rays = r.stats.rays.shadow;
  s.reflection_rays = r.stats.rays.reflection;
  s.refraction_rays = r.stats.rays.refraction;
  s.build_seconds = r.build_seconds;
  s.render_seconds = r.stats.seconds;
  s.threads = r.stats.threads;
  s.builds = 1;
  return s;
}

}  // namespace

bool render_frames(const Scene& scene, const FramesOptions& options,
                   const std::function<void(const FrameReport&)>& on_frame) {
  const glint::Scene& internal = *scene.state()->scene;
  const glint::FrameJob job = frame_job(options);
  job.output.check();
  const std::string pattern = options.output.string();
  const std::vector<FrameOutput> plan =
      plan_frames(internal, pattern, options.frames.empty() ? std::nullopt : std::optional(options.frames));
  for (const FrameOutput& out : plan) check_output_path(out.path);  // before any frame is rendered
  FrameEvents events;
  events.skipped = [&](const FrameOutput& out) {
    if (!on_frame) return;
    FrameReport report;
    report.frame = out.frame;
    report.output = out.path;
    report.skipped = true;
    on_frame(report);
  };
  // As Renderer::render: 0 before any pixel, so a caller can cancel early.
  events.starting = [&](const FrameOutput&) {
    if (options.progress) options.progress(0.0);
  };
  events.finished = [&](const FrameOutput& out, const glint::FrameReport& r) {
    if (!on_frame) return;
    FrameReport report;
    report.frame = out.frame;
    report.output = out.path;
    report.resumed = r.resumed;
    report.complete = r.complete;
    report.tiles_done = r.tiles_done;
    report.tiles_total = r.tiles_total;
    report.stats = public_stats(r);
    on_frame(report);
  };
  return glint::render_frames(
      internal, [&] { return inputs_digest(scene); }, plan, options.skip_existing, job, events);
}

uint64_t resume_key(const Scene& scene, int frame) {
  const glint::Scene& internal = *scene.state()->scene;
  const int frames = frame_count(internal);
  if (frame < 0 || frame >= frames)
    throw Error("frame " + std::to_string(frame) + " is not in the scene (it has " + std::to_string(frames) +
                (frames == 1 ? " frame)" : " frames)"));
  return glint::resume_key(inputs_digest(scene), internal.render, frame);
}

std::filesystem::path resume_file_for(const std::filesystem::path& output) { return resume_path_for(output); }

}  // namespace glint::api
