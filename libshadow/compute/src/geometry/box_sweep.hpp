// SPDX-License-Identifier: GPL-3.0-or-later
// Every two axis-aligned boxes that overlap, by one sort and a read-only scan, and such pairs as
// lists of neighbours: the fast path's clusters of casts (fast/cluster_union.hpp) and the exact
// union's neighbours (exact/convex_union_area.hpp), on their own coordinates (integers, doubles).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace shadow::geometry {

/// A box in the sweep's order, with the extents its tests read (no look-up through an index).
template <class T>
struct BoxSweepEntry {
  T lo, hi;              ///< extent in the sweep's axis
  T lo_across, hi_across;
  std::size_t index;
};

/// sweep_boxes' `passed` where the caller never has done with a box.
struct NonePassed {
  constexpr bool operator()(std::size_t) const { return false; }
};

/// Calls pair(later, earlier) for every two of `boxes` (with members x0, y0, x1, y1) that
/// overlap: with positive extent along both axes, or with `Closed` touching too. Along x, or
/// along y with `AlongY`: each box against the boxes after it in the order of their lower ends
/// (ties by index) that start before it ends; a box then meets a later one exactly when a sweep
/// with a list of open boxes would still hold it at the later one's lower end, so the pairs are
/// those (open: a box of zero extent at another's lower end in the sweep's axis is reported
/// too; along the other axis the pairs are the same, in another order). `sorted` is scratch.
///
/// `passed(index)`, where given, says a box needs no more pairs (the caller has done with it):
/// from then on none of its pairs is reported, and the boxes after it are not scanned for it.
template <bool AlongY, bool Closed, class Box, class T, class Pair, class Passed = NonePassed>
void sweep_boxes(const std::vector<Box>& boxes, std::vector<BoxSweepEntry<T>>& sorted, Pair&& pair,
                 Passed&& passed = {}) {
  using Entry = BoxSweepEntry<T>;
  sorted.resize(boxes.size());
  for (std::size_t a = 0; a < boxes.size(); ++a) {
    const Box& b = boxes[a];
    sorted[a] = AlongY ? Entry{b.y0, b.y1, b.x0, b.x1, a} : Entry{b.x0, b.x1, b.y0, b.y1, a};
  }
  std::sort(sorted.begin(), sorted.end(), [](const Entry& a, const Entry& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.index < b.index;
  });
  const std::size_t n = sorted.size();
  for (std::size_t a = 0; a < n; ++a) {
    const Entry& p = sorted[a];
    if (passed(p.index)) continue;
    for (std::size_t b = a + 1; b < n; ++b) {
      const Entry& q = sorted[b];
      if (Closed ? q.lo > p.hi : q.lo >= p.hi) break;  // this one and every later one start after p ends
      if (Closed ? p.hi_across >= q.lo_across && q.hi_across >= p.lo_across
                 : p.hi_across > q.lo_across && q.hi_across > p.lo_across) {
        if (passed(q.index)) continue;
        pair(q.index, p.index);
        if (passed(p.index)) break;
      }
    }
  }
}

/// The pairs (a[k], b[k]) of n items as lists of neighbours, both ways: item p's are
/// list[start[p]] .. list[start[p + 1]], in the pairs' order. `fill` is scratch.
inline void neighbour_lists(const std::vector<std::size_t>& a, const std::vector<std::size_t>& b, std::size_t n,
                            std::vector<std::size_t>& start, std::vector<std::size_t>& list,
                            std::vector<std::size_t>& fill) {
  start.assign(n + 1, 0);
  for (std::size_t k = 0; k < a.size(); ++k) {
    ++start[a[k] + 1];
    ++start[b[k] + 1];
  }
  for (std::size_t p = 0; p < n; ++p) start[p + 1] += start[p];
  list.resize(start[n]);
  fill = start;
  for (std::size_t k = 0; k < a.size(); ++k) {
    list[fill[a[k]]++] = b[k];
    list[fill[b[k]]++] = a[k];
  }
}

}  // namespace shadow::geometry
