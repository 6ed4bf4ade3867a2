// SPDX-License-Identifier: GPL-3.0-or-later
// shadow_cli::World: one process, or the ranks of an MPI job (world.hpp, docs/cluster.md).
#include "world.hpp"

#include "out_of_memory.hpp"

#include <shadow/error.hpp>

#ifdef LIBSHADOW_HAVE_MPI
#include <mpi.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>
#include <thread>

namespace shadow_cli {
namespace {

const char* env(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : nullptr;
}


#ifdef LIBSHADOW_HAVE_MPI
// Pieces of at most 1 GiB: MPI counts are ints.
constexpr std::size_t kPiece = std::size_t{1} << 30;

/// Waits for `request` sleeping between tests. MPI's blocking calls spin on a core while they
/// wait; a rank waiting for rank 0 to write (or for a slower rank's round) would take that core
/// from the computing threads of the ranks that share its node.
void wait(MPI_Request& request) {
  int done = 0;
  long sleep_us = 20;
  for (MPI_Test(&request, &done, MPI_STATUS_IGNORE); !done; MPI_Test(&request, &done, MPI_STATUS_IGNORE)) {
    std::this_thread::sleep_for(std::chrono::microseconds(sleep_us));
    sleep_us = std::min(sleep_us * 2, 5000L);  // at most 5 ms late
  }
}

void send_bytes(const std::string& bytes, int to) {
  std::uint64_t n = bytes.size();
  MPI_Request request;
  MPI_Isend(&n, 1, MPI_UINT64_T, to, 1, MPI_COMM_WORLD, &request);
  wait(request);
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    MPI_Isend(bytes.data() + at, static_cast<int>(std::min(kPiece, bytes.size() - at)), MPI_BYTE, to, 2,
              MPI_COMM_WORLD, &request);
    wait(request);
  }
}

std::string receive_bytes(int from) {
  std::uint64_t n = 0;
  MPI_Request request;
  MPI_Irecv(&n, 1, MPI_UINT64_T, from, 1, MPI_COMM_WORLD, &request);
  wait(request);
  std::string bytes(n, '\0');
  for (std::size_t at = 0; at < bytes.size(); at += kPiece) {
    MPI_Irecv(&bytes[at], static_cast<int>(std::min(kPiece, bytes.size() - at)), MPI_BYTE, from, 2, MPI_COMM_WORLD,
              &request);
    wait(request);
  }
  return bytes;
}

void allreduce(const void* in, void* out, MPI_Datatype type, MPI_Op op) {
  MPI_Request request;
  MPI_Iallreduce(in, out, 1, type, op, MPI_COMM_WORLD, &request);
  wait(request);
}

void bcast(void* data, int count, MPI_Datatype type, int root) {
  MPI_Request request;
  MPI_Ibcast(data, count, type, root, MPI_COMM_WORLD, &request);
  wait(request);
}
#endif

}  // namespace

long launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* value = env(name)) return launched_by_mpi_launcher() ? std::strtol(value, nullptr, 10) : 0;
  return 0;
}

long launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* value = env(name)) return std::strtol(value, nullptr, 10);
  return 0;
}

bool launched_by_mpi_launcher() {
  // Open MPI's mpirun; PMI-1/2 launchers (MPICH's hydra, srun --mpi=pmi2); PMIx (srun --mpi=pmix,
  // Open MPI 5's prterun).
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (env(name) != nullptr) return true;
  return false;
}

World::World() {
  if (!launched_by_mpi_launcher()) return;
#ifdef LIBSHADOW_HAVE_MPI
  int provided = 0;
  // Only the main thread calls MPI; the engine's worker threads never do.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  mpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
#else
  if (launcher_size() > 1)
    throw RunStopped(2, launcher_rank() != 0 ? std::string() :
                        "shadow: error: started by an MPI launcher with " + std::to_string(launcher_size()) +
                            " processes, but this shadow was built without MPI (LIBSHADOW_MPI=OFF): each would "
                            "compute the whole series; run one process, or rebuild with MPI (docs/cluster.md)");
#endif
}

World::~World() {
#ifdef LIBSHADOW_HAVE_MPI
  if (mpi_) MPI_Finalize();
#endif
}

void World::agree(std::exception_ptr error) {
  if (!error) {
    agree(0, std::string());
    return;
  }
  if (!mpi_ || size_ == 1) std::rethrow_exception(error);
  int code = 0;
  std::string message;
  try {
    std::rethrow_exception(error);
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
  agree(code, message);
}

void World::agree(int code, const std::string& message) {
  if (!mpi_ || size_ == 1) {
    if (code != 0) throw RunStopped(code, message);
    return;
  }
#ifdef LIBSHADOW_HAVE_MPI
  // The lowest failing rank speaks for all.
  int mine = code != 0 ? rank_ : size_;
  int first = size_;
  allreduce(&mine, &first, MPI_INT, MPI_MIN);
  if (first == size_) return;
  int failed_code = code;
  bcast(&failed_code, 1, MPI_INT, first);
  std::string text = rank_ == first ? message : std::string();
  std::uint64_t n = text.size();
  bcast(&n, 1, MPI_UINT64_T, first);
  text.resize(n);
  if (n > 0) bcast(&text[0], static_cast<int>(std::min<std::uint64_t>(n, 1u << 20)), MPI_CHAR, first);
  text.resize(std::min<std::uint64_t>(n, 1u << 20));
  // Name the rank when it is not rank 0 (which prints): a node that cannot see a file says so.
  if (first != 0 && text.rfind("shadow: ", 0) == 0)
    text.insert(std::strlen("shadow: "), "rank " + std::to_string(first) + ": ");
  throw RunStopped(failed_code, text);
#endif
}

std::uint64_t World::max(std::uint64_t value) {
#ifdef LIBSHADOW_HAVE_MPI
  if (mpi_ && size_ > 1) {
    std::uint64_t out = value;
    allreduce(&value, &out, MPI_UINT64_T, MPI_MAX);
    return out;
  }
#endif
  return value;
}

std::vector<std::string> World::gather(const std::string& bytes) {
  std::vector<std::string> out;
  if (!mpi_ || size_ == 1) {
    out.push_back(bytes);
    return out;
  }
#ifdef LIBSHADOW_HAVE_MPI
  if (rank_ != 0) {
    send_bytes(bytes, 0);
    return out;
  }
  out.resize(static_cast<std::size_t>(size_));
  out[0] = bytes;
  for (int r = 1; r < size_; ++r) out[static_cast<std::size_t>(r)] = receive_bytes(r);
#endif
  return out;
}

void World::broadcast(std::string& bytes) {
#ifdef LIBSHADOW_HAVE_MPI
  if (!mpi_ || size_ == 1) return;
  std::uint64_t n = bytes.size();
  bcast(&n, 1, MPI_UINT64_T, 0);
  bytes.resize(n);
  for (std::size_t at = 0; at < bytes.size(); at += kPiece)
    bcast(&bytes[at], static_cast<int>(std::min(kPiece, bytes.size() - at)), MPI_BYTE, 0);
#else
  (void)bytes;
#endif
}

}  // namespace shadow_cli
