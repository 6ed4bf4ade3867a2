// SPDX-License-Identifier: GPL-3.0-or-later
// Large vectors sized on one thread, their pages first touched on every thread. A vector of
// objects that are not trivial (a scene's faces, the OBJ reader's polygons) can only be sized by
// its own resize(), on the calling thread; on a fresh allocation, most of that call is the
// kernel clearing each page at its first write (on the 2-core benchmark host about 0.6 GB/s:
// a million faces' 168 MB of Face took 0.3 s of one thread while the other waited). Touching the
// new storage's pages on every thread first leaves the resize its stores alone.
#pragma once

#include "runtime/parallel.hpp"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace shadow::runtime {

/// Writes one byte of every 4 KiB page of [begin, begin + bytes) on `threads` threads, so that
/// the kernel maps them there. Only for storage that holds no object yet (the bytes written are
/// garbage to whatever constructs there next). Small ranges are left to their first writer.
inline void touch_pages(void* begin, std::size_t bytes, unsigned threads) {
  constexpr std::size_t kPage = 4096;
  constexpr std::size_t kPagesPerBlock = 512;  // 2 MiB: one transparent huge page's worth
  threads = std::min(resolve_threads(threads), kMaxThreads);
  if (begin == nullptr || bytes < 2 * kPagesPerBlock * kPage || threads < 2) return;
  auto* const bytes_at = static_cast<volatile char*>(begin);
  const std::size_t pages = (bytes + kPage - 1) / kPage;
  parallel_for_blocks(pages, kPagesPerBlock, threads, [&](unsigned, std::size_t, std::size_t first, std::size_t end) {
    for (std::size_t p = first; p < end; ++p) bytes_at[p * kPage] = 0;
  });
  bytes_at[bytes - 1] = 0;  // (the last page, where `begin` is not page-aligned)
}

/// v.resize(n) after reserving room for n elements and touching the new elements' pages on
/// `threads` threads (touch_pages): the same vector, its pages faulted in parallel. The room
/// grows at least twofold, as resize's own does, so that a vector grown by many calls (a scene
/// read one mesh file after another) is not moved whole each time.
template <class T, class Allocator>
void resize_touched(std::vector<T, Allocator>& v, std::size_t n, unsigned threads) {
  if (n > v.size()) {
    if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
    // The storage past size() holds no object yet: its pages can be touched before resize().
    touch_pages(v.data() + v.size(), (n - v.size()) * sizeof(T), threads);
  }
  v.resize(n);
}

}  // namespace shadow::runtime
