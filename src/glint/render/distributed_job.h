// A whole distributed render over MPI, as `glint render` runs under mpirun
// (docs/distributed.md): the counterpart for several processes of
// render_frames (render/frame_job.h), built on render/distributed.h and part
// of the glint_mpi library. Every rank prepares the job itself (loads the
// scene), and they agree it worked everywhere before any work is handed out,
// so a bad scene ends every rank with no hang. More frames than ranks: whole
// frames go to ranks (each writes its own); otherwise each frame's tiles are
// spread over all ranks and rank 0 writes it. Never prints: callers report
// from the events and the outcome.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "glint/render/distributed.h"
#include "glint/render/frame_job.h"
#include "glint/scene/scene.h"

namespace glint::mpi {

// What each rank prepares before any work is handed out.
struct Prepared {
  Scene scene;                    // its render settings final (any overrides applied)
  uint64_t inputs_digest = 0;     // scene_inputs_digest(...) of it, for resume keys
  std::vector<FrameOutput> plan;  // every frame asked for, with its output
  // How each frame is rendered (job.output.path is replaced by each frame's).
  // render.progress and render.cancel are not used: a distributed render
  // ends as a whole (JobFailure).
  FrameJob job;
};

struct DistributedOptions {
  bool skip_existing = false;  // frames already done are skipped (rank 0 alone decides which)
  double rank_timeout = kDefaultRankTimeout;
  FaultInjection faults;  // tests only
};

// What render_distributed tells its caller as it goes.
struct DistributedEvents {
  std::function<void(const Scene&)> prepared;       // rank 0, once every rank has prepared
  std::function<void(const FrameOutput&)> skipped;  // rank 0: skip_existing found the frame done
  // Frames to ranks: on the rank that rendered the frame, once it is written;
  // `seconds` since the frame started. May throw: that rank's error fails the job.
  std::function<void(const FrameOutput&, const RenderSettings&, const FrameReport&, double seconds)> frame_finished;
  // Frames in tiles: on rank 0, once the frame's image is written.
  std::function<void(const FrameOutput&, const RenderSettings&, const DistributedStats&, int threads)> tiles_finished;
};

struct DistributedOutcome {
  bool done = true;  // false: every rank refused the job before any work was handed out
  // Then what this rank reports; empty on the ranks that leave it to
  // another, so that the job says it once.
  std::string error;
};

// Collective: every rank calls it with the same arguments. `prepare` runs on
// every rank; when it throws on any, every rank returns done = false, and
// the error is reported by rank 0 when it failed too (the same file, the
// same error), otherwise by each rank that failed, as "rank R: what". So
// does a job that asks passes, adaptive sampling or resume of frames split
// in tiles (they need one process to hold the whole frame): rank 0 reports
// it. A failure on the way (a rank's error, a hung rank, a failed MPI call)
// throws JobFailure: the caller reports it and calls abort_job.
DistributedOutcome render_distributed(const Session& session, const std::function<Prepared()>& prepare,
                                      const DistributedOptions& options, const DistributedEvents& events = {});

}  // namespace glint::mpi
