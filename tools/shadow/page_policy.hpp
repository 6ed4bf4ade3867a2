// SPDX-License-Identifier: GPL-3.0-or-later
// How a stage's memory is paged. The programs ask jemalloc for transparent huge pages on all of
// their memory (tools/allocator/jemalloc_conf.cpp): the engine revisits its prepared faces and
// light-space grids for every receiver (and `shadow series` for thousands of instants), where a
// 2 MiB page saves TLB misses. Reading a scene and writing its result touch their memory about
// once, and there a huge page only costs: the kernel clears all 2 MiB at the first touch, out
// of cache, before the program writes it again. jemalloc also hands the pages of freed blocks
// back to the kernel over its decay time (10 s), much of them within a run of a few seconds, so
// what the OBJ parse frees is cleared afresh for the scene's arrays (a million faces: 2.6 GB
// cleared for a peak of 1.1 GB). So `shadow compute` reads and writes on 4 KiB pages and keeps
// its freed blocks meanwhile, and prepares and computes as before. A million faces, fast, 2
// threads, side by side: 6.9-8.9 s before (huge pages cleared at the host's varying speed),
// 6.2-6.8 s after, the same peak; the scene's own arrays, read on small pages, cost a
// 10,000-box city's polygons 2-3% in the shadows (the engine revisits them)
// (docs/benchmarks.md, "Twenty-third look").
#pragma once

#include <dlfcn.h>
#if defined(__linux__)
#include <sys/prctl.h>
#endif
#include <sys/types.h>

#include <cstddef>
#include <cstdio>
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

/// A stage whose memory is touched about once (reading a scene, writing a result): while it
/// lasts, 4 KiB pages, and jemalloc keeps the pages this process frees for its own later
/// allocations instead of handing them back to the kernel (decay -1 on every arena made so far
/// and, as their default, on those made later): no page is cleared twice. end() (or the
/// destructor) puts the page mode and each arena's decay back for the stages that revisit their
/// memory (arenas made during the stage get the default; the CLI makes them all at its start,
/// prepare_allocator_arenas). Kept through preparing and computing as well, the two cost a
/// 10,000-box city's polygons 3-5%. Without jemalloc, only the page size is set.
class TouchedOnceStage {
 public:
  TouchedOnceStage() : control_(allocator_control()) {
    // (Everything that may throw before the process is changed.)
    unsigned arenas = 0;
    std::size_t count_size = sizeof arenas;
    std::size_t size = sizeof(ssize_t);
    const bool decays = control_ != nullptr && control_("arenas.dirty_decay_ms", &default_[0], &size, nullptr, 0) == 0 &&
                        control_("arenas.muzzy_decay_ms", &default_[1], &size, nullptr, 0) == 0 &&
                        control_("arenas.narenas", &arenas, &count_size, nullptr, 0) == 0;
    if (decays) saved_.assign(std::size_t{2} * arenas, kUnread);
    mode_before_ = huge_page_mode();
    set_huge_page_mode(1);
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
