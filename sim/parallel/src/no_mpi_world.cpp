// world() of a build without MPI: always the process alone.
#include "tocd/sim/parallel/team.hpp"

namespace tocd::sim::parallel {

Team& world() {
  return solo();
}

void finish_world() noexcept {}

bool built_with_mpi() noexcept {
  return false;
}

}  // namespace tocd::sim::parallel
