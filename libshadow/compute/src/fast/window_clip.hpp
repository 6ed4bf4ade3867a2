// SPDX-License-Identifier: GPL-3.0-or-later
// A convex grid polygon clipped exactly to a convex grid window, each new vertex rounded to the
// grid once.
//
// The fast path measures the union of a receiver's casts from their boundaries cluster by
// cluster (fast/cluster_union.hpp), which needs the casts already inside the receiver: a box
// receiver's casts are clipped to its box in doubles. A convex receiver that is not its box (a
// triangle of a terrain, a turned roof) used Clipper's intersection of all the casts with its
// outline instead, which sweeps every crossing of every pair of casts. Here each convex cast is
// clipped to the convex outline on its own (Sutherland-Hodgman), exactly: every vertex of the
// result is a cast vertex, a window vertex or the crossing of a cast edge's line with a window
// edge's line, kept as homogeneous integers (X, Y, W) and rounded to the nearest grid point only
// when the clip is done. So each output vertex is within half a cell's diagonal of the exact
// one, and a clipped polygon's perimeter is at most its cast's (a convex subset): the rounding
// is bounded by the casts' lengths alone (LitAreaBound::union_rounding).
//
// The integers' bounds (grid coordinates below 2^30 in magnitude: fast/receiver_job.hpp's
// kHalf): a line through two grid points a x + b y + c has |a|, |b| < 2^31 and |c| < 2^62; a
// crossing of two such lines has |W| < 2^63 and |X|, |Y| < 2^94; a side a X + b Y + c W is below
// 3 2^125 < 2^127. Everything fits in __int128.
#pragma once

#include "fast/cluster_scratch.hpp"

#include <polyclipping/clipper.hpp>

#include <cstddef>
#include <vector>

namespace shadow::fast {

inline GridLine grid_line(const ClipperLib::IntPoint& p, const ClipperLib::IntPoint& q) {
  GridLine l;
  l.a = static_cast<WindowInt128>(p.Y) - q.Y;
  l.b = static_cast<WindowInt128>(q.X) - p.X;
  l.c = -(l.a * p.X + l.b * p.Y);
  return l;
}

/// The sign of line `l` at point `p` (W > 0).
inline int window_side(const GridLine& l, const WindowPoint& p) {
  const WindowInt128 s = l.a * p.x + l.b * p.y + l.c * p.w;
  return s > 0 ? 1 : s < 0 ? -1 : 0;
}

/// Where lines `e` and `l` cross (not parallel: the caller has points strictly on both sides).
inline WindowPoint window_crossing(const GridLine& e, const GridLine& l) {
  WindowPoint p;
  p.w = e.a * l.b - l.a * e.b;
  p.x = e.b * l.c - l.b * e.c;
  p.y = e.c * l.a - l.c * e.a;
  if (p.w < 0) {
    p.w = -p.w;
    p.x = -p.x;
    p.y = -p.y;
  }
  return p;
}

/// n / d rounded to the nearest integer (d > 0; halves up).
inline long long round_quotient(WindowInt128 n, WindowInt128 d) {
  WindowInt128 q = (2 * n + d) / (2 * d);
  if ((2 * n + d) % (2 * d) != 0 && 2 * n + d < 0) --q;  // floor for negative numerators
  return static_cast<long long>(q);
}

/// Whether every point of `inner` is in the closed convex counter-clockwise grid polygon `outer`.
inline bool convex_contains(const ClipperLib::Path& outer, const ClipperLib::Path& inner) {
  for (std::size_t a = 0; a < outer.size(); ++a) {
    const GridLine l = grid_line(outer[a], outer[a + 1 == outer.size() ? 0 : a + 1]);
    for (const ClipperLib::IntPoint& p : inner)
      if (l.a * p.X + l.b * p.Y + l.c < 0) return false;
  }
  return true;
}

/// Sets up `s.window` for a convex counter-clockwise grid polygon `window`.
inline void set_window(const ClipperLib::Path& window, WindowClipScratch& s) {
  s.window.clear();
  for (std::size_t a = 0; a < window.size(); ++a)
    s.window.push_back(grid_line(window[a], window[a + 1 == window.size() ? 0 : a + 1]));
}

/// Clips the convex counter-clockwise grid polygon `poly` to the window set by set_window, and
/// writes the result rounded to the grid (repeated points dropped) to `out`: empty when nothing
/// of positive area is left before the rounding.
inline void clip_to_window(const ClipperLib::Path& poly, WindowClipScratch& s, ClipperLib::Path& out) {
  out.clear();
  const std::size_t n0 = poly.size();
  s.points.clear();
  s.lines.clear();
  for (std::size_t a = 0; a < n0; ++a) {
    s.points.push_back({poly[a].X, poly[a].Y, 1});
    s.lines.push_back(grid_line(poly[a], poly[a + 1 == n0 ? 0 : a + 1]));
  }
  for (const GridLine& l : s.window) {
    const std::size_t n = s.points.size();
    if (n < 3) return;
    s.side.resize(n);
    bool all_in = true;
    for (std::size_t a = 0; a < n; ++a) {
      s.side[a] = window_side(l, s.points[a]);
      all_in &= s.side[a] >= 0;
    }
    if (all_in) continue;
    s.next_points.clear();
    s.next_lines.clear();
    for (std::size_t a = 0; a < n; ++a) {
      const std::size_t b = a + 1 == n ? 0 : a + 1;
      const int sa = s.side[a], sb = s.side[b];
      if (sa >= 0) {
        s.next_points.push_back(s.points[a]);
        // Leaving the window at a itself (on the line): the next point is further along l.
        s.next_lines.push_back(sa == 0 && sb < 0 ? l : s.lines[a]);
      }
      if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) {
        s.next_points.push_back(window_crossing(s.lines[a], l));
        s.next_lines.push_back(sa > 0 ? l : s.lines[a]);  // out: along the window's edge
      }
    }
    s.points.swap(s.next_points);
    s.lines.swap(s.next_lines);
  }
  if (s.points.size() < 3) return;
  // Positive area before rounding: some point strictly left of the first two's line (convex).
  bool area = false;
  {
    const WindowPoint& p = s.points[0];
    for (std::size_t a = 1; a < s.points.size() && !area; ++a) area = window_side(s.lines[a], p) > 0;
  }
  if (!area) return;
  for (const WindowPoint& p : s.points) {
    const ClipperLib::IntPoint q{round_quotient(p.x, p.w), round_quotient(p.y, p.w)};
    if (out.empty() || !(out.back() == q)) out.push_back(q);
  }
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  if (out.size() < 3) out.clear();
}

}  // namespace shadow::fast
