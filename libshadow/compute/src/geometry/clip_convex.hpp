// SPDX-License-Identifier: GPL-3.0-or-later
// Sutherland–Hodgman clipping of a convex polygon to one half-space, written once for every
// number type and point representation of the engine (lazy exact 3D and 2D points, GMP points,
// doubles, homogeneous doubles). The caller says on which side each vertex lies and how to make a
// crossing point; this header owns the walk, so that every copy keeps f >= 0 and makes crossings
// only on strict sign changes (no duplicate vertex at a vertex on the boundary).
//
// The variants the engine needs, as (side, cross) pairs at the call sites:
//  - 3D affine half-space, exact signs evaluated (exact/lazy_geometry.hpp clip_convex,
//    exact/leaf_projector.hpp, planes/plane_shadows.cpp): side = sign(f(p)), cross = p + t (q - p)
//    with t = f(p) / (f(p) - f(q));
//  - 3D affine half-space, exact signs known (lazy_geometry.hpp clip_front): f evaluated only on
//    crossing edges;
//  - 2D axis bound x_c >= m or <= m (lazy_geometry.hpp clip_convex_2d; fast_receiver.cpp clip_axis):
//    the crossing gets m exactly in coordinate c;
//  - homogeneous (fast_receiver.cpp clip_hom): f linear in (X, Z, w).
// The fast path's double variants report side +1 or -1 only (f >= 0 or not, as before): a vertex
// exactly on the boundary counts as inside, and the crossing's t is clamped to [0, 1]; their bits
// are part of the golden check.
#pragma once

#include "geometry/cyclic_index.hpp"

#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::geometry {

/// What a half-space does to a polygon, from its vertices' sides.
enum class ClipCase {
  Inside,  ///< no vertex strictly outside: the polygon is unchanged
  Empty,   ///< no vertex strictly inside: the closed half-space keeps no area
  Cut,     ///< vertices on both sides: clip_convex makes the new polygon
};

/// Classifies n vertices by side(a) (> 0 inside, 0 on the boundary, < 0 outside).
template <class SideOf>
ClipCase clip_case(std::size_t n, SideOf&& side) {
  bool any_out = false, any_in = false;
  for (std::size_t a = 0; a < n; ++a) {
    const int s = side(a);
    any_out |= s < 0;
    any_in |= s > 0;
  }
  if (!any_out) return ClipCase::Inside;
  return any_in ? ClipCase::Cut : ClipCase::Empty;
}

/// The Sutherland–Hodgman walk around the convex polygon `poly` (vertex indices a, b = a + 1
/// cyclically): keeps every vertex with side(a) >= 0, and between two consecutive vertices on
/// strictly opposite sides inserts cross(a, b), the point where the boundary crosses edge ab.
/// `out` is cleared first and receives the clipped polygon (it may then be swapped in).
/// `Points`: a std::vector of the point type, with any allocator.
template <class Points, class SideOf, class Cross>
void clip_convex(const Points& poly, SideOf&& side, Cross&& cross, Points& out) {
  using Point = typename Points::value_type;
  const std::size_t n = poly.size();
  // Plain points (the fast path's doubles) are written in place instead of by a push_back call
  // per vertex (an out-of-line call the compiler kept). Each vertex gives at most two (itself
  // and a crossing), so 2n is room for any polygon, convex or made a little less so by rounding.
  constexpr bool in_place = std::is_trivially_copyable_v<Point> && std::is_default_constructible_v<Point>;
  std::size_t m = 0;
  if constexpr (in_place) out.resize(2 * n);
  else out.clear();
  auto put = [&](auto&& p) {
    if constexpr (in_place) out[m++] = p;
    else out.push_back(std::forward<decltype(p)>(p));
  };
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = cyclic_next(a, n);
    const int sa = side(a), sb = side(b);
    if (sa >= 0) put(poly[a]);
    if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) put(cross(a, b));
  }
  if constexpr (in_place) out.resize(m);
}

}  // namespace shadow::geometry
