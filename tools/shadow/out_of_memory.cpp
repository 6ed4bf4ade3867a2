// SPDX-License-Identifier: GPL-3.0-or-later
#include "out_of_memory.hpp"

#include "page_policy.hpp"

#include <gmp.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <new>
#include <system_error>

namespace shadow_cli {
namespace {

std::atomic<Stage> g_stage{Stage::Starting};
std::atomic<bool> g_reported{false};  // one line, even when several threads run out at once

void* gmp_allocate(std::size_t size) {
  void* p = std::malloc(size);
  if (p == nullptr && size > 0) exit_out_of_memory();
  return p;
}

void* gmp_reallocate(void* old, std::size_t /*old_size*/, std::size_t new_size) {
  void* p = std::realloc(old, new_size);
  if (p == nullptr && new_size > 0) exit_out_of_memory();
  return p;
}

void gmp_free(void* p, std::size_t /*size*/) { std::free(p); }

void write_all(const char* text) {
  std::size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<std::size_t>(n);
  }
}

}  // namespace

void set_stage(Stage stage) { g_stage.store(stage, std::memory_order_relaxed); }

const char* stage_words(Stage stage) {
  switch (stage) {
    case Stage::Starting: return "starting";
    case Stage::Loading: return "loading the scene";
    case Stage::Preparing: return "preparing the faces";
    case Stage::Computing: return "computing the shadows";
    case Stage::Writing: return "writing the outputs";
    case Stage::Rendering: return "rendering";
  }
  return "running";
}

void install_gmp_out_of_memory() { mp_set_memory_functions(gmp_allocate, gmp_reallocate, gmp_free); }

void install_new_out_of_memory() { std::set_new_handler([] { exit_out_of_memory(); }); }

void prepare_allocator_arenas() {
  const AllocatorControl mallctl = allocator_control();
  if (mallctl == nullptr) return;
  unsigned arenas = 0, mine = 0;
  std::size_t size = sizeof arenas;
  if (mallctl("arenas.narenas", &arenas, &size, nullptr, 0) != 0) return;
  size = sizeof mine;
  if (mallctl("thread.arena", &mine, &size, nullptr, 0) != 0) return;
  // Binding this thread to an arena initialises it (jemalloc's "thread.arena"); then back.
  for (unsigned a = 0; a < arenas && a < 1024; ++a) mallctl("thread.arena", nullptr, nullptr, &a, sizeof a);
  mallctl("thread.arena", nullptr, nullptr, &mine, sizeof mine);
}

bool is_thread_start_failure(const std::exception& e) {
  if (const auto* system = dynamic_cast<const std::system_error*>(&e))
    return system->code() == std::errc::resource_unavailable_try_again;
  // TBB's (VTK's threads): "pthread_create has failed: Resource temporarily unavailable".
  return std::strncmp(e.what(), "pthread_create has failed", 25) == 0;
}

constexpr const char* kLineStart = "shadow: error: out of memory while ";
constexpr const char* kLineEnd =
    " (the process may not use more memory: free some, raise its limit (ulimit -v), or use fewer --threads); "
    "no report.json was written";

/// The line itself, by the one caller that claimed it.
static void write_out_of_memory_line() {
  // Pieces written one after the other: nothing here may allocate.
  write_all(kLineStart);
  write_all(stage_words(g_stage.load(std::memory_order_relaxed)));
  write_all(kLineEnd);
  write_all("\n");
}

void print_out_of_memory() {
  if (!g_reported.exchange(true)) write_out_of_memory_line();
}

std::string out_of_memory_line() {
  return std::string(kLineStart) + stage_words(g_stage.load(std::memory_order_relaxed)) + kLineEnd;
}

void exit_out_of_memory() {
  // One claim: a second thread out of memory at the same moment waits for the first one's line
  // and exit instead of ending the process in the middle of it.
  if (g_reported.exchange(true)) {
    for (;;) ::pause();
  }
  write_out_of_memory_line();
  ::_exit(kOutOfMemory);
}

}  // namespace shadow_cli
