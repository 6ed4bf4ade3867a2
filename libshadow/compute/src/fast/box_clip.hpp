// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's clip of a convex chart polygon to the receiver's chart box, in doubles.
// Internal to fast/ (and its tests).
#pragma once

#include "geometry/clip_convex.hpp"
#include "geometry/default_init_allocator.hpp"

#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <vector>

namespace shadow::fast {

/// Chart points in doubles: the casts' polygons and the scratch of their clips and hulls, which
/// grow without a zero fill (geometry/default_init_allocator.hpp): an element that resize() or
/// ChartPoints(n) makes holds no value until it is written (write before reading).
using ChartPoints = geometry::UnfilledVector<glm::dvec2>;

/// Sutherland-Hodgman clip of a convex polygon to x[c] >= bound (lower) or <= bound (upper)
/// (geometry/clip_convex.hpp). Crossing points get the bound exactly in coordinate c. In doubles a
/// vertex is inside or outside (side +1 or -1), never on the boundary: as before the one walk.
inline void clip_axis(ChartPoints& poly, int c, double bound, bool lower, ChartPoints& scratch) {
  auto side = [&](std::size_t a) {
    const glm::dvec2& p = poly[a];
    return (lower ? p[c] >= bound : p[c] <= bound) ? 1 : -1;
  };
  geometry::clip_convex(poly, side, [&](std::size_t a, std::size_t b) {
    const glm::dvec2& p = poly[a];
    const glm::dvec2& q = poly[b];
    const double t = std::clamp((bound - p[c]) / (q[c] - p[c]), 0.0, 1.0);
    glm::dvec2 x = p + t * (q - p);
    x[c] = bound;
    return x;
  }, scratch);
  poly.swap(scratch);
}

/// The clip of `poly` to the box [lo, hi] (lower then upper bound of x, then of y, while at
/// least 3 vertices are left): the same points as clip_axis at all four sides, but a side that
/// every vertex is inside of (clip_axis's own comparison) is skipped, for there the clip would
/// keep the polygon as it is. The lower clip of an axis leaves its upper test as it was (its new
/// vertices lie on the lower bound); the new vertices' other coordinate is rounded, so the second
/// axis is tested on the polygon as clipped. A cast is most often inside most of the sides.
inline void clip_to_box_sides(ChartPoints& poly, const std::array<double, 2>& lo,
                              const std::array<double, 2>& hi, ChartPoints& scratch) {
  for (int c = 0; c < 2 && poly.size() >= 3; ++c) {
    bool above_lo = true, below_hi = true;
    for (const glm::dvec2& p : poly) {
      above_lo = above_lo && p[c] >= lo[c];
      below_hi = below_hi && p[c] <= hi[c];
    }
    if (!above_lo) clip_axis(poly, c, lo[c], true, scratch);
    if (!below_hi) clip_axis(poly, c, hi[c], false, scratch);
  }
}

}  // namespace shadow::fast
