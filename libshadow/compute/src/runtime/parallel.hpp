// SPDX-License-Identifier: GPL-3.0-or-later
// A small dynamic scheduler: items are handed out one at a time from an atomic counter, because
// the cost per item varies wildly (a face facing away from the light costs nothing; a ground
// face under a city costs a large union). Static chunks left one thread with all the work.
#pragma once

#include <shadow/error.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace shadow::runtime {

/// ShadowOptions::threads (and ShadowEngine's `threads`) above this is an InputError: a typo
/// such as 99999999 would otherwise try to start that many threads and workers.
inline constexpr unsigned kMaxThreads = 1024;

/// `requested`, or InputError when it is above kMaxThreads.
inline unsigned checked_threads(unsigned requested) {
  if (requested > kMaxThreads)
    throw InputError({"", "ShadowOptions::threads"}, "must be 0 (every hardware thread) to " +
                                                          std::to_string(kMaxThreads) + ", got " +
                                                          std::to_string(requested));
  return requested;
}

inline unsigned resolve_threads(unsigned requested) {
  if (requested != 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : hw;
}

/// Thrown inside an item of a parallel_for that was stopped (another item or its progress
/// callback threw first; that first exception is the one parallel_for rethrows).
class Stopped : public std::exception {
 public:
  [[nodiscard]] const char* what() const noexcept override { return "computation stopped"; }
};

namespace detail {
/// The stop flags of the parallel_for calls a thread is working inside, innermost first.
struct StopChain {
  const std::atomic<bool>* flag = nullptr;
  const StopChain* parent = nullptr;
};
inline thread_local const StopChain* stop_chain = nullptr;
/// TickScope's callback on the thread that installed it.
inline thread_local const std::function<void()>* ambient_tick = nullptr;
}  // namespace detail

/// Whether any parallel_for this thread is working inside was stopped.
inline bool stop_requested() noexcept {
  for (const detail::StopChain* c = detail::stop_chain; c != nullptr; c = c->parent)
    if (c->flag->load(std::memory_order_relaxed)) return true;
  return false;
}

/// Throws Stopped when stop_requested(): long items (a face's instants in the sun-hours map)
/// call it between their steps, so that Ctrl-C reaches the caller within about a second
/// instead of when every running item has finished.
inline void check_stop() {
  if (stop_requested()) throw Stopped();
}

/// While alive, every parallel_for called on this thread without a progress callback of its own
/// calls `tick` about every 100 ms while it waits, and stops (rethrowing it) when `tick` throws:
/// a stage made of several parallel_for calls with nothing to count (ShadowEngine's
/// preparation) can be stopped from one callback. Only this thread's calls see it.
class TickScope {
 public:
  explicit TickScope(std::function<void()> tick) : saved_(detail::ambient_tick), tick_(std::move(tick)) {
    if (tick_) detail::ambient_tick = &tick_;
  }
  ~TickScope() { detail::ambient_tick = saved_; }
  TickScope(const TickScope&) = delete;
  TickScope& operator=(const TickScope&) = delete;

 private:
  const std::function<void()>* saved_;
  std::function<void()> tick_;
};

/// Runs task(w) for every w in [0, n) on the library's pool of threads and waits, calling
/// `tick` (if any) about every 100 ms while it does; neither may throw. The pool's threads are
/// started on first need and kept for the process (starting and joining them on every call,
/// about eight calls per light, was a serial cost: docs/benchmarks.md). False, having done nothing, when the
/// pool is running another call's tasks (a nested or concurrent call) or cannot start a thread:
/// the caller then starts threads of its own. runtime/thread_pool.cpp.
bool run_on_pool(unsigned n, const std::function<void(unsigned)>& task, const std::function<void()>& tick);

/// Runs work(worker, item) for item in [0, count) on `threads` workers. The calling thread
/// reports progress (items finished so far) every ~100 ms and at the end. The first exception
/// thrown by any item or by `progress` stops the others and is rethrown here: no new item
/// starts, and running items that call check_stop() end early. A parallel_for inside an item
/// of a stopped one stops too (Stopped). `leaving(worker)`, when given, runs on each worker's
/// own thread once it takes no more items (after its last, or at once when there was none for
/// it), like an item: what it throws stops the call. A worker whose thread could not be started
/// (the threads' own fallback) takes no item and does not leave.
inline void parallel_for(std::size_t count, unsigned threads,
                         const std::function<void(unsigned worker, std::size_t item)>& work,
                         const std::function<void(std::size_t done)>& progress = {},
                         const std::function<void(unsigned worker)>& leaving = {}) {
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  unsigned running = 0;

  auto record = [&](std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!error) error = e;
    failed = true;
  };
  // This call's flag, chained to those of the calls the calling thread is working inside.
  const detail::StopChain chain{&failed, detail::stop_chain};
  auto run = [&](unsigned worker) {
    struct Enter {
      const detail::StopChain* saved = detail::stop_chain;
      explicit Enter(const detail::StopChain* c) { detail::stop_chain = c; }
      ~Enter() { detail::stop_chain = saved; }
    } enter(&chain);
    for (;;) {
      const std::size_t item = next.fetch_add(1, std::memory_order_relaxed);
      if (item >= count || failed.load(std::memory_order_relaxed)) break;
      if (stop_requested()) {  // an enclosing call was stopped: so is this one (never a partial result)
        record(std::make_exception_ptr(Stopped()));
        break;
      }
      try {
        work(worker, item);
      } catch (...) {
        record(std::current_exception());
      }
      done.fetch_add(1, std::memory_order_relaxed);
    }
    if (leaving) {
      try {
        leaving(worker);
      } catch (...) {
        record(std::current_exception());
      }
    }
  };

  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(count, 1))));
  const std::function<void()>* ambient = progress ? nullptr : detail::ambient_tick;
  if (threads == 1 && !progress && ambient == nullptr) {
    run(0);
  } else {
    std::function<void()> tick;
    if (progress || ambient != nullptr)
      tick = [&] {
        try {
          if (progress) {
            progress(done.load());
          } else {
            // Not again from a parallel_for that the tick itself runs on this thread.
            struct Suspend {
              const std::function<void()>* saved = detail::ambient_tick;
              Suspend() { detail::ambient_tick = nullptr; }
              ~Suspend() { detail::ambient_tick = saved; }
            } suspend;
            (*ambient)();
          }
        } catch (...) {
          record(std::current_exception());
        }
      };
    if (!run_on_pool(threads, run, tick)) {
      // The pool is busy: threads of this call's own.
      std::vector<std::thread> pool;
      {
        std::lock_guard<std::mutex> lock(mutex);
        running = 0;
      }
      try {
        for (unsigned w = 0; w < threads; ++w) {
          {
            std::lock_guard<std::mutex> lock(mutex);
            ++running;
          }
          try {
            pool.emplace_back([&, w] {
              run(w);
              std::lock_guard<std::mutex> lock(mutex);
              if (--running == 0) finished.notify_all();
            });
          } catch (...) {  // no more threads to be had: the ones running finish the work
            std::lock_guard<std::mutex> lock(mutex);
            --running;
            break;  // (none at all, e.g. no memory for a stack under a limit: this thread, below)
          }
        }
        std::unique_lock<std::mutex> lock(mutex);
        while (running != 0) {
          finished.wait_for(lock, std::chrono::milliseconds(100));
          if (tick && running != 0) {
            lock.unlock();
            tick();
            lock.lock();
          }
        }
      } catch (...) {
        record(std::current_exception());
      }
      for (std::thread& t : pool) t.join();  // never leave a joinable thread behind
      // Not one thread could be started: the results do not depend on the thread count.
      if (pool.empty()) run(0);
    }
  }
  if (error) std::rethrow_exception(error);
  if (progress) progress(done.load());
}

