// SPDX-License-Identifier: GPL-3.0-or-later
// The page policy of `shadow compute`'s reading and writing (tools/shadow/page_policy.hpp):
// during such a stage on small pages the process gets no transparent huge pages, and on either
// size a large block it frees is used again without fresh page faults; after it, what was there
// before. Which size the stage asks for is measured on the host (a probe) or chosen with
// LIBSHADOW_PAGES. Each test runs in a process of its own (gtest_discover_tests).
#include "page_policy.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

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

/// The page faults of a block of `size` bytes, written through once (every page touched), then
/// freed.
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

/// The process's THP_enabled line (1: it may have huge pages), or -1 where the kernel (older
/// than 5.0) does not print it.
int thp_enabled() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("THP_enabled:", 0) == 0) return line.find('1') != std::string::npos ? 1 : 0;
  return -1;
}

ssize_t decay(shadow_cli::AllocatorControl control, const char* name) {
  ssize_t value = -3;
  std::size_t size = sizeof value;
  EXPECT_EQ(control(name, &value, &size, nullptr, 0), 0) << name;
  return value;
}

}  // namespace

TEST(PagePolicy, ATouchedOnceStageRunsOnSmallPagesAndPutsBackWhatWasThere) {
  const int before = thp_enabled();
  if (before < 0) GTEST_SKIP() << "this kernel's /proc/self/status has no THP_enabled line (before Linux 5.0)";
  const int mode = shadow_cli::huge_page_mode();
  {
    shadow_cli::TouchedOnceStage stage;
    EXPECT_EQ(thp_enabled(), 0);
  }
  EXPECT_EQ(thp_enabled(), before);
  EXPECT_EQ(shadow_cli::huge_page_mode(), mode);
  if (before != 1) return;  // (huge pages were off for this process already)
  // A process that had huge pages turned off keeps them off after a stage.
  shadow_cli::set_huge_page_mode(1);
  { shadow_cli::TouchedOnceStage stage; }
  EXPECT_EQ(thp_enabled(), 0);
  shadow_cli::set_huge_page_mode(mode);
  EXPECT_EQ(thp_enabled(), 1);
}

TEST(PagePolicy, AFreedLargeBlockIsUsedAgainWithoutFreshPagesDuringTheStageOnly) {
  const shadow_cli::AllocatorControl control = shadow_cli::allocator_control();
  if (control == nullptr) GTEST_SKIP() << "not on jemalloc: the C library's allocator as it is";
  const ssize_t dirty = decay(control, "arenas.dirty_decay_ms"), arena0 = decay(control, "arena.0.dirty_decay_ms");
  // 64 MiB: 16,384 pages of 4 KiB the first time, next to none the second.
  constexpr std::size_t kBlock = std::size_t{64} << 20;
  const long pages = static_cast<long>(kBlock / static_cast<std::size_t>(sysconf(_SC_PAGESIZE)));
  {
    shadow_cli::TouchedOnceStage stage;
    EXPECT_EQ(decay(control, "arenas.dirty_decay_ms"), -1);
    EXPECT_EQ(decay(control, "arena.0.dirty_decay_ms"), -1);
    if (thp_enabled() != 0) GTEST_SKIP() << "huge pages could not be turned off: page faults not counted";
    const long first = faults_of_one_block(kBlock);
    const long second = faults_of_one_block(kBlock);
    EXPECT_GE(first, pages / 2);
    EXPECT_LT(second, first / 10) << "first " << first << " faults, second " << second;
  }
  EXPECT_EQ(decay(control, "arenas.dirty_decay_ms"), dirty);
  EXPECT_EQ(decay(control, "arena.0.dirty_decay_ms"), arena0);
}

TEST(PagePolicy, AStageOnHugePagesLeavesTheHugePageModeAlone) {
  const int before = thp_enabled();
  if (before < 0) GTEST_SKIP() << "this kernel's /proc/self/status has no THP_enabled line (before Linux 5.0)";
  {
    shadow_cli::TouchedOnceStage stage(/*small_pages=*/false);
    EXPECT_EQ(thp_enabled(), before);
  }
  EXPECT_EQ(thp_enabled(), before);
}

TEST(PagePolicy, TheProbeTimesBothPageSizes) {
  const shadow_cli::PageCosts costs = shadow_cli::measure_page_costs();
  if (costs.small < 0 || costs.huge < 0) GTEST_SKIP() << "no transparent huge pages to ask for (madvise refused)";
  // 2 MiB written page by page takes some time, and far less than ten seconds, on either size.
  EXPECT_GT(costs.small, 0.0);
  EXPECT_GT(costs.huge, 0.0);
  EXPECT_LT(costs.small, 10.0);
  EXPECT_LT(costs.huge, 10.0);
}

TEST(PagePolicy, AnEnvironmentVariableChoosesThePageSizeWithoutTheProbe) {
  // (the choice is made once a process: this test's process makes it here)
  ASSERT_EQ(::setenv("LIBSHADOW_PAGES", "huge", 1), 0);
  const long before = minor_faults();
  EXPECT_FALSE(shadow_cli::small_pages_for_touched_once());
  // The probe would fault in at least 64 small pages and a huge one.
  EXPECT_LT(minor_faults() - before, 16) << "the probe ran";
  ASSERT_EQ(::setenv("LIBSHADOW_PAGES", "small", 1), 0);
  EXPECT_FALSE(shadow_cli::small_pages_for_touched_once()) << "measured once a process";
  ::unsetenv("LIBSHADOW_PAGES");
}

TEST(PagePolicy, SmallPagesAskedForAreSmallPages) {
  ASSERT_EQ(::setenv("LIBSHADOW_PAGES", "small", 1), 0);
  EXPECT_TRUE(shadow_cli::small_pages_for_touched_once());
  ::unsetenv("LIBSHADOW_PAGES");
}
