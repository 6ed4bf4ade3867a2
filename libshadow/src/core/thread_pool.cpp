// SPDX-License-Identifier: GPL-3.0-or-later
// The library's pool of worker threads (core::run_on_pool, used by core::parallel_for).
//
// parallel_for used to start its threads and join them on every call: several calls per light
// (the workers, the item table, the light-space grid, the receivers, the tiles, the result rows),
// and on 16 threads each start and join cost about 0.3-0.6 ms, serial, in the calling thread.
// The pool's threads are started once, on first need, and wait for the next call's tasks.
//
// - One call at a time: a call made while another is running (from inside a task, or from
//   another thread) gets false and its caller starts threads of its own, as before.
// - The pool is never destroyed: its threads may still be waiting on it when the process exits
//   (destroying a mutex or condition variable that a thread waits on is undefined).
// - fork(): the child has only the forking thread, so it drops the parent's pool (leaked, its
//   locks possibly held by threads that no longer exist) and starts its own on first need.
#include "core/parallel.hpp"

#include <pthread.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace shadow::core {
namespace {

class ThreadPool {
 public:
  /// Runs task(w) for w in [0, n) and waits (see run_on_pool).
  bool run(unsigned n, const std::function<void(unsigned)>& task, const std::function<void()>& tick) {
    std::unique_lock<std::mutex> call(call_mutex_, std::try_to_lock);
    if (!call.owns_lock()) return false;
    if (!grow(n)) return false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = &task;
      tasks_ = n;
      next_ = 0;
      unfinished_ = n;
    }
    work_.notify_all();
    std::unique_lock<std::mutex> lock(mutex_);
    while (unfinished_ != 0) {
      if (done_.wait_for(lock, std::chrono::milliseconds(100), [&] { return unfinished_ == 0; })) break;
      if (tick) {
        lock.unlock();
        tick();
        lock.lock();
      }
    }
    task_ = nullptr;  // no thread reads it again: every task has been taken and has returned
    return true;
  }

 private:
  /// At least n threads (false when not even one can be started).
  bool grow(unsigned n) {
    while (threads_.size() < n) {
      try {
        threads_.emplace_back([this] { serve(); });
      } catch (const std::system_error&) {
        // Fewer threads than tasks is fine: each thread takes tasks until none is left.
        return !threads_.empty();
      }
    }
    return true;
  }

  void serve() {
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

  std::mutex call_mutex_;  ///< held by the one call running (try_lock: others start their own threads)
  std::mutex mutex_;
  std::condition_variable work_, done_;
  std::vector<std::thread> threads_;  ///< never joined: the pool lives as long as the process
  const std::function<void(unsigned)>* task_ = nullptr;
  unsigned tasks_ = 0, next_ = 0, unfinished_ = 0;
};

// The pool and the mutex that guards making it: pointers, so that a forked child can drop both
// (another thread of the parent may have held either at the fork) and make its own.
ThreadPool* g_pool = nullptr;
ThreadPool* g_parents_pool = nullptr;  ///< in a forked child: kept reachable, never used
std::mutex* g_pool_mutex = new std::mutex;
std::once_flag g_atfork_once;

void forget_pool_in_child() {
  if (g_pool != nullptr) g_parents_pool = g_pool;
  g_pool = nullptr;
  g_pool_mutex = new std::mutex;
}

ThreadPool& pool() {
  std::call_once(g_atfork_once, [] { pthread_atfork(nullptr, nullptr, forget_pool_in_child); });
  std::lock_guard<std::mutex> lock(*g_pool_mutex);
  if (g_pool == nullptr) g_pool = new ThreadPool;  // never deleted (see the top of this file)
  return *g_pool;
}

}  // namespace

bool run_on_pool(unsigned n, const std::function<void(unsigned)>& task, const std::function<void()>& tick) {
  if (n == 0) return true;
  return pool().run(n, task, tick);
}

}  // namespace shadow::core
