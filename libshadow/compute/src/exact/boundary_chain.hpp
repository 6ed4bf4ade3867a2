// SPDX-License-Identifier: GPL-3.0-or-later
// A region's boundary as a chain of oriented segments, and its canonical form (docs/algorithm.md,
// "The union's area without a Boolean operation"). Internal to the library (GMP rationals).
//
// A bounded region R of the plane with a polygonal boundary is described, as far as any sum over
// it goes, by its boundary as a 1-chain: segments run with R on their left, where a stretch run
// both ways counts as nothing. So lit = window - union has the chain boundary(window) -
// boundary(union), whatever order the pieces come in, however they are split, and whichever
// stretches appear twice in opposite directions (the shared sides of two convex pieces of a
// chart, the opposite coincident edges of two casts). The canonical form of a chain is the one
// list of segments that every description of the same chain gives: on each supporting line,
// the maximal stretches of constant net multiplicity, each run from its lexicographically
// smaller end, the lines sorted by (vertical, slope, intercept) and the stretches along each
// line. CGAL's Boolean operations and the boundary-measure union describe the same lit region
// with different vertices (collinear ones left where input edges met), so the sun-hours map
// feeds its overlay the canonical form: the same segments, in the same order, from either.
#pragma once

#include "exact/rational_points.hpp"

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace shadow::exact {

class BoundaryChain {
 public:
  struct Point {
    EQ x, y;
  };
  /// A canonical segment: `from` lexicographically before `to`; the region lies on the left of
  /// from -> to when `left`, on its right otherwise.
  struct Segment {
    Point from, to;
    bool left = true;
  };

  /// The sign of a - b.
  static int compare(const EQ& a, const EQ& b) {
    const int r = mpq_cmp(a.get_mpq_t(), b.get_mpq_t());
    return (r > 0) - (r < 0);
  }

  void clear() { used_ = 0; }

  /// Adds the segment a -> b with the region on its left (nothing when a == b).
  void add(const EQ& ax, const EQ& ay, const EQ& bx, const EQ& by) {
    const int cx = compare(ax, bx);
    const int order = cx != 0 ? cx : compare(ay, by);
    if (order == 0) return;
    if (used_ == items_.size()) items_.emplace_back();
    Item& it = items_[used_++];
    const bool forward = order < 0;
    it.sign = forward ? 1 : -1;
    it.lo.x = forward ? ax : bx;
    it.lo.y = forward ? ay : by;
    it.hi.x = forward ? bx : ax;
    it.hi.y = forward ? by : ay;
    it.vertical = cx == 0;
    if (it.vertical) {  // the line x = lo.x; stretches along it by y
      it.m = it.lo.x;
      it.c = 0;
    } else {  // y = m x + c; stretches by x
      it.m = it.hi.y - it.lo.y;
      it.c = it.hi.x - it.lo.x;
      it.m /= it.c;
      it.c = it.m * it.lo.x;
      it.c = it.lo.y - it.c;
    }
  }
  void add(const Point& a, const Point& b) { add(a.x, a.y, b.x, b.y); }

  /// The chain's canonical form into `out` (cleared first). False when some stretch has a net
  /// multiplicity other than -1, 0 or 1: the segments were not a region's boundary.
  bool canonical(std::vector<Segment>& out) {
    out.clear();
    order_.resize(used_);
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
      const int line = compare_lines(items_[a], items_[b]);
      if (line != 0) return line < 0;
      return a < b;
    });
    std::size_t g = 0;
    while (g < order_.size()) {
      std::size_t h = g + 1;
      while (h < order_.size() && compare_lines(items_[order_[g]], items_[order_[h]]) == 0) ++h;
      if (!sweep_line(g, h, out)) return false;
      g = h;
    }
    return true;
  }

 private:
  struct Item {
    Point lo, hi;
    int sign = 1;
    bool vertical = false;
    EQ m, c;  ///< the line: y = m x + c, or x = m when vertical
  };
  struct Event {
    const Point* at;
    const EQ* param;
    int delta;
  };

  static int compare_lines(const Item& a, const Item& b) {
    if (a.vertical != b.vertical) return a.vertical ? 1 : -1;
    const int m = compare(a.m, b.m);
    return m != 0 ? m : compare(a.c, b.c);
  }

  /// The stretches of one line (items order_[g, h)): events sorted along it, net multiplicity
  /// swept, a segment emitted wherever it is non-zero, split where it changes.
  bool sweep_line(std::size_t g, std::size_t h, std::vector<Segment>& out) {
    events_.clear();
    for (std::size_t k = g; k < h; ++k) {
      const Item& it = items_[order_[k]];
      events_.push_back({&it.lo, it.vertical ? &it.lo.y : &it.lo.x, it.sign});
      events_.push_back({&it.hi, it.vertical ? &it.hi.y : &it.hi.x, -it.sign});
    }
    std::sort(events_.begin(), events_.end(),
              [](const Event& a, const Event& b) { return compare(*a.param, *b.param) < 0; });
    int sum = 0;
    const Point* start = nullptr;
    std::size_t e = 0;
    while (e < events_.size()) {
      const Point* here = events_[e].at;
      int next = sum;
      std::size_t f = e;
      for (; f < events_.size() && compare(*events_[f].param, *events_[e].param) == 0; ++f) next += events_[f].delta;
      if (next != sum) {
        if (sum != 0) out.push_back(Segment{*start, *here, sum > 0});
        if (next < -1 || next > 1) return false;
        start = here;
        sum = next;
      }
      e = f;
    }
    return sum == 0;
  }

  std::vector<Item> items_;  ///< [0, used_) in use; the rest keeps its numbers' storage
  std::size_t used_ = 0;
  std::vector<std::size_t> order_;
  std::vector<Event> events_;
};

}  // namespace shadow::exact
