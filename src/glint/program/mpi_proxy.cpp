// Distributed rendering through the plugin glint-mpi.so (plugin.h), loaded
// only when an MPI launcher started the program (mpi::launched, which needs
// no MPI, is in the library: render/distributed_env.cpp).
#include <cstdlib>

#include "glint/program/api.h"
#include "glint/version.h"

namespace glint::mpi {

namespace {
// Global: Open MPI's components, loaded by MPI_Init, look for its symbols there.
const plugin::MpiApi& plugin_api() {
  return plugin::api<plugin::MpiApi>("mpi", "glint_mpi_api", GLINT_VERSION_STRING, true);
}
}  // namespace

Session::Session() { plugin_api().open_session(rank, size); }
Session::~Session() { plugin_api().close_session(); }

void abort_job(int rank, const std::string& what) {
  plugin_api().abort_job(rank, what);
  std::abort();  // not reached: MPI_Abort ends the process
}

std::vector<int> failed_ranks(bool ok) { return plugin_api().failed_ranks(ok); }

void broadcast(std::vector<int>& values) { plugin_api().broadcast(values); }

Image render_image(const Scene& scene, const Accelerator& accel, int threads, int tile_size, DistributedStats* stats,
                   double rank_timeout, const FaultInjection& faults) {
  return plugin_api().render_image(scene, accel, threads, tile_size, stats, rank_timeout, faults);
}

void run_items(int count, const std::function<void(int item)>& render, double rank_timeout,
               const std::function<std::string(int item)>& name, const FaultInjection& faults) {
  plugin_api().run_items(count, render, rank_timeout, name, faults);
}

}  // namespace glint::mpi
