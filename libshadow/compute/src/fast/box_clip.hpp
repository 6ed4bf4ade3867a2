// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's clip of a convex chart polygon to the receiver's chart box, in doubles.
// Internal to fast/ (and its tests).
#pragma once

#include "geometry/clip_convex.hpp"
#include "geometry/default_init_allocator.hpp"

#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
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

namespace box_clip_detail {

/// One clip_axis walk on the axis C, lower or upper bound, from in[0, n) into out (room for 2n
/// points): the same sides, the same crossings and the same arithmetic, each vertex's side
/// found once and the axis fixed at compile time. Returns the number of points written.
template <int C, bool Lower>
inline std::size_t clip_pass(const glm::dvec2* in, std::size_t n, double bound, glm::dvec2* out) {
  if (n == 0) return 0;
  auto inside = [bound](const glm::dvec2& p) { return Lower ? p[C] >= bound : p[C] <= bound; };
  const bool first = inside(in[0]);
  bool sa = first;
  std::size_t m = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = a + 1 < n ? a + 1 : 0;
    const bool sb = b == 0 ? first : inside(in[b]);
    if (sa) out[m++] = in[a];
    if (sa != sb) {
      const glm::dvec2& p = in[a];
      const glm::dvec2& q = in[b];
      const double t = std::clamp((bound - p[C]) / (q[C] - p[C]), 0.0, 1.0);
      glm::dvec2 x = p + t * (q - p);
      x[C] = bound;
      out[m++] = x;
    }
    sa = sb;
  }
  return m;
}

}  // namespace box_clip_detail

/// The clip of `poly` to the box [lo, hi] (lower then upper bound of x, then of y, while at
/// least 3 vertices are left): the same points as clip_axis at all four sides, but a side that
/// every vertex is inside of (clip_axis's own comparison) is skipped, for there the clip would
/// keep the polygon as it is. The lower clip of an axis leaves its upper test as it was (its new
/// vertices lie on the lower bound); the new vertices' other coordinate is rounded, so the second
/// axis is tested on the polygon as clipped. A cast is most often inside most of the sides.
///
/// The walks run between two buffers on the stack and the result is copied into `poly` once: a
/// million casts an instant's worth of the year went through two vector resizes and a walk
/// that found each vertex's side twice per clipped side. A polygon too large for the buffers
/// (over half of them: a walk may double it) is walked by clip_axis, with `scratch`.
inline void clip_to_box_sides(ChartPoints& poly, const std::array<double, 2>& lo,
                              const std::array<double, 2>& hi, ChartPoints& scratch) {
  constexpr std::size_t kRoom = 64;
  glm::dvec2 buffer[2][kRoom];  // (no value until written: glm's vectors are not zero-filled)
  const glm::dvec2* src = poly.data();
  std::size_t n = poly.size();
  int held = -1;  // the buffer that holds src, or -1: poly does
  auto clip = [&](int c, bool lower, double bound) {
    if (2 * n > kRoom) {  // the vectors' walk
      if (held >= 0) poly.assign(src, src + n);
      held = -1;
      clip_axis(poly, c, bound, lower, scratch);
      src = poly.data();
      n = poly.size();
      return;
    }
    const int to = held == 0 ? 1 : 0;
    glm::dvec2* out = buffer[to];
    using box_clip_detail::clip_pass;
    n = c == 0 ? (lower ? clip_pass<0, true>(src, n, bound, out) : clip_pass<0, false>(src, n, bound, out))
               : (lower ? clip_pass<1, true>(src, n, bound, out) : clip_pass<1, false>(src, n, bound, out));
    src = out;
    held = to;
  };
  for (int c = 0; c < 2 && n >= 3; ++c) {
    bool above_lo = true, below_hi = true;
    for (std::size_t a = 0; a < n; ++a) {
      above_lo = above_lo && src[a][c] >= lo[c];
      below_hi = below_hi && src[a][c] <= hi[c];
    }
    if (!above_lo) clip(c, true, lo[c]);
    if (!below_hi) clip(c, false, hi[c]);
  }
  if (held >= 0) poly.assign(src, src + n);
}

}  // namespace shadow::fast
