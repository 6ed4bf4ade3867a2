// SPDX-License-Identifier: GPL-3.0-or-later
// Every two polygons whose boxes overlap and whose extents across a direction are not apart, by
// one sort and a read-only scan, and such pairs as lists of neighbours: the fast path's clusters
// of casts (fast/cluster_union.hpp) and the exact union's neighbours (exact/convex_union_area.hpp),
// on their own coordinates (integers, doubles).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace shadow::geometry {

/// sweep_across's `passed` where the caller never has done with an item.
struct NonePassed {
  constexpr bool operator()(std::size_t) const { return false; }
};

/// The main direction of segments, for sweep_across's axis: the principal axis of their
/// directions, each weighted by its length squared (sums of |d|^2 (cos 2a, sin 2a), so that a
/// segment and its reverse count alike). Under a low sun the casts' long edges run along the
/// shadows.
struct MainDirection {
  double c = 0, s = 0;
  void add(double dx, double dy) {
    c += dx * dx - dy * dy;
    s += 2 * dx * dy;
  }
  /// The unit normal (nx, ny) to the main direction; (-1, 0), the normal to (0, 1), where there
  /// is none (no segment, or sums that are not finite).
  [[nodiscard]] std::pair<double, double> across() const {
    if (!std::isfinite(c) || !std::isfinite(s) || (c == 0 && s == 0)) return {-1.0, 0.0};
    const double a = 0.5 * std::atan2(s, c);
    return {-std::sin(a), std::cos(a)};
  }
};

/// An item in sweep_across's order: its extent across (the sweep's axis), its box (members x0,
/// y0, x1, y1) and its index, read in order without a look-up.
template <class Box>
struct AcrossSweepEntry {
  double lo = 0, hi = 0;
  Box box{};
  std::size_t index = 0;
};

/// Calls pair(later, earlier) for every two items whose extents `across` (closed intervals
/// along some axis, one per box: a separating axis's, where items apart along it are disjoint)
/// are not apart and whose `boxes` overlap with positive extent along both axes, or with
/// `Closed` touching too: one sort by the extents' lower ends (ties by index) and a scan of the
/// later ones that start before each ends, the box test after. Where items are long and narrow
/// along one direction (a low sun's shadows), across it each meets few later ones, while a sweep
/// along x or y met most of a crowded cluster: a diagonal shadow's box is long both ways.
///
/// `passed(index)`, where given, says an item needs no more pairs (the caller has done with it):
/// from then on none of its pairs is reported, and the items after it are not scanned for it.
/// Every extent must have lo <= hi (neither a NaN): the scan's stop relies on it.
template <bool Closed, class Box, class Pair, class Passed = NonePassed>
void sweep_across(const std::vector<Box>& boxes, const std::vector<std::pair<double, double>>& across,
                  std::vector<AcrossSweepEntry<Box>>& sorted, Pair&& pair, Passed&& passed = {}) {
  using Entry = AcrossSweepEntry<Box>;
  const std::size_t n = boxes.size();
  sorted.resize(n);
  for (std::size_t a = 0; a < n; ++a) sorted[a] = Entry{across[a].first, across[a].second, boxes[a], a};
  std::sort(sorted.begin(), sorted.end(), [](const Entry& a, const Entry& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.index < b.index;
  });
  for (std::size_t a = 0; a < n; ++a) {
    const Entry& p = sorted[a];
    if (passed(p.index)) continue;
    for (std::size_t b = a + 1; b < n; ++b) {
      const Entry& q = sorted[b];
      if (q.lo > p.hi) break;  // apart, as is every later one (q.hi >= q.lo >= p.lo)
      const Box &u = p.box, &v = q.box;
      const bool meet = Closed ? u.x0 <= v.x1 && v.x0 <= u.x1 && u.y0 <= v.y1 && v.y0 <= u.y1
                               : u.x0 < v.x1 && v.x0 < u.x1 && u.y0 < v.y1 && v.y0 < u.y1;
      if (!meet || passed(q.index)) continue;
      pair(q.index, p.index);
      if (passed(p.index)) break;
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
