// SPDX-License-Identifier: GPL-3.0-or-later
// runtime::parallel_for on the library's pool of threads (runtime/thread_pool.cpp): every item once,
// the same threads from call to call, a nested or concurrent call on threads of its own, errors
// and progress as before, and a forked child that makes its own pool.
#include "runtime/parallel.hpp"

#include <gtest/gtest.h>

#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace {

using shadow::runtime::parallel_for;

long kernel_thread_id() { return static_cast<long>(syscall(SYS_gettid)); }

/// parallel_for over `count` items on `threads`: whether every item ran exactly once.
bool every_item_once(std::size_t count, unsigned threads) {
  std::vector<std::atomic<int>> runs(count);
  parallel_for(count, threads, [&](unsigned, std::size_t i) { runs[i].fetch_add(1); });
  for (const auto& r : runs)
    if (r.load() != 1) return false;
  return true;
}

TEST(Parallel, EveryItemOnce) {
  for (unsigned threads : {1u, 2u, 3u, 8u, 16u})
    for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{5}, std::size_t{1000}})
      EXPECT_TRUE(every_item_once(count, threads)) << threads << " threads, " << count << " items";
}

TEST(Parallel, TheSameThreadsFromCallToCall) {
  // Kernel thread ids (not std::thread::id, which the C library may hand out again): threads
  // started per call would show 4 new ids per call, 40 in all. The pool has at most as many
  // threads as the most any call of this process asked for (16 in this file).
  std::set<long> seen;
  std::mutex mutex;
  for (int call = 0; call < 10; ++call)
    parallel_for(64, 4, [&](unsigned, std::size_t) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      std::lock_guard<std::mutex> lock(mutex);
      seen.insert(kernel_thread_id());
    });
  EXPECT_LE(seen.size(), 16u);
  EXPECT_EQ(seen.count(kernel_thread_id()), 0u);  // the caller only waits
}

TEST(Parallel, WorkerIdsAreDistinctAndBelowTheThreadCount) {
  std::vector<std::set<long>> threads_of(6);
  std::mutex mutex;
  parallel_for(600, 6, [&](unsigned w, std::size_t) {
    ASSERT_LT(w, 6u);
    std::this_thread::sleep_for(std::chrono::microseconds(50));
    std::lock_guard<std::mutex> lock(mutex);
    threads_of[w].insert(kernel_thread_id());
  });
  // A worker id is one thread's at a time: two threads never share one id in a call.
  for (const auto& ids : threads_of) EXPECT_LE(ids.size(), 1u);
}

TEST(Parallel, EachWorkerLeavesOnceOnItsOwnThreadAfterItsLastItem) {
  // What the engine's SpanTimer relies on: a worker's `leaving` runs on the thread that ran its
  // items (the per-thread CPU clock is read there), once, after every item of that worker.
  for (unsigned threads : {1u, 3u}) {
    std::vector<std::set<long>> item_threads(threads), leave_threads(threads);
    std::vector<int> items_after_leaving(threads, 0), leaves(threads, 0);
    std::vector<char> left(threads, 0);
    std::mutex mutex;
    std::size_t items = 0;
    parallel_for(
        300, threads,
        [&](unsigned w, std::size_t) {
          std::this_thread::sleep_for(std::chrono::microseconds(20));
          std::lock_guard<std::mutex> lock(mutex);
          item_threads[w].insert(kernel_thread_id());
          items_after_leaving[w] += left[w];
          ++items;
        },
        {},
        [&](unsigned w) {
          std::lock_guard<std::mutex> lock(mutex);
          leave_threads[w].insert(kernel_thread_id());
          left[w] = 1;
          ++leaves[w];
        });
    EXPECT_EQ(items, 300u);
    for (unsigned w = 0; w < threads; ++w) {
      EXPECT_EQ(items_after_leaving[w], 0) << w;
      EXPECT_LE(leaves[w], 1) << w;
      if (!item_threads[w].empty()) {
        EXPECT_EQ(leaves[w], 1) << w;
        EXPECT_EQ(leave_threads[w], item_threads[w]) << w;
      }
    }
  }
  // What `leaving` throws stops the call as an item's error does.
  EXPECT_THROW(parallel_for(10, 2, [](unsigned, std::size_t) {}, {},
                            [](unsigned) { throw std::runtime_error("leaving"); }),
               std::runtime_error);
}

TEST(Parallel, NestedAndConcurrentCallsRunOnThreadsOfTheirOwn) {
  std::atomic<long> sum{0};
  parallel_for(8, 4, [&](unsigned, std::size_t) {
    // The pool is running this call: the inner one starts its own threads.
    parallel_for(100, 3, [&](unsigned, std::size_t i) { sum.fetch_add(static_cast<long>(i)); });
  });
  EXPECT_EQ(sum.load(), 8 * 4950);

  std::atomic<long> a{0}, b{0};
  std::thread other([&] {
    for (int k = 0; k < 20; ++k) parallel_for(500, 3, [&](unsigned, std::size_t i) { a.fetch_add(static_cast<long>(i)); });
  });
  for (int k = 0; k < 20; ++k) parallel_for(500, 3, [&](unsigned, std::size_t i) { b.fetch_add(static_cast<long>(i)); });
  other.join();
  EXPECT_EQ(a.load(), 20 * 124750);
  EXPECT_EQ(b.load(), 20 * 124750);
}

