// SPDX-License-Identifier: GPL-3.0-or-later
// The page policy of `shadow compute`'s reading and writing (tools/shadow/page_policy.hpp):
// during such a stage the process gets no transparent huge pages and a large block it frees is
// used again without fresh page faults; after it, what was there before. Each test runs in a
// process of its own (gtest_discover_tests).
#include "page_policy.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

namespace {

long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

/// A block of `size` bytes, written through once (every page touched), then freed.
long faults_of_one_block(std::size_t size) {
  const long before = minor_faults();
  auto* block = static_cast<char*>(std::malloc(size));
  EXPECT_NE(block, nullptr);
  if (block == nullptr) return 0;
  std::memset(block, 1, size);
  // (the block escapes here, so the compiler cannot take the writes away as dead stores)
  asm volatile("" : : "r"(block) : "memory");
  std::free(block);
  return minor_faults() - before;
}

/// The process's THP_enabled line (1: it may have huge pages), or -1 where the kernel has none.
int thp_enabled() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("THP_enabled:", 0) == 0) return line.find('1') != std::string::npos ? 1 : 0;
  return -1;
}

ssize_t decay(const char* name) {
  ssize_t value = -3;
  std::size_t size = sizeof value;
  EXPECT_EQ(mallctl(name, &value, &size, nullptr, 0), 0) << name;
  return value;
}

}  // namespace

TEST(PagePolicy, ATouchedOnceStageRunsOnSmallPagesAndPutsBackWhatWasThere) {
  const int before = thp_enabled();
  if (before < 0) GTEST_SKIP() << "this kernel does not say whether a process may have huge pages";
  {
    shadow_cli::TouchedOnceStage stage;
    EXPECT_EQ(thp_enabled(), 0);
  }
  EXPECT_EQ(thp_enabled(), before);
  // A process that had huge pages turned off keeps them off after a stage.
  shadow_cli::set_small_pages_only(true);
  { shadow_cli::TouchedOnceStage stage; }
  EXPECT_EQ(thp_enabled(), 0);
  shadow_cli::set_small_pages_only(false);
  EXPECT_EQ(thp_enabled(), 1);
}

TEST(PagePolicy, AFreedLargeBlockIsUsedAgainWithoutFreshPagesDuringTheStageOnly) {
  if (mallctl == nullptr) GTEST_SKIP() << "not linked with jemalloc: the C library's allocator as it is";
  const ssize_t dirty = decay("arenas.dirty_decay_ms"), arena0 = decay("arena.0.dirty_decay_ms");
  // 64 MiB (above jemalloc's 8 MiB, where blocks are handed back at once): 16,384 pages the
  // first time, next to none the second.
  constexpr std::size_t kBlock = std::size_t{64} << 20;
  {
    shadow_cli::TouchedOnceStage stage;
    EXPECT_EQ(decay("arenas.dirty_decay_ms"), -1);
    EXPECT_EQ(decay("arena.0.dirty_decay_ms"), -1);
    const long first = faults_of_one_block(kBlock);
    const long second = faults_of_one_block(kBlock);
    EXPECT_GE(first, 8000);
    EXPECT_LT(second, first / 10) << "first " << first << " faults, second " << second;
  }
  EXPECT_EQ(decay("arenas.dirty_decay_ms"), dirty);
  EXPECT_EQ(decay("arena.0.dirty_decay_ms"), arena0);
}
