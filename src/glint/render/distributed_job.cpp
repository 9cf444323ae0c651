#include "glint/render/distributed_job.h"

#include <chrono>
#include <exception>
#include <optional>

#include "glint/accel/accelerator.h"
#include "glint/error.h"
#include "glint/io/image_file.h"
#include "glint/render/renderer.h"
#include "glint/scene/animation.h"

namespace glint::mpi {

namespace {

using Clock = std::chrono::steady_clock;

// Every rank's `prepare`, and whether it worked everywhere: the ranks load
// the scene at their own pace, and failed_ranks waits for the last.
std::optional<Prepared> prepare_everywhere(const Session& session, const std::function<Prepared()>& prepare,
                                           DistributedOutcome& outcome) {
  std::optional<Prepared> prepared;
  std::string error;
  try {
    prepared = prepare();
  } catch (const std::exception& e) {
    error = e.what();
  }
  const std::vector<int> failed = failed_ranks(error.empty());
  if (failed.empty()) return prepared;
  outcome.done = false;
  // Rank 0 speaks for all when it failed too (the same file, the same error).
  if (!error.empty() && (session.rank == 0 || failed.front() != 0))
    outcome.error = session.rank == 0 ? error : "rank " + std::to_string(session.rank) + ": " + error;
  return std::nullopt;
}

// The frames to render, as rank 0 alone decides them (skip_existing), so
// ranks on file systems that disagree cannot deadlock over different lists.
std::vector<FrameOutput> frames_to_do(const Session& session, const std::vector<FrameOutput>& plan,
                                      const DistributedOptions& options, const DistributedEvents& events) {
  std::vector<int> todo;
  if (session.rank == 0)
    for (size_t i = 0; i < plan.size(); ++i) {
      if (options.skip_existing && frame_done(plan[i].path)) {
        if (events.skipped) events.skipped(plan[i]);
        continue;
      }
      todo.push_back(static_cast<int>(i));
    }
  broadcast(todo);
  std::vector<FrameOutput> frames;
  for (int i : todo) frames.push_back(plan[i]);
  return frames;
}

// Whole frames to ranks: each rank renders its frames as a local render
// does. A failed job stops the frame in work, which keeps its partial image
// and a resume file, as an interrupted render does.
void render_frames_on_ranks(const Prepared& p, const std::vector<FrameOutput>& frames,
                            const DistributedOptions& options, const DistributedEvents& events) {
  run_items(
      static_cast<int>(frames.size()),
      [&](int item, const std::atomic<bool>& stop) {
        const auto start = Clock::now();
        FrameJob job = p.job;
        job.render.progress = nullptr;
        job.render.cancel = &stop;
        FrameEvents frame_events;
        frame_events.finished = [&](const FrameOutput& out, const FrameReport& report) {
          if (!report.complete || !events.frame_finished) return;
          events.frame_finished(out, p.scene.render, report,
                                std::chrono::duration<double>(Clock::now() - start).count());
        };
        if (!render_frames(p.scene, [&] { return p.inputs_digest; }, {frames[item]}, false, job, frame_events))
          throw Error(frames[item].path + ": stopped, as the job failed; it keeps a resume file");
      },
      options.rank_timeout, [&](int item) { return std::to_string(frames[item].frame); }, options.faults);
}

// Each frame's tiles over all ranks; rank 0 writes the image. Passes,
// adaptive sampling and resume need one process to hold the whole frame.
DistributedOutcome render_tiles_on_ranks(const Session& session, const Prepared& p,
                                         const std::vector<FrameOutput>& frames, const DistributedOptions& options,
                                         const DistributedEvents& events) {
  const FrameJob& job = p.job;
  DistributedOutcome refused{false, {}};
  if (!job.output.passes.empty() || job.output.layered || p.scene.render.adaptive) {
    // Tiles of one image come from every rank as image pixels only.
    if (session.rank == 0)
      refused.error =
          "--passes and adaptive sampling work when frames go to ranks (more frames "
          "than ranks); for a frame split in tiles over ranks, render without them";
    return refused;
  }
  if (job.resume) {
    // Tiles of one image come from every rank: there is no one resume file.
    if (session.rank == 0)
      refused.error =
          "--resume works when frames go to ranks (more frames than ranks); "
          "for a frame split in tiles over ranks, render it again";
    return refused;
  }
  const int threads = resolve_thread_count(job.render.threads);
  AcceleratorOptions accel_options = job.accel;
  accel_options.threads = threads;
  for (const FrameOutput& out : frames) {
    Scene posed;
    const Scene& frame_scene = p.scene.animation.frames > 0 ? (posed = scene_at_frame(p.scene, out.frame)) : p.scene;
    const auto accel = build_accelerator(frame_scene, accel_options);
    DistributedStats stats;
    const Image image =
        render_image(frame_scene, *accel, threads, job.render.tile_size, &stats, options.rank_timeout, options.faults);
    if (session.rank != 0) continue;
    write_image(image, out.path, job.output.light);
    if (events.tiles_finished) events.tiles_finished(out, frame_scene.render, stats, threads);
  }
  return {};
}

}  // namespace

DistributedOutcome render_distributed(const Session& session, const std::function<Prepared()>& prepare,
                                      const DistributedOptions& options, const DistributedEvents& events) {
  DistributedOutcome outcome;
  const std::optional<Prepared> prepared = prepare_everywhere(session, prepare, outcome);
  if (!prepared) return outcome;
  if (session.rank == 0 && events.prepared) events.prepared(prepared->scene);
  const std::vector<FrameOutput> frames = frames_to_do(session, prepared->plan, options, events);
  if (static_cast<int>(frames.size()) > session.size) {
    render_frames_on_ranks(*prepared, frames, options, events);
    return outcome;
  }
  return render_tiles_on_ranks(session, *prepared, frames, options, events);
}

}  // namespace glint::mpi
