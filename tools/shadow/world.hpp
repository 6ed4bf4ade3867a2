// SPDX-License-Identifier: GPL-3.0-or-later
// The processes of one `shadow series` run: one process, or the ranks of an MPI job
// (docs/cluster.md). libshadow itself knows nothing of MPI; this is the command line's.
//
// MPI is initialised only when the process was started by an MPI launcher (mpirun, mpiexec,
// srun with PMI/PMIx): a plain `shadow` never touches the MPI library, so it runs as it always
// has, on machines without an MPI runtime configured and as root.
#pragma once

#include <shadow/series_job.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadow_cli {

/// Every rank stops: thrown on all ranks at once by World::agree when one of them failed.
/// `message` is the line to print (rank 0 prints it, the others stay silent), `code` the exit status.
struct RunStopped : std::runtime_error {
  RunStopped(int code_in, const std::string& message_in) : std::runtime_error(message_in), code(code_in) {}
  int code;
};

/// Whether this process was started by an MPI launcher (Open MPI's mpirun, a PMI or PMIx
/// launcher such as MPICH's hydra or Slurm's srun). Reads the environment only.
bool launched_by_mpi_launcher();

/// The number of processes the launcher says it started, and this one's rank among them, from
/// the environment alone (0 when no launcher says).
long launcher_size();
long launcher_rank();

/// The ranks of the run, as the library's series job sees them (shadow::SeriesWorld). Without
/// MPI (not built with it, or not launched under a launcher) it is one rank and every
/// collective is a no-op.
class World final : public shadow::SeriesWorld {
 public:
  /// Joins the MPI job when launched under a launcher (MPI_Init), else a world of one.
  /// @throws RunStopped (exit 2) when launched under a launcher with several ranks but built
  /// without MPI: each process would otherwise compute the whole series alone.
  World();
  ~World();  ///< MPI_Finalize when it was initialised
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  [[nodiscard]] int rank() const override { return rank_; }
  [[nodiscard]] int size() const override { return size_; }

  /// Collective: each rank hands in how its part ended; when any failed, throws RunStopped on
  /// every rank with the lowest failing rank's exit status and line (printed once, by rank 0):
  /// an InputError is exit 2, an OutputError 3, running out of memory kOutOfMemory, anything
  /// else 4. On a world of one the error itself is rethrown, exactly as without MPI.
  void agree(std::exception_ptr error) override;

  /// Collective: the largest of the ranks' values (e.g. "stop now" flags).
  std::uint64_t max(std::uint64_t value) override;

  /// Collective: rank 0 gets every rank's bytes (index = rank); the others get an empty vector.
  /// Any size (sent in pieces below MPI's int counts).
  std::vector<std::string> gather(const std::string& bytes) override;

  /// Collective: rank 0's `bytes` on every rank.
  void broadcast(std::string& bytes) override;

 private:
  /// agree() once the error is an exit status and a line (code 0: this rank went well).
  void agree(int code, const std::string& message);
  int rank_ = 0;
  int size_ = 1;
  bool mpi_ = false;
};

}  // namespace shadow_cli
