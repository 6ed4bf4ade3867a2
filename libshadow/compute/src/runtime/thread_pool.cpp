// SPDX-License-Identifier: GPL-3.0-or-later
// The library's pool of worker threads (runtime::run_on_pool, used by runtime::parallel_for).
//
// parallel_for is called about eight times per light (the workers, the item table, the
// light-space grid, the receivers, the tile cells, the tiles, the result rows, their release);
// starting and joining threads on every call is a serial cost in the calling thread
// (docs/benchmarks.md). The pool's threads are started once, on first need, and wait for the
// next call's tasks.
//
// - One call at a time: a call made while another is running (from inside a task or a progress
//   report, or from another thread) gets false and its caller starts threads of its own.
// - The pool is never destroyed, and the shared library is never unloaded (-z nodelete): its
//   threads wait in this code until the process exits. It grows to the most threads one call
//   asked for; they keep their thread-local scratch (fast/cluster_union.hpp's) between calls.
// - Its threads start with every signal blocked (a program's sigwait stays its own) and the
//   default floating-point environment (round to nearest, which CGAL's filters expect).
// - fork(): the child has only the forking thread, so it drops the parent's pool (its locks
//   possibly held by threads that no longer exist) and starts its own on first need.
#include "runtime/parallel.hpp"

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <cfenv>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

namespace shadow::runtime {
namespace {

class ThreadPool {
 public:
  /// Runs task(w) for w in [0, n) and waits (see run_on_pool).
  bool run(unsigned n, const std::function<void(unsigned)>& task, const std::function<void()>& tick) {
    if (busy_.exchange(true, std::memory_order_acquire)) return false;
    struct Release {
      std::atomic<bool>& busy;
      ~Release() { busy.store(false, std::memory_order_release); }
    } release{busy_};
    if (!grow(n)) return false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = &task;
      tasks_ = n;
      next_ = 0;
      unfinished_ = n;
    }
    if (n >= threads_.size()) {
      work_.notify_all();
    } else {
      for (unsigned k = 0; k < n; ++k) work_.notify_one();
    }
    // Until every task has returned, whatever happens here: the tasks use the caller's frame.
    std::unique_lock<std::mutex> lock(mutex_);
    while (!done_.wait_for(lock, std::chrono::milliseconds(100), [&] { return unfinished_ == 0; })) {
      if (!tick) continue;
      lock.unlock();
      try {
        tick();
      } catch (...) {  // tick must not throw (parallel_for's records its errors); if it does, ignored
      }
      lock.lock();
    }
    task_ = nullptr;  // no thread reads it again: every task has been taken and has returned
    return true;
  }

 private:
  /// At least n threads (false when not even one can be started).
  bool grow(unsigned n) {
    if (threads_.size() >= n) return true;
    // New threads inherit the signal mask: all blocked while they start.
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    while (threads_.size() < n) {
      try {
        threads_.emplace_back([this] { serve(); });
      } catch (...) {
        break;  // fewer threads than tasks is fine: each thread takes tasks until none is left
      }
    }
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    return !threads_.empty();
  }

  void serve() {
    std::fesetenv(FE_DFL_ENV);
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      work_.wait(lock, [&] { return task_ != nullptr && next_ < tasks_; });
      const unsigned w = next_++;
      const std::function<void(unsigned)>& task = *task_;
      lock.unlock();
      task(w);
      lock.lock();
      if (--unfinished_ == 0) done_.notify_all();
    }
  }

  std::atomic<bool> busy_{false};  ///< a call is running (others start threads of their own)
  std::mutex mutex_;
  std::condition_variable work_, done_;
  std::vector<std::thread> threads_;  ///< never joined: the pool lives as long as the process (busy_ guards it)
  const std::function<void(unsigned)>* task_ = nullptr;
  unsigned tasks_ = 0, next_ = 0, unfinished_ = 0;
};

// The pool and the mutex that guards making it, through pointers, so that a forked child can
// drop both (another thread of the parent may have held either at the fork) and make its own:
// a fresh mutex in static storage (no allocation in the child's fork handler).
ThreadPool* g_pool = nullptr;
std::vector<ThreadPool*> g_parents_pools;  ///< in forked children: kept reachable, never used
std::mutex g_first_mutex;                  // constant-initialised
std::mutex* g_pool_mutex = &g_first_mutex;
alignas(std::mutex) unsigned char g_child_mutex[sizeof(std::mutex)];

void forget_pool_in_child() {
  g_pool_mutex = new (g_child_mutex) std::mutex;
  if (g_pool != nullptr) {
    try {
      g_parents_pools.push_back(g_pool);
    } catch (...) {  // leaked unreachably: only a leak checker would mind
    }
  }
  g_pool = nullptr;
}

// Registered when the library loads (not on first use: a fork during a first registration
// through call_once would leave the child's flag running forever).
[[maybe_unused]] const int g_atfork_registered = pthread_atfork(nullptr, nullptr, forget_pool_in_child);

ThreadPool& pool() {
  std::lock_guard<std::mutex> lock(*g_pool_mutex);
  if (g_pool == nullptr) g_pool = new ThreadPool;  // never deleted (see the top of this file)
  return *g_pool;
}

}  // namespace

bool run_on_pool(unsigned n, const std::function<void(unsigned)>& task, const std::function<void()>& tick) {
  if (n == 0) return true;
  return pool().run(n, task, tick);
}

}  // namespace shadow::runtime
