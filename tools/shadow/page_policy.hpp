// SPDX-License-Identifier: GPL-3.0-or-later
// How a stage's memory is paged. The programs ask jemalloc for transparent huge pages on all of
// their memory (tools/allocator/jemalloc_conf.cpp): the engine revisits its prepared faces and
// light-space grids for every receiver (and `shadow series` for thousands of instants), where a
// 2 MiB page saves TLB misses. Reading a scene and writing its result touch their memory about
// once; there the cheaper page size depends on the host, by a factor of 2 to 30 either way:
//  - on some virtual machines the kernel clears a huge page whole, out of cache and slowly (2.6 GB
//    of huge pages cost a million faces 3.7-5.5 s of system time where 4 KiB pages cost 1.9 s);
//  - on others every 4 KiB fault is a trip through the hypervisor (10 us each, 5 ms for 2 MiB
//    where one huge page takes 0.15 ms): there small pages cost a million faces 2 s.
// So `shadow compute` measures the two on its host once (twice 256 KiB and 2 MiB: 2-8 ms) and
// reads and writes on the cheaper, with LIBSHADOW_PAGES=small|huge to choose without the probe
// (any other value: the probe). Linux only; elsewhere small pages, as the prctl below.
// jemalloc also hands the pages of freed blocks back to the kernel over its decay time (10 s),
// much of them within a run of a few seconds, so what the OBJ parse frees is cleared afresh for
// the scene's arrays (a million faces: 2.6 GB cleared for a peak of 1.1 GB). So the stages that
// touch their memory once keep their freed blocks meanwhile, on either page size
// (docs/benchmarks.md, "Twenty-third look" and "Twenty-eighth look").
#pragma once

#include <dlfcn.h>
#if defined(__linux__)
#include <sys/prctl.h>
#endif
#include <sys/types.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace shadow_cli {

/// jemalloc's control call where the program runs on jemalloc (our builds link it, or it is
/// preloaded), looked up at run time; null with another allocator.
using AllocatorControl = int (*)(const char*, void*, std::size_t*, void*, std::size_t);
inline AllocatorControl allocator_control() {
  return reinterpret_cast<AllocatorControl>(::dlsym(RTLD_DEFAULT, "mallctl"));
}

/// The process's transparent-huge-page mode (prctl's PR_GET_THP_DISABLE: 0 where huge pages may
/// be given, 1 where not; newer kernels add flags), or -1 where it cannot be read.
inline int huge_page_mode() {
#if defined(__linux__) && defined(PR_GET_THP_DISABLE)
  return prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0);
#else
  return -1;
#endif
}

/// Sets the mode huge_page_mode() read (1: 4 KiB pages only for memory first touched from here
/// on, the kernel then ignoring the allocator's MADV_HUGEPAGE; 0: huge pages where asked). Where
/// the call is not available or fails, nothing changes but the speed.
inline void set_huge_page_mode(int mode) {
#if defined(__linux__) && defined(PR_SET_THP_DISABLE)
  if (mode >= 0) (void)prctl(PR_SET_THP_DISABLE, mode & 1, mode & ~1, 0, 0);
#else
  (void)mode;
#endif
}

/// A transparent huge page on x86-64: the probe's unit.
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// What first touching 2 MiB costs this process on each page size, in seconds (negative where
/// it could not be measured: no anonymous memory, or madvise refused).
struct PageCosts {
  double small = -1;  ///< 4 KiB pages, each cleared by the kernel at its first write (64 timed, x 8)
  double huge = -1;   ///< one transparent huge page, where the kernel gives one (else small ones)
};

/// Writes through `bytes` (at most 2 MiB) of fresh memory page by page, as a reader filling its
/// arrays does, on the page size asked for, and returns the seconds it took (-1 where the memory
/// was refused).
inline double time_first_touch(bool huge, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE) && defined(MADV_NOHUGEPAGE)
  constexpr std::size_t kHuge = kHugePageBytes;
  void* raw = ::mmap(nullptr, 2 * kHuge, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) return -1;
  // (aligned to 2 MiB, so that one huge page can cover it)
  auto* block = reinterpret_cast<char*>((reinterpret_cast<std::uintptr_t>(raw) + kHuge - 1) & ~(kHuge - 1));
  double seconds = -1;
  if (::madvise(block, kHuge, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE) == 0) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t offset = 0; offset < std::min(bytes, kHuge); offset += 4096) std::memset(block + offset, 1, 4096);
    asm volatile("" : : "r"(block) : "memory");  // (the writes are not dead stores)
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  ::munmap(raw, 2 * kHuge);
  return seconds;
#else
  (void)huge;
  (void)bytes;
  return -1;
#endif
}

/// Both costs, measured now: the mean of two rounds, small then huge. Small pages are timed on
/// 256 KiB (64 faults; each costs the same) and scaled to 2 MiB, a huge page whole: about 2 ms
/// on a host whose small pages fault at 10 us, 4-8 ms on one whose huge pages clear at 1 GB/s.
/// The first huge page a process touches may wait for the kernel to find or make one (up to
/// 7 ms here), and a host that clears fresh huge pages slowly shows it only on the first: the
/// mean keeps it at half weight, where the minimum would hide such a host.
inline PageCosts measure_page_costs() {
  constexpr std::size_t kSmallSample = std::size_t{256} << 10;
  PageCosts costs{0, 0};
  for (int round = 0; round < 2; ++round) {
    const double small = time_first_touch(false, kSmallSample), huge = time_first_touch(true, kHugePageBytes);
    if (small < 0 || huge < 0) return PageCosts{};
    costs.small += 8 * small / 2;
    costs.huge += huge / 2;
  }
  return costs;
}

