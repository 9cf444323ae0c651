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

}  // namespace

GLINT_PLUGIN_ENTRY const glint::plugin::MpiApi* glint_mpi_api() {
  static const glint::plugin::MpiApi api{{sizeof api, GLINT_VERSION_STRING},
                                         &open_session,
                                         &close_session,
                                         &glint::mpi::abort_job,
                                         &glint::mpi::render_distributed};
  return &api;
}