/// parallel_for over the indices [0, count) in blocks of `block` consecutive ones, each block
/// one work item: work(worker, b, begin, end) for block b = [begin, end) (the last may be
/// shorter). For items too small to be handed out one by one, or whose neighbours share data.
/// `progress` counts blocks; `leaving` as parallel_for's.
inline void parallel_for_blocks(std::size_t count, std::size_t block, unsigned threads,
                                const std::function<void(unsigned, std::size_t, std::size_t, std::size_t)>& work,
                                const std::function<void(std::size_t done)>& progress = {},
                                const std::function<void(unsigned worker)>& leaving = {}) {
  parallel_for(
      (count + block - 1) / block, threads,
      [&](unsigned worker, std::size_t b) { work(worker, b, b * block, std::min(count, (b + 1) * block)); },
      progress, leaving);
}

/// A block size for parallel_for_blocks over `count` items of unknown, possibly very unequal
/// cost on `threads` threads: at most 256 items (a million cheap items need not be handed out
/// one by one), and at least 64 blocks a thread where there are items enough (a few costly ones
/// still spread over the threads, and a stop request is seen between them).
inline std::size_t block_of(std::size_t count, unsigned threads) {
  return std::clamp<std::size_t>(count / (std::size_t{64} * std::max(1u, threads)), 1, 256);
}

}  // namespace shadow::runtime