TEST(Parallel, AnErrorStopsTheCallAndThePoolGoesOn) {
  EXPECT_THROW(parallel_for(1000, 4,
                            [&](unsigned, std::size_t i) {
                              if (i == 17) throw std::runtime_error("item 17");
                            }),
               std::runtime_error);
  EXPECT_TRUE(every_item_once(1000, 4));
}

TEST(Parallel, ProgressWhileItRunsAndAtTheEnd) {
  std::vector<std::size_t> reports;
  parallel_for(
      40, 2, [&](unsigned, std::size_t) { std::this_thread::sleep_for(std::chrono::milliseconds(20)); },
      [&](std::size_t done) { reports.push_back(done); });
  ASSERT_GE(reports.size(), 2u);  // about 400 ms of work: reports before the end
  EXPECT_EQ(reports.back(), 40u);
  for (std::size_t k = 1; k < reports.size(); ++k) EXPECT_LE(reports[k - 1], reports[k]);
}

TEST(Parallel, AProgressReportThatThrowsOrComputesInTurn) {
  // The error of a progress report stops the call, after every running item has returned.
  std::atomic<int> running{0};
  EXPECT_THROW(parallel_for(
                   40, 2,
                   [&](unsigned, std::size_t) {
                     running.fetch_add(1);
                     std::this_thread::sleep_for(std::chrono::milliseconds(20));
                     running.fetch_sub(1);
                   },
                   [&](std::size_t done) {
                     if (done < 40) throw std::runtime_error("report");
                   }),
               std::runtime_error);
  EXPECT_EQ(running.load(), 0);
  EXPECT_TRUE(every_item_once(1000, 4));  // the pool goes on
  // A report that runs a parallel_for of its own (a Python callback calling the library, say):
  // it gets threads of its own while the pool runs the outer call.
  std::atomic<long> inner{0};
  parallel_for(
      20, 2, [&](unsigned, std::size_t) { std::this_thread::sleep_for(std::chrono::milliseconds(20)); },
      [&](std::size_t) { parallel_for(10, 3, [&](unsigned, std::size_t i) { inner.fetch_add(static_cast<long>(i)); }); });
  EXPECT_GT(inner.load(), 0);
  EXPECT_EQ(inner.load() % 45, 0);
}

// ---- stopping (issue 30, item 13: Ctrl-C within about a second) ---------------------------------

TEST(Parallel, RunningItemsStopAtTheirNextCheckWhenTheProgressReportThrows) {
  // Four items of 400 steps of 5 ms each: without a stop, 1,600 steps. The first report throws;
  // the running items see it at their next check_stop() instead of finishing their 400 steps.
  std::atomic<int> steps{0};
  EXPECT_THROW(parallel_for(
                   4, 2,
                   [&](unsigned, std::size_t) {
                     for (int k = 0; k < 400; ++k) {
                       shadow::runtime::check_stop();
                       std::this_thread::sleep_for(std::chrono::milliseconds(5));
                       steps.fetch_add(1);
                     }
                   },
                   [&](std::size_t) { throw std::runtime_error("report"); }),
               std::runtime_error);
  EXPECT_LT(steps.load(), 400);
  EXPECT_FALSE(shadow::runtime::stop_requested());  // nothing left behind on this thread
  EXPECT_TRUE(every_item_once(1000, 4));
}

TEST(Parallel, ACallInsideAStoppedItemStopsToo) {
  // The inner call runs on threads of its own (the pool runs the outer one); it must stop, and
  // never hand the item a partial result as if it were complete.
  std::atomic<int> inner_items{0};
  std::atomic<int> partial_results{0};
  try {
    parallel_for(
        2, 2,
        [&](unsigned, std::size_t) {
          parallel_for(400, 2, [&](unsigned, std::size_t) {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
            inner_items.fetch_add(1);
          });
          partial_results.fetch_add(1);  // reached only when the inner call did every item
        },
        [&](std::size_t) { throw std::runtime_error("report"); });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "report");  // the first error, not the inner Stopped
  }
  EXPECT_LT(inner_items.load(), 2 * 400);
  EXPECT_EQ(partial_results.load(), 0);
}

TEST(Parallel, ATickScopeStopsCallsThatHaveNoProgressOfTheirOwn) {
  std::atomic<int> items{0};
  int ticks = 0;
  {
    shadow::runtime::TickScope scope([&] {
      if (++ticks >= 1) throw std::runtime_error("tick");
    });
    EXPECT_THROW(parallel_for(200, 1,
                              [&](unsigned, std::size_t) {
                                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                                items.fetch_add(1);
                              }),
                 std::runtime_error);
  }
  EXPECT_GE(ticks, 1);
  EXPECT_LT(items.load(), 200);
  // Outside the scope: no tick, every item.
  const int before = ticks;
  EXPECT_TRUE(every_item_once(100, 2));
  EXPECT_EQ(ticks, before);
}

TEST(Parallel, AForkedChildMakesItsOwnPool) {
  ASSERT_TRUE(every_item_once(100, 4));  // the parent's pool exists
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // Only this thread exists here: the parent's pool threads do not. A pool that believed
    // in them would wait forever.
    try {
      const bool ok = every_item_once(1000, 4) && every_item_once(10, 3);
      _exit(ok ? 0 : 1);
    } catch (...) {
      _exit(2);
    }
  }
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  pid_t done = 0;
  while ((done = waitpid(child, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (done == 0) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    FAIL() << "the forked child's parallel_for did not finish in 20 s";
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(every_item_once(100, 4));  // and the parent's pool still works
}

}  // namespace
