// SPDX-License-Identifier: GPL-3.0-or-later
// What the engine knows about each face once prepared: plain numbers and indices, no CGAL types,
// so that it can be shared between threads and used by code that does not include CGAL.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace shadow::core {

/// What validation and the shadow computation need to know about a face, computed once with
/// exact predicates and stored without CGAL types.
struct FacePrep {
  bool degenerate = false;     ///< zero area: casts and receives nothing
  int axis = 2;                ///< k: dominant axis of the exact normal; the chart drops it
  bool flipped = false;        ///< n_k < 0: the chart (x_i, x_j) sees the face clockwise
  bool exactly_planar = true;  ///< all vertices lie exactly on one plane
  /// Vertex indices around the face, counter-clockwise in the chart, collinear vertices removed.
  std::vector<int> chart_ring;
  /// Convex pieces (vertex indices, counter-clockwise in the chart) that tile the face.
  std::vector<std::vector<int>> convex_pieces;
  /// For exactly planar faces: a convex corner (prev, corner, next) whose cross product gives
  /// the exact normal with the face's orientation.
  std::array<int, 3> corner{0, 1, 2};
  std::array<double, 2> chart_min{0, 0}, chart_max{0, 0};  ///< chart bounding box (exact doubles)
  bool chart_is_box = false;  ///< the face is its own chart bounding box (axis-aligned rectangle)
};

/// Chart axes (i, j) for dropped axis k: cyclic, so that the chart sees the face
/// counter-clockwise exactly when the normal's k component is positive.
inline int chart_i(int k) { return (k + 1) % 3; }
inline int chart_j(int k) { return (k + 2) % 3; }

/// The area of a face's chart box, in doubles.
inline double chart_box_area(const FacePrep& fp) {
  return (fp.chart_max[0] - fp.chart_min[0]) * (fp.chart_max[1] - fp.chart_min[1]);
}

/// Twice the signed area of a ring of `n` points, point(a) for a in [0, n) (an
/// std::array<double, 2>), summed in doubles in ring order with every point taken about
/// `corner`: georeferenced charts (coordinates of 1e6) would otherwise cancel the products'
/// leading digits away. A guide, not an exact value.
template <class ChartPoint>
double twice_area_about(const std::array<double, 2>& corner, std::size_t n, const ChartPoint& point) {
  double twice = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const std::array<double, 2> p = point(a), q = point((a + 1) % n);
    const double px = p[0] - corner[0], py = p[1] - corner[1];
    const double qx = q[0] - corner[0], qy = q[1] - corner[1];
    twice += px * qy - qx * py;
  }
  return twice;
}

/// twice_area_about the chart box's lower corner, for a ring of chart points (how much of its
/// box a face fills, whether a cast may be the whole box).
template <class ChartPoint>
double twice_area_about_box_corner(const FacePrep& fp, std::size_t n, const ChartPoint& point) {
  return twice_area_about({fp.chart_min[0], fp.chart_min[1]}, n, point);
}

/// Makes a fragment's polygon of doubles (on a face whose chart drops axis k) fit the output
/// contract: removes consecutive repeated vertices (cyclically; rounding can merge neighbours)
/// and says whether what remains is one simple polygon with at least 3 vertices and non-zero
/// area, decided with exact predicates on the doubles in the chart (simple there implies simple
/// in 3D; non-zero chart area implies non-zero 3D area), whose area computed in doubles (the
/// shoelace relative to its first vertex, and Newell's formula on the absolute coordinates) is
/// certainly non-zero too. O(n log n). Defined in
/// core/clean_polygon.cpp.
bool clean_double_polygon(std::vector<glm::dvec3>& polygon, int k);

}  // namespace shadow::core
