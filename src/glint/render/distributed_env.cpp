// The parts of render/distributed.h that need no MPI, in the library itself:
// the program asks them on every run, and loads MPI only when launched under
// it (program/plugin.h).
#include <cstdlib>

#include "glint/render/distributed.h"

namespace glint::mpi {

bool launched(const std::function<const char*(const char* name)>& environment) {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (environment(name)) return true;
  return false;
}

FaultInjection test_faults(const std::function<const char*(const char* name)>& environment) {
  FaultInjection faults;
  if (const char* die = environment("GLINT_TEST_DIE_RANK")) faults.die_rank = std::atoi(die);
  if (const char* hang = environment("GLINT_TEST_HANG_RANK")) faults.hang_rank = std::atoi(hang);
  return faults;
}

}  // namespace glint::mpi
