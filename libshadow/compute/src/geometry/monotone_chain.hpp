// SPDX-License-Identifier: GPL-3.0-or-later
// Andrew's monotone chain on items already sorted by (x, y), for the fast path's hulls in doubles:
// a convex solid's cast (fast/fast_receiver_casts.cpp) and its outline seen from the light
// (core/solid_outlines.hpp), which must agree on which points are corners.
#pragma once

#include <cstddef>

namespace shadow::geometry {

/// The convex hull of sorted[0, n) (n >= 1, sorted by x, then y) into out[0, k), k returned:
/// counter-clockwise from sorted[0], every corner a strict left turn (`left(a, b, c)`: a -> b -> c
/// turns strictly left; collinear and repeated items are dropped). `out` has room for 2n items.
/// k < 3 where the items bound no area.
template <class Item, class Left>
std::size_t monotone_chain(const Item* sorted, std::size_t n, Item* out, Left&& left) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower hull, left to right
    while (k >= 2 && !left(out[k - 2], out[k - 1], sorted[i])) --k;
    out[k++] = sorted[i];
  }
  for (std::size_t i = n - 1, t = k + 1; i > 0; --i) {  // upper hull, right to left
    while (k >= t && !left(out[k - 2], out[k - 1], sorted[i - 1])) --k;
    out[k++] = sorted[i - 1];
  }
  return k - 1;  // (the chain ends on sorted[0] again)
}

}  // namespace shadow::geometry
