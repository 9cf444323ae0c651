// The plugin glint-mpi.so (plugin.h): distributed rendering over Open MPI.
#include <optional>

#include "glint/program/api.h"
#include "glint/version.h"

namespace {

std::optional<glint::mpi::Session> session;  // the process's one MPI session

void open_session(int& rank, int& size) {
  session.emplace();
  rank = session->rank;
  size = session->size;
}

void close_session() { session.reset(); }

void abort_job(int rank, const std::string& what) { glint::mpi::abort_job(rank, what); }

}  // namespace

GLINT_PLUGIN_ENTRY const glint::plugin::MpiApi* glint_mpi_api() {
  static const glint::plugin::MpiApi api{{sizeof api, GLINT_VERSION_STRING},
                                         &open_session,
                                         &close_session,
                                         &abort_job,
                                         &glint::mpi::failed_ranks,
                                         &glint::mpi::broadcast,
                                         &glint::mpi::render_image,
                                         &glint::mpi::run_items};
  return &api;
}
