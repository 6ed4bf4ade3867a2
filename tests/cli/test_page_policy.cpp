// SPDX-License-Identifier: GPL-3.0-or-later
// The page policy of `shadow compute` (tools/shadow/page_policy.hpp): after it, the process
// gets no transparent huge pages, and a large block it frees is used again without fresh page
// faults. Each test runs in a process of its own (gtest_discover_tests), so the policy set here
// stays here.
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

}  // namespace

TEST(PagePolicy, ComputeRunsOnSmallPages) {
  shadow_cli::prefer_small_pages();
  std::ifstream status("/proc/self/status");
  std::string line;
  bool seen = false;
  while (std::getline(status, line))
    if (line.rfind("THP_enabled:", 0) == 0) {
      seen = true;
      EXPECT_NE(line.find('0'), std::string::npos) << line;
    }
  if (!seen) GTEST_SKIP() << "this kernel does not say whether a process may have huge pages";
}

TEST(PagePolicy, AFreedLargeBlockIsUsedAgainWithoutFreshPages) {
  if (mallctl == nullptr) GTEST_SKIP() << "not linked with jemalloc: the C library's allocator as it is";
  shadow_cli::prefer_small_pages();
  shadow_cli::keep_freed_pages();
  ssize_t decay = 0;
  std::size_t size = sizeof decay;
  ASSERT_EQ(mallctl("arenas.dirty_decay_ms", &decay, &size, nullptr, 0), 0);
  EXPECT_EQ(decay, -1);
  ASSERT_EQ(mallctl("arena.0.dirty_decay_ms", &decay, &size, nullptr, 0), 0);
  EXPECT_EQ(decay, -1);
  // 64 MiB (above jemalloc's 8 MiB, where blocks were handed back at once): 16,384 pages the
  // first time, next to none the second.
  constexpr std::size_t kBlock = std::size_t{64} << 20;
  const long first = faults_of_one_block(kBlock);
  const long second = faults_of_one_block(kBlock);
  EXPECT_GE(first, 8000);
  EXPECT_LT(second, first / 10) << "first " << first << " faults, second " << second;
}
