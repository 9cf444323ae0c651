// Distributed rendering over MPI (built with GLINT_MPI; the glint_mpi
// library). Rank 0 hands out work on demand (tiles of one image, or whole
// frames) and also renders; every rank renders with its own threads. Only
// each rank's main thread calls MPI (MPI_THREAD_FUNNELED): it polls for
// messages while worker threads render.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "glint/accel/accelerator.h"
#include "glint/image/image.h"
#include "glint/render/integrator.h"
#include "glint/render/tile_size.h"
#include "glint/scene/scene.h"

namespace glint::mpi {

// Whether an MPI launcher (mpirun, mpiexec, srun) started this process, from
// the environment as the program passes it (std::getenv: the library itself
// reads no environment variable).
bool launched(const std::function<const char*(const char* name)>& environment);

// A job that cannot go on: a failed MPI call, a rank that stopped answering,
// an error in a rank's own render. Thrown on the rank that found it, once
// that rank's own threads are stopped and joined; `rank` is the rank it is
// about (the hung one, the failed one). The other ranks are left waiting:
// the caller reports it and ends the job with abort_job, which is what
// keeps no rank waiting forever. Never let it unwind past the Session (its
// MPI_Finalize would wait for the ranks that will not come).
class JobFailure : public std::runtime_error {
 public:
  JobFailure(int rank, const std::string& what) : std::runtime_error(what), rank_(rank) {}
  int rank() const { return rank_; }

 private:
  int rank_;
};

// MPI_Init_thread (funneled) on construction, MPI_Finalize on destruction.
// Errors on MPI_COMM_WORLD return codes (MPI_ERRORS_RETURN); glint turns a
// failed call into a JobFailure naming the rank. The constructor throws
// JobFailure when MPI cannot run funneled threads (MPI is initialized then:
// abort_job ends the job).
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  int rank = 0, size = 1;
};

// Ends every process of the job, this one included (MPI_Abort with
// `exit_code`), after a JobFailure: no rank is left waiting for one that gave
// up. Prints nothing (the caller reports the failure first). Open MPI's
// MPI_Abort does not return; should another MPI's return, so does this, and
// the caller ends the process.
void abort_job(int exit_code);

// Collective: the ranks whose `ok` is false (the same list on every rank).
std::vector<int> failed_ranks(bool ok);

// Collective: rank 0's `values` on every rank.
void broadcast(std::vector<int>& values);

// Seconds a rank that holds work may stay silent before rank 0 takes it as
// hung and ends the job (`--rank-timeout`). Ranks send a heartbeat at least
// every second while they hold work, whatever a tile or frame takes.
constexpr double kDefaultRankTimeout = 60;

// Faults to inject, for tests of how a job fails (tests/mpi): after its first
// finished tile or frame, rank `die_rank` kills itself (SIGKILL) and rank
// `hang_rank` stops (SIGSTOP), as a crashed or hung process would. -1: none.
struct FaultInjection {
  int die_rank = -1;
  int hang_rank = -1;
};
// The faults the test-only variables GLINT_TEST_DIE_RANK=R and
// GLINT_TEST_HANG_RANK=R ask for (tests/mpi/mpi_tests.sh), in the
// environment as the program passes it; none when they are unset.
FaultInjection test_faults(const std::function<const char*(const char* name)>& environment);

struct DistributedStats {
  RayStats rays;                   // summed over ranks (rank 0)
  uint64_t bytes_sent = 0;         // by every rank to every other, summed (rank 0)
  uint64_t pixel_bytes = 0;        // of that, tile pixels received by rank 0 (the rest: tile numbers, requests)
  std::vector<int> tiles_by_rank;  // rank 0
  // rank 0: each rank's CPU seconds in the render, and of that its main thread's (MPI)
  std::vector<double> cpu_by_rank, main_cpu_by_rank;
  double seconds = 0;
};

// Collective. Renders `scene` over all ranks, tiles of `tile_size` handed
// out by rank 0 on demand; finished tiles' pixels go to rank 0. Returns the
// whole image on rank 0 (bit-identical to render_image), an empty one elsewhere.
// A rank that holds tiles and sends nothing for `rank_timeout` seconds (a
// stopped or hung process, a lost node) fails the job: rank 0 throws
// JobFailure(R, "no answer for N s (holding tiles ...)"). Any failure throws
// JobFailure (see there).
Image render_image(const Scene& scene, const Accelerator& accel, int threads, int tile_size = kTileSize,
                   DistributedStats* stats = nullptr, double rank_timeout = kDefaultRankTimeout,
                   const FaultInjection& faults = {});

// Collective. Hands out items 0..count-1 on demand, one at a time per rank;
// each rank calls render(item, stop) for the items it gets (from another
// thread). An exception from render fails the job with the rank's error
// (JobFailure). A hung rank fails it as in render_image; `name` words an
// item in that error. When the job fails, `stop` becomes true: render
// should then return soon (a frame render cancels), as the rank waits for
// it before throwing.
void run_items(int count, const std::function<void(int item, const std::atomic<bool>& stop)>& render,
               double rank_timeout = kDefaultRankTimeout, const std::function<std::string(int item)>& name = {},
               const FaultInjection& faults = {});

}  // namespace glint::mpi
