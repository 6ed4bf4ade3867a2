// SPDX-License-Identifier: GPL-3.0-or-later
// The processes of one `shadow series` run: one process, or the ranks of an MPI job
// (docs/cluster.md). libshadow itself knows nothing of MPI; this is the command line's.
//
// MPI is initialised only when the process was started by an MPI launcher (mpirun, mpiexec,
// srun with PMI/PMIx): a plain `shadow` never touches the MPI library, so it runs as it always
// has, on machines without an MPI runtime configured and as root.
#pragma once

#include "out_of_memory.hpp"

#include <shadow/error.hpp>
#include <shadow/output.hpp>

#include <cstdint>
#include <new>
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

/// The ranks of the run. Without MPI (not built with it, or not launched under a launcher)
/// it is one rank and every collective is a no-op.
class World {
 public:
  /// Joins the MPI job when launched under a launcher (MPI_Init), else a world of one.
  /// @throws RunStopped (exit 2) when launched under a launcher with several ranks but built
  /// without MPI: each process would otherwise compute the whole series alone.
  World();
  ~World();  ///< MPI_Finalize when it was initialised
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  [[nodiscard]] bool root() const { return rank_ == 0; }
  [[nodiscard]] bool distributed() const { return size_ > 1; }

  /// Collective: each rank says whether its part went well (code 0) or not (an exit status and
  /// the line to print). When any failed, throws RunStopped on every rank with the lowest
  /// failing rank's code and message (so one message is printed, by rank 0).
  void agree(int code, const std::string& message);

  /// Collective: the largest of the ranks' values (e.g. "stop now" flags).
  std::uint64_t max(std::uint64_t value);

  /// Collective: rank 0 gets every rank's bytes (index = rank); the others get an empty vector.
  /// Any size (sent in pieces below MPI's int counts).
  std::vector<std::string> gather(const std::string& bytes);

  /// Collective: rank 0's `bytes` on every rank.
  void broadcast(std::string& bytes);

 private:
  int rank_ = 0;
  int size_ = 1;
  bool mpi_ = false;
};

/// Runs `part` on this rank; on a distributed world every rank then agrees on the outcome
/// (World::agree): an InputError on any rank (exit 2), OutputError (3) or other exception (4)
/// stops every rank with that rank's message. On a world of one, exceptions pass through
/// unchanged, exactly as without MPI.
template <typename Part>
void on_every_rank(World& world, Part&& part) {
  if (!world.distributed()) {
    part();
    return;
  }
  int code = 0;
  std::string message;
  try {
    part();
  } catch (const RunStopped&) {
    throw;  // already agreed by every rank
  } catch (const shadow::InputError& e) {
    code = 2;
    message = std::string("shadow: error: ") + e.what();
  } catch (const shadow::OutputError& e) {
    code = 3;
    message = std::string("shadow: error: ") + e.what();
  } catch (const std::bad_alloc&) {
    code = kOutOfMemory;
    message = out_of_memory_line();
  } catch (const std::exception& e) {
    code = is_thread_start_failure(e) ? kOutOfMemory : 4;
    message = code == 4 ? std::string("shadow: internal error: ") + e.what() : out_of_memory_line();
  }
  world.agree(code, message);
}

}  // namespace shadow_cli
