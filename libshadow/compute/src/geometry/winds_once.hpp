// SPDX-License-Identifier: GPL-3.0-or-later
// Whether a closed polygon that turns one way everywhere goes round once: the test shared by the
// convexity checks, in integers (fast/cluster_union.hpp's is_convex_ccw), in doubles (the fast
// casts' hull from a solid's outline) and in rationals (exact/convex_union_area.hpp's convex).
#pragma once

namespace shadow::geometry {

/// Counts how often the x direction of a closed polygon's edges changes sign, the edges given in
/// order by the signs of their x differences (any int of that sign, as a comparison returns;
/// zeros, vertical edges, are passed over). A boundary that turns one way at every vertex winds once exactly when the count, the
/// change around the end included, is at most 2: each full turn of the edge direction changes it
/// twice (a pentagram turns left everywhere but winds twice, and changes it four times).
class XSignChanges {
 public:
  void add(int difference) {
    const int sign = (difference > 0) - (difference < 0);
    if (sign == 0) return;
    if (first_ == 0) first_ = sign;
    if (last_ != 0 && sign != last_) ++changes_;
    last_ = sign;
  }
  /// Whether the edges added so far, closed up, wind at most once.
  [[nodiscard]] bool winds_once() const { return changes_ + (last_ != 0 && last_ != first_ ? 1 : 0) <= 2; }

 private:
  int changes_ = 0, first_ = 0, last_ = 0;
};

/// The sign of b - a: 1, -1, or 0.
template <class T>
int sign_of_difference(T a, T b) {
  return b > a ? 1 : b < a ? -1 : 0;
}

}  // namespace shadow::geometry