/// Whether memory touched about once should come on 4 KiB pages: LIBSHADOW_PAGES=small or huge
/// where set, else the page size the probe found cheaper a byte (small where it could not tell).
/// Measured once a process.
inline bool small_pages_for_touched_once() {
  static const bool small = [] {
    if (const char* choice = std::getenv("LIBSHADOW_PAGES")) {
      if (std::strcmp(choice, "small") == 0) return true;
      if (std::strcmp(choice, "huge") == 0) return false;
    }
    const PageCosts costs = measure_page_costs();
    return !(costs.small > 0 && costs.huge > 0 && costs.huge < costs.small);
  }();
  return small;
}

/// A stage whose memory is touched about once (reading a scene, writing a result): while it
/// lasts, 4 KiB pages where asked (small_pages_for_touched_once()), and jemalloc keeps the pages
/// this process frees for its own later allocations instead of handing them back to the kernel
/// (decay -1 on every arena made so far and, as their default, on those made later): no page is
/// cleared twice. end() (or the destructor) puts the page mode and each arena's decay back for
/// the stages that revisit their memory (arenas made during the stage get the default; the CLI
/// makes them all at its start, prepare_allocator_arenas). Kept through preparing and computing
/// as well, the two cost a 10,000-box city's polygons 3-5%. Without jemalloc, only the page
/// size is set.
class TouchedOnceStage {
 public:
  /// On 4 KiB pages.
  TouchedOnceStage() : TouchedOnceStage(true) {}
  /// On 4 KiB pages where `small_pages`, else on the page size the process had.
  explicit TouchedOnceStage(bool small_pages) : control_(allocator_control()) {
    // (Everything that may throw before the process is changed.)
    unsigned arenas = 0;
    std::size_t count_size = sizeof arenas;
    std::size_t size = sizeof(ssize_t);
    const bool decays = control_ != nullptr && control_("arenas.dirty_decay_ms", &default_[0], &size, nullptr, 0) == 0 &&
                        control_("arenas.muzzy_decay_ms", &default_[1], &size, nullptr, 0) == 0 &&
                        control_("arenas.narenas", &arenas, &count_size, nullptr, 0) == 0;
    if (decays) saved_.assign(std::size_t{2} * arenas, kUnread);
    mode_before_ = huge_page_mode();
    if (small_pages) set_huge_page_mode(1);
    if (!decays) return;
    for (unsigned a = 0; a < arenas; ++a)  // (arenas not made yet answer an error: nothing to do)
      for (int kind = 0; kind < 2; ++kind) {
        ssize_t never = -1, old = 0;
        std::size_t old_size = sizeof old;
        if (control_(DecayName(a, kind).text, &old, &old_size, &never, sizeof never) == 0) saved_[2 * a + kind] = old;
      }
    set_defaults(-1, -1);
    active_ = true;
  }
  TouchedOnceStage(const TouchedOnceStage&) = delete;
  TouchedOnceStage& operator=(const TouchedOnceStage&) = delete;
  ~TouchedOnceStage() { end(); }

  /// Puts back what the stage changed (once; allocates nothing).
  void end() noexcept {
    if (ended_) return;
    ended_ = true;
    set_huge_page_mode(mode_before_);
    if (!active_) return;
    set_defaults(default_[0], default_[1]);
    const std::size_t saved_arenas = saved_.size() / 2;
    unsigned arenas = static_cast<unsigned>(saved_arenas);
    std::size_t count_size = sizeof arenas;
    (void)control_("arenas.narenas", &arenas, &count_size, nullptr, 0);
    for (unsigned a = 0; a < arenas; ++a)
      for (int kind = 0; kind < 2; ++kind) {
        ssize_t value = a < saved_arenas ? saved_[2 * a + kind] : kUnread;
        if (value == kUnread) value = default_[kind];
        (void)control_(DecayName(a, kind).text, nullptr, nullptr, &value, sizeof value);
      }
  }

 private:
  static constexpr ssize_t kUnread = -2;
  struct DecayName {  // "arena.<a>.dirty_decay_ms" or "...muzzy...", without the heap
    DecayName(unsigned arena, int kind) {
      std::snprintf(text, sizeof text, "arena.%u.%s_decay_ms", arena, kind == 0 ? "dirty" : "muzzy");
    }
    char text[48];
  };
  void set_defaults(ssize_t dirty, ssize_t muzzy) const {
    (void)control_("arenas.dirty_decay_ms", nullptr, nullptr, &dirty, sizeof dirty);
    (void)control_("arenas.muzzy_decay_ms", nullptr, nullptr, &muzzy, sizeof muzzy);
  }

  AllocatorControl control_;
  int mode_before_ = -1;
  bool ended_ = false;
  bool active_ = false;  // decay times changed (jemalloc there)
  ssize_t default_[2] = {0, 0};
  std::vector<ssize_t> saved_;  // each arena's dirty and muzzy decay before the stage
};

}  // namespace shadow_cli
