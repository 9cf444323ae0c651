// Distributed rendering through the plugin glint-mpi.so (plugin.h), loaded
// only when an MPI launcher started the program (mpi::launched, which needs
// no MPI, is in the library: render/distributed_env.cpp).
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

void abort_job(int exit_code) { plugin_api().abort_job(exit_code); }

// JobFailure and glint::Error thrown in the plugin reach the program's
// handlers: both are built with the same libstdc++, which matches a caught
// type by its name (the plugin's copy of a type_info is its own, hidden).
DistributedOutcome render_distributed(const Session& session, const std::function<Prepared()>& prepare,
                                      const DistributedOptions& options, const DistributedEvents& events) {
  return plugin_api().render_distributed(session, prepare, options, events);
}

}  // namespace glint::mpi
