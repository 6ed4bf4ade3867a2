// SPDX-License-Identifier: GPL-3.0-or-later
// The exact union's polygons measured across their main direction, for its sweep for neighbours
// (exact/convex_union_area.hpp, geometry::sweep_across). Under a low sun a ground's casts are
// long along the shadows and narrow across them; two polygons apart across are disjoint, so
// neither covers any part of the other's edges. Include only from src/exact/*.cpp or tests (CGAL).
#pragma once

#include "exact/rational_points.hpp"
#include "geometry/box_sweep.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace shadow::exact {

/// Into `out`, for each polygon i of points[first[i], first[i + 1]) (`next`: each vertex's next
/// around its polygon), an interval [lo, hi] that holds the exact projection of every point of
/// the polygon on the unit normal to the polygons' main direction (geometry::MainDirection, of
/// their edges in doubles: any direction gives rigorous extents, this one narrow ones). The
/// projections are taken in interval arithmetic from the points' intervals (rounding upward set
/// here); a polygon with a projection that is not a number is given the whole line.
inline void across_extents(const std::vector<IPoint2>& points, const std::vector<std::size_t>& next,
                           const std::vector<std::size_t>& first, std::vector<std::pair<double, double>>& out) {
  const std::size_t n = first.empty() ? 0 : first.size() - 1;
  geometry::MainDirection main;
  for (std::size_t v = 0; n > 0 && v < first[n]; ++v)
    main.add(points[next[v]].x.inf() - points[v].x.inf(), points[next[v]].y.inf() - points[v].y.inf());
  const auto [nx, ny] = main.across();
  out.resize(n);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  CGAL::Protect_FPU_rounding<true> guard;  // IA's operations round outward only so
  for (std::size_t i = 0; i < n; ++i) {
    double lo = kInfinity, hi = -kInfinity;
    for (std::size_t v = first[i]; v < first[i + 1]; ++v) {
      const IA t = nx * points[v].x + ny * points[v].y;
      if (!(t.inf() <= t.sup())) {  // (not a number: std::min would drop it silently)
        lo = -kInfinity;
        hi = kInfinity;
        break;
      }
      lo = std::min(lo, t.inf());
      hi = std::max(hi, t.sup());
    }
    out[i] = lo <= hi ? std::pair{lo, hi} : std::pair{-kInfinity, kInfinity};
  }
}

}  // namespace shadow::exact
