// MPI ranks for morun; see mpi_world.hpp.
#include "mpi_world.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#ifdef MO_HAVE_MPI
#include <mpi.h>
#endif

namespace mo::tools {

namespace {

#ifdef MO_HAVE_MPI
/// True if a launcher (OpenMPI, MPICH/Hydra, PMIx) started this process.
bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (const char* v = std::getenv(name); v && *v) return true;
  return false;
}

void finalize_at_exit() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

MpiWorld initialise() {
  MpiWorld w;
  if (!launched_by_mpirun()) return w;
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    MPI_Init(nullptr, nullptr);
    std::atexit(finalize_at_exit);
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  return w;
}
#else
MpiWorld initialise() { return {}; }
#endif

}  // namespace

const MpiWorld& mpi_world() {
  static const MpiWorld world = initialise();
  return world;
}

void send_output_to_log(const std::string& dir, int rank) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const std::string path = (std::filesystem::path(dir) / ("rank_" + std::to_string(rank) + ".log")).string();
  std::cout.flush(), std::cerr.flush(), std::fflush(nullptr);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return;
  ::dup2(fd, 1), ::dup2(fd, 2), ::close(fd);
}

std::vector<std::string> mpi_gather(const std::string& text) {
  const MpiWorld& w = mpi_world();
  if (w.size == 1) return {text};
#ifdef MO_HAVE_MPI
  const int length = static_cast<int>(text.size());
  std::vector<int> lengths(w.root() ? static_cast<std::size_t>(w.size) : 0);
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(lengths.size());
  int total = 0;
  for (std::size_t r = 0; r < lengths.size(); ++r) offsets[r] = total, total += lengths[r];
  std::string all(static_cast<std::size_t>(total), '\0');
  MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
              MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < lengths.size(); ++r)
    out.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(lengths[r])));
  return out;
#else
  throw std::logic_error("mpi_gather: several ranks without MPI");
#endif
}

}  // namespace mo::tools
