// SPDX-License-Identifier: GPL-3.0-or-later
// How a stage's memory is paged. The programs ask jemalloc for transparent huge pages on all of
// their memory (tools/allocator/jemalloc_conf.cpp): the engine revisits its prepared faces and
// light-space grids for every receiver (and `shadow series` for thousands of instants), where a
// 2 MiB page saves TLB misses. Reading a scene and writing its result touch their memory about
// once, and there a huge page only costs: the kernel clears all 2 MiB at the first touch, out
// of cache, before the program writes it again. jemalloc also hands freed blocks back to the
// kernel (at once for blocks of 8 MiB and more), so what the OBJ parse frees is cleared afresh
// for the scene's arrays (a million faces: 2.6 GB cleared for a peak of 1.1 GB). So `shadow
// compute` reads and writes on 4 KiB pages and keeps its freed blocks meanwhile, and prepares
// and computes as before. A million faces, fast, 2 threads, side by side: 6.9-8.9 s before
// (huge pages cleared at the host's varying speed), 6.2-6.8 s after, the same peak; the scene's
// own arrays, read on small pages, cost a 10,000-box city's polygons 2-3% in the shadows (the
// engine revisits them) (docs/benchmarks.md, "Twenty-third look").
#pragma once

#if defined(__linux__)
#include <sys/prctl.h>
#endif

#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

// jemalloc's control call, where the program links jemalloc (LIBSHADOW_USE_JEMALLOC); null
// otherwise (a weak reference: the program then runs on the C library's allocator as it is).
extern "C" int mallctl(const char* name, void* oldp, std::size_t* oldlenp, void* newp, std::size_t newlen)
    __attribute__((weak));

namespace shadow_cli {

/// Whether memory first touched from here on gets 4 KiB pages only (prctl's PR_SET_THP_DISABLE:
/// the kernel then ignores the allocator's MADV_HUGEPAGE). Where the calls are not available or
/// fail, nothing changes but the speed.
inline bool small_pages_only() {
#if defined(__linux__) && defined(PR_GET_THP_DISABLE)
  return prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0) == 1;
#else
  return false;
#endif
}

inline void set_small_pages_only(bool small) {
#if defined(__linux__) && defined(PR_SET_THP_DISABLE)
  (void)prctl(PR_SET_THP_DISABLE, small ? 1 : 0, 0, 0, 0);
#else
  (void)small;
#endif
}

/// A stage whose memory is touched about once (reading a scene, writing a result): while it
/// lasts, 4 KiB pages, and jemalloc keeps the pages this process frees for its own later
/// allocations instead of handing them back to the kernel (decay -1 on the arenas made so far
/// and, as their default, on those made later, the one for blocks of 8 MiB and more among
/// them): no page is cleared twice. end() (or the destructor) puts huge pages and each arena's
/// decay back for the stages that revisit their memory (arenas made during the stage get
/// jemalloc's default; kept through preparing and computing as well, the two cost a 10,000-box
/// city's polygons 5%). Without jemalloc, only the page size is set.
class TouchedOnceStage {
 public:
  TouchedOnceStage() : small_pages_before_(small_pages_only()) {
    set_small_pages_only(true);
    if (mallctl == nullptr) return;
    std::size_t size = sizeof(ssize_t);
    if (mallctl("arenas.dirty_decay_ms", &default_[0], &size, nullptr, 0) != 0 ||
        mallctl("arenas.muzzy_decay_ms", &default_[1], &size, nullptr, 0) != 0)
      return;
    std::size_t count_size = sizeof arenas_;
    if (mallctl("arenas.narenas", &arenas_, &count_size, nullptr, 0) != 0) return;
    saved_.assign(std::size_t{2} * arenas_, kUnread);
    for (unsigned a = 0; a < arenas_; ++a)  // (arenas not made yet answer an error: nothing to do)
      for (int kind = 0; kind < 2; ++kind) {
        const std::string name = decay_name(a, kind);
        ssize_t never = -1, old = 0;
        std::size_t old_size = sizeof old;
        if (mallctl(name.c_str(), &old, &old_size, &never, sizeof never) == 0) saved_[2 * a + kind] = old;
      }
    set_defaults(-1, -1);
    active_ = true;
  }
  TouchedOnceStage(const TouchedOnceStage&) = delete;
  TouchedOnceStage& operator=(const TouchedOnceStage&) = delete;
  ~TouchedOnceStage() { end(); }

  void end() {
    if (ended_) return;
    ended_ = true;
    set_small_pages_only(small_pages_before_);
    if (!active_) return;
    active_ = false;
    set_defaults(default_[0], default_[1]);
    // Arenas made during the stage took -1 as their default: they get the default back.
    unsigned arenas = arenas_;
    std::size_t count_size = sizeof arenas;
    (void)mallctl("arenas.narenas", &arenas, &count_size, nullptr, 0);
    for (unsigned a = 0; a < arenas; ++a)
      for (int kind = 0; kind < 2; ++kind) {
        ssize_t value = a < arenas_ ? saved_[2 * a + kind] : default_[kind];
        if (value == kUnread) value = default_[kind];
        (void)mallctl(decay_name(a, kind).c_str(), nullptr, nullptr, &value, sizeof value);
      }
  }

 private:
  static constexpr ssize_t kUnread = -2;
  static std::string decay_name(unsigned arena, int kind) {
    return "arena." + std::to_string(arena) + (kind == 0 ? ".dirty_decay_ms" : ".muzzy_decay_ms");
  }
  static void set_defaults(ssize_t dirty, ssize_t muzzy) {
    (void)mallctl("arenas.dirty_decay_ms", nullptr, nullptr, &dirty, sizeof dirty);
    (void)mallctl("arenas.muzzy_decay_ms", nullptr, nullptr, &muzzy, sizeof muzzy);
  }

  bool small_pages_before_;
  bool ended_ = false;
  bool active_ = false;  // decay times changed (jemalloc there)
  unsigned arenas_ = 0;
  ssize_t default_[2] = {0, 0};
  std::vector<ssize_t> saved_;  // each arena's dirty and muzzy decay before the stage
};

}  // namespace shadow_cli
