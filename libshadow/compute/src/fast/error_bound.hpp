// SPDX-License-Identifier: GPL-3.0-or-later
// The fast path's bound on its lit-area error (FaceLighting::lit_area_error_bound), collected in
// one object: every term has a name that says where it comes from (docs/numeric-contract.md,
// "The fast path"). Terms are summed in the chart, in the order they are added (the bound's bits
// are part of the golden check), and turned into a 3D area bound once at the end.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadow::fast {

/// The bound on |area change| when every point of a polygon of perimeter L moves by <= r.
inline double tube(double length, double r) {
  constexpr double kPi = 3.14159265358979323846;
  return 2 * r * length + kPi * r * r;
}

/// The lit-area error bound of one receiver, term by term.
class LitAreaBound {
 public:
  /// A cast polygon that the box clip removed in doubles: the exact polygon may keep a sliver
  /// within r of the box's edge, no longer than the polygon's perimeter before the clip.
  void clipped_away(double free_length, double r) {
    if (free_length > 0) chart_ += tube(free_length, r);
  }
  /// A cast polygon given to the union: each vertex within delta of the exact one, then rounded
  /// to the grid (r = grid rounding + delta + roundings); its boundary, before or after the box
  /// clip, whichever is longer, plus the moved vertices' own reach.
  void cast_polygon(double free_length, double length, double vertices, double delta, double r) {
    chart_ += tube(std::max(free_length, length) + 2 * vertices * delta, r);
  }
  /// A convex solid whose projected hull is flat in doubles: the exact hull is at most a sliver.
  void flat_solid(double perimeter, double r) { chart_ += tube(perimeter, r); }
  /// A caster piece nowhere clearly in front, with every vertex of unsure side but close to the
  /// receiver's plane: its exact front part is at most a sliver along the plane.
  void unsure_sliver(double perimeter, double r) { chart_ += tube(perimeter, r); }
  /// The receiver's own outline rounded to the grid (not for a receiver that is its chart box,
  /// whose corners are grid points).
  void receiver_outline(double length, double rho) { chart_ += tube(length, rho); }
  /// Clipper rounds the intersection points it creates to the grid (by under one step): the
  /// output's boundary, on the input polygons' boundaries of total length `length`, moves by
  /// under 2 rho. Unions in sequence (fast/strip_union.hpp: n levels) pass rho = n x the grid
  /// rounding: each level moves the boundary it was given by under 2 x the grid rounding.
  void union_rounding(double length, double rho) { chart_ += tube(length, 2 * rho); }

  /// The union's area measured from its boundary in doubles (fast/cluster_union.hpp): `chart_area`
  /// bounds its arithmetic error (interval ends and sums), already in chart units.
  void boundary_arithmetic(double chart_area) {
    if (chart_area > 0) chart_ += chart_area;
  }

  /// Whether the terms so far are finite (overflow in doubles sends the receiver to the exact
  /// engine).
  [[nodiscard]] bool finite() const { return std::isfinite(chart_); }

  /// The bound for an unshadowed receiver: the chart terms times the chart-to-3D area `scale`.
  [[nodiscard]] double unshadowed(double scale) const { return chart_ * scale * (1 + 1e-9); }

  /// The bound after the union: the chart terms times `scale`, plus half the gap between the
  /// unions without and with the nearly coplanar casters' footprints (`gap_cells` grid cells of
  /// 3D area `cell`), plus the roundings of area, scale and the subtraction (a few ulps of the
  /// face's area).
  [[nodiscard]] double after_union(double scale, double gap_cells, double cell, double face_area) const {
    constexpr double kEps = std::numeric_limits<double>::epsilon();
    return (chart_ * scale + 0.25 * gap_cells * cell) * (1 + 1e-9) + 16 * kEps * face_area;
  }

 private:
  double chart_ = 0;  ///< the sum of the chart-area terms
};

}  // namespace shadow::fast
