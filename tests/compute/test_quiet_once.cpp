// SPDX-License-Identifier: GPL-3.0-or-later
// The library's pthread_once (libshadow/compute/src/runtime/quiet_once.cpp), which its own std::call_once
// calls reach through the linker's --wrap: runs the routine exactly once, makes late callers
// wait for it, runs it again after an exception, and shares glibc's "done" value both ways.
#include <gtest/gtest.h>

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

extern "C" int __wrap_pthread_once(pthread_once_t* once, void (*init)(void));

namespace {

std::atomic<int> runs{0};
std::atomic<bool> inside{false};

void count_run() { runs.fetch_add(1); }

void slow_run() {
  EXPECT_FALSE(inside.exchange(true));  // never two runs at once
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  runs.fetch_add(1);
  inside = false;
}

std::atomic<int> attempts{0};
void fail_first_two() {
  std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (attempts.fetch_add(1) < 2) throw std::runtime_error("not yet");
  runs.fetch_add(1);
}

TEST(QuietOnce, RunsOnceOnOneThread) {
  runs = 0;
  pthread_once_t once = PTHREAD_ONCE_INIT;
  for (int k = 0; k < 5; ++k) EXPECT_EQ(__wrap_pthread_once(&once, count_run), 0);
  EXPECT_EQ(runs.load(), 1);
}

TEST(QuietOnce, LateCallersWaitForTheRun) {
  runs = 0;
  pthread_once_t once = PTHREAD_ONCE_INIT;
  std::vector<std::thread> threads;
  std::atomic<int> returned_before_done{0};
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&] {
      __wrap_pthread_once(&once, slow_run);
      if (runs.load() != 1) returned_before_done.fetch_add(1);
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(runs.load(), 1);
  EXPECT_EQ(returned_before_done.load(), 0);
}

TEST(QuietOnce, AnExceptionLeavesItToRunAgain) {
  runs = 0;
  attempts = 0;
  pthread_once_t once = PTHREAD_ONCE_INIT;
  EXPECT_THROW(__wrap_pthread_once(&once, fail_first_two), std::runtime_error);
  EXPECT_EQ(runs.load(), 0);
  // Concurrent callers after a failure: one of them fails once more, then one succeeds, and
  // every caller that did not throw returns after the successful run.
  std::vector<std::thread> threads;
  std::atomic<int> threw{0}, returned_before_done{0};
  for (int t = 0; t < 6; ++t)
    threads.emplace_back([&] {
      for (;;) {
        try {
          __wrap_pthread_once(&once, fail_first_two);
          if (runs.load() != 1) returned_before_done.fetch_add(1);
          return;
        } catch (const std::runtime_error&) {
          threw.fetch_add(1);
        }
      }
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(runs.load(), 1);
  EXPECT_EQ(attempts.load(), 3);
  EXPECT_EQ(threw.load(), 1);
  EXPECT_EQ(returned_before_done.load(), 0);
}

TEST(QuietOnce, SharesGlibcsDoneValue) {
  runs = 0;
  pthread_once_t ours = PTHREAD_ONCE_INIT, theirs = PTHREAD_ONCE_INIT;
  __wrap_pthread_once(&ours, count_run);
  pthread_once(&ours, count_run);  // glibc's: sees it done
  pthread_once(&theirs, count_run);
  __wrap_pthread_once(&theirs, count_run);  // ours: sees glibc's done
  EXPECT_EQ(runs.load(), 2);
}

}  // namespace
