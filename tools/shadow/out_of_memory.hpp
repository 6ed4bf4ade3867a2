// SPDX-License-Identifier: GPL-3.0-or-later
// Running out of memory in the `shadow` program: one line naming the stage, exit status 6, and
// no report.json (it is written last, under a temporary name, and the old one is removed before
// computing). Two ways memory runs out:
//
// - GMP (and MPFR, which allocates through GMP's functions) cannot allocate: GMP's manual allows
//   its allocation functions no error return, and says a longjmp or a C++ exception thrown from
//   them has undefined results (GMP is C; its objects may be left half-updated). So the CLI's
//   functions do not throw: on failure they print the line and end the process with _exit (a
//   GMP allocation fails on any thread, while the others still run: no destructors, no atexit
//   handlers). A temporary output file may be left; the next run removes it.
// - operator new cannot allocate: the CLI's new handler does the same. Letting std::bad_alloc
//   unwind was tried: CGAL's Boolean operations are not exception safe, and a Polygon_set_2
//   left by a bad_alloc in the middle of a join crashed in its destructor (SIGSEGV) on the way.
// - A thread cannot be started (no memory for its stack): the library's own threads fall back
//   to fewer (runtime/parallel.hpp); elsewhere (VTK's TBB threads while writing) the exception
//   reaches main(), which prints the line (is_thread_start_failure).
//
// The library itself installs nothing: GMP's functions are process-wide, and a program that
// uses libshadow (or Python, with other GMP users in the same process) may have its own.
#pragma once

#include <exception>
#include <string>

namespace shadow_cli {

/// Exit status when memory ran out (README.md's table, `shadow --help`).
constexpr int kOutOfMemory = 6;

/// What the program is doing, for the out-of-memory line.
enum class Stage { Starting, Loading, Preparing, Computing, Writing, Rendering };

/// Sets the stage named by the out-of-memory line (any thread may read it at any time).
void set_stage(Stage stage);

/// "loading the scene", "preparing the faces", ... for `stage`.
const char* stage_words(Stage stage);

/// Replaces GMP's allocation functions by malloc, realloc and free that end the process with
/// the out-of-memory line when they fail, instead of GMP's message and abort(). Call once, at
/// the start of main() before any thread is started. Compatible with blocks GMP allocated
/// before (the same malloc and free underneath), so static GMP numbers made earlier are fine.
void install_gmp_out_of_memory();

/// Makes operator new's failures (and new (std::nothrow)'s) end the process like GMP's:
/// exit_out_of_memory from the new handler. Call once, at the start of main().
void install_new_out_of_memory();

/// Whether `e` says that a thread could not be started for want of resources (std::thread's
/// EAGAIN, TBB's "pthread_create has failed"): out of memory under a limit such as ulimit -v.
bool is_thread_start_failure(const std::exception& e);

/// Where the program runs on jemalloc (our builds link it): initialises every automatic arena
/// now, while memory is plentiful. jemalloc makes a thread's arena on the thread's first
/// allocation, and when the mapping for it fails (a limit such as ulimit -v reached) it
/// dereferences the missing arena (SIGSEGV, jemalloc 5.3, seen under ulimit -v when a pool or
/// TBB thread started late). A no-op with another allocator (mallctl looked up at run time).
void prepare_allocator_arenas();

/// Writes the out-of-memory line for the current stage to stderr, without allocating (once per
/// process: threads that run out together print one line).
void print_out_of_memory();

/// The same line as a string, without its newline (MPI ranks agree on one message to print).
std::string out_of_memory_line();

/// print_out_of_memory(), then _exit(kOutOfMemory).
[[noreturn]] void exit_out_of_memory();

}  // namespace shadow_cli
