// The MPI ranks of `mpirun -n K morun study.opt`, when morun runs under
// mpirun and was built with MPI (CMake found it); otherwise one rank.
//
// MPI is initialised on the first call to mpi_world() only when the
// environment says that mpirun started this process (OMPI_COMM_WORLD_SIZE,
// PMI_SIZE or PMIX_RANK), and finalised at exit; a plain `morun` never
// touches MPI.
#pragma once

#include <string>
#include <vector>

namespace mo::tools {

/// This process's place among the ranks.
struct MpiWorld {
  int rank = 0;  ///< 0 .. size-1; rank 0 writes the results
  int size = 1;  ///< number of ranks (1 without MPI)
  /// True for rank 0 (and for a process without MPI).
  [[nodiscard]] bool root() const { return rank == 0; }
};

/// The world of this process (initialises MPI on the first call, see above).
const MpiWorld& mpi_world();

/// Sends this process's stdout and stderr to DIR/rank_<rank>.log (for the
/// ranks other than 0, so that one terminal shows one run).
void send_output_to_log(const std::string& dir, int rank);

/// Every rank's `text`, in rank order, on rank 0; empty on the other ranks.
/// Collective: every rank must call it. Without MPI: {text}.
std::vector<std::string> mpi_gather(const std::string& text);

}  // namespace mo::tools
