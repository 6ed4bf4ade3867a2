// SPDX-License-Identifier: GPL-3.0-or-later
// How a subcommand's memory is paged. The programs ask jemalloc for transparent huge pages on
// all of their memory (tools/allocator/jemalloc_conf.cpp): `shadow series` revisits the
// prepared faces, the light-space grids and its table for thousands of instants, where a 2 MiB
// page saves the TLB misses. `shadow compute` touches most of its memory once (a million faces:
// read, prepared, computed, written), and there a huge page only
// costs more: the kernel clears all 2 MiB at the first touch, out of cache, before the program
// writes it again. And jemalloc hands freed pages back to the kernel (at once for blocks of
// 8 MiB and more), so memory freed by one stage is cleared afresh for the next (2.6 GB cleared
// for a peak of 1.1 GB): `shadow compute` keeps it instead. A million faces on the 2-core
// machine, side by side: 8.4-10.1 s before, 7.2-7.4 s after, 1.34 GB peak against 1.13
// (docs/benchmarks.md, "Twenty-third look").
#pragma once

#if defined(__linux__)
#include <sys/prctl.h>
#endif

#include <sys/types.h>

#include <cstddef>
#include <string>

// jemalloc's control call, where the program links jemalloc (LIBSHADOW_USE_JEMALLOC); null
// otherwise (a weak reference: the program then runs on the C library's allocator as it is).
extern "C" int mallctl(const char* name, void* oldp, std::size_t* oldlenp, void* newp, std::size_t newlen)
    __attribute__((weak));

namespace shadow_cli {

/// Keeps this process on 4 KiB pages from here on (prctl's PR_SET_THP_DISABLE: the kernel then
/// ignores the allocator's MADV_HUGEPAGE). For subcommands that touch their memory once. Where
/// the call is not available or fails, nothing changes but the speed.
inline void prefer_small_pages() {
#if defined(__linux__) && defined(PR_SET_THP_DISABLE)
  (void)prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0);
#endif
}

/// Lets jemalloc keep the pages this process frees for its own later allocations instead of
/// handing them back to the kernel (decay -1 on the arenas made so far and, as their default,
/// on those made later, the one for blocks of 8 MiB and more among them). The peak grows by
/// what the freed blocks hold (a million faces: 1.09 to 1.34 GB); no page is cleared twice.
/// For subcommands that end when their one computation is written.
inline void keep_freed_pages() {
  if (mallctl == nullptr) return;
  ssize_t never = -1;
  (void)mallctl("arenas.dirty_decay_ms", nullptr, nullptr, &never, sizeof never);
  (void)mallctl("arenas.muzzy_decay_ms", nullptr, nullptr, &never, sizeof never);
  unsigned arenas = 0;
  std::size_t size = sizeof arenas;
  if (mallctl("arenas.narenas", &arenas, &size, nullptr, 0) != 0) return;
  for (unsigned a = 0; a < arenas; ++a)  // (arenas not made yet answer an error: nothing to do)
    for (const char* kind : {"dirty", "muzzy"}) {
      const std::string name = "arena." + std::to_string(a) + "." + kind + "_decay_ms";
      (void)mallctl(name.c_str(), nullptr, nullptr, &never, sizeof never);
    }
}

}  // namespace shadow_cli
