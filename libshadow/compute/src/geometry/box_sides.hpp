// SPDX-License-Identifier: GPL-3.0-or-later
// The four planes that bound, from a light, the part of space that projects into a box of a
// receiving plane's chart: a prism for a directional light, a pyramid for a point light. Written
// once for every number type the engine uses (double for culling, lazy exact values, GMP).
#pragma once

#include <array>

namespace shadow::geometry {

/// Affine functions f(x) = f[0] x + f[1] y + f[2] z + f[3], one per side, that are >= 0 inside.
/// `plane` = (n, c) with the light on its front; `light` = (L, 1) or (d, 0); `light_side` =
/// n . l_xyz + c l_w > 0; the box is [lo, hi] in chart axes (i, j). For a bound x_a >= m the side
/// is  s~ (x_a - m) - (l_a - m l_w) s(x) = 0: it contains the bound's line on the receiving plane
/// (s = 0, x_a = m) and the light. Order: (i, lo), (i, hi), (j, lo), (j, hi).
template <class T>
std::array<std::array<T, 4>, 4> box_sides(const std::array<T, 4>& plane, const std::array<T, 4>& light,
                                          const T& light_side, int i, int j, const double lo[2],
                                          const double hi[2]) {
  std::array<std::array<T, 4>, 4> sides;
  const int axes[2] = {i, j};
  for (int c = 0; c < 2; ++c) {
    for (int upper = 0; upper < 2; ++upper) {
      const T m(upper ? hi[c] : lo[c]);
      const T coef = light[axes[c]] - m * light[3];
      std::array<T, 4>& f = sides[c * 2 + upper];
      for (int col = 0; col < 4; ++col) f[col] = -coef * plane[col];
      f[axes[c]] += light_side;
      f[3] -= light_side * m;
      if (upper)
        for (T& x : f) x = -x;
    }
  }
  return sides;
}

}  // namespace shadow::geometry
