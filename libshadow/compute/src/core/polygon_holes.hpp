// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: a planar polygon with holes split into hole-free convex pieces (CityJSON inner rings,
// EnergyPlus windows cut out of their walls). No CGAL type in this header.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadow::core {

/// Why a polygon with holes could not be split. what() is the problem only (no file, no place):
/// the caller knows where the polygon came from and turns it into an InputError. `ring` says which
/// ring is at fault (-1: the outer ring, k: holes[k]) and `vertex` which of its vertices, or -1.
class PolygonHolesError : public std::runtime_error {
 public:
  PolygonHolesError(int ring, int vertex, const std::string& problem)
      : std::runtime_error(problem), ring(ring), vertex(vertex) {}
  int ring;
  int vertex;
};

/// What split_polygon_with_holes_checked returns: the pieces, or the problem (`error` non-empty,
/// `pieces` empty, `ring`/`vertex` as in PolygonHolesError).
struct PolygonHolesSplit {
  std::vector<std::vector<glm::dvec3>> pieces;
  std::string error;
  int ring = -1;
  int vertex = -1;
};

/// Splits the planar polygon `outer` with the holes `holes` into simple convex polygons that tile
/// it exactly (their union is the polygon minus the holes, their interiors are disjoint) and use
/// only the input's own vertices: no coordinate is computed, so the pieces are exact. The pieces
/// run the same way round as `outer` (so they face where it faces); the holes may run either way.
/// Consecutive repeated vertices (and a closing copy of the first) are dropped.
///
/// How: the polygon is charted on the dominant axis of its Newell normal, triangulated by a
/// constrained Delaunay triangulation with exact predicates on the doubles (CGAL Epick, no
/// constructions), the triangles inside by nesting depth are kept, and diagonals are removed
/// while both their ends stay strictly convex (Hertel-Mehlhorn). Without holes and with a convex
/// outer ring, the result is the outer ring itself.
///
/// Errors (PolygonHolesError): a ring with fewer than 3 distinct vertices, an outer ring of zero
/// area or not simple, a hole not simple, a hole vertex off the outer ring's plane by more than
/// `planarity_tolerance` times the outer ring's diameter, a hole not strictly inside the outer
/// ring (outside it, crossing or touching its boundary), two holes that overlap or touch, a
/// non-finite coordinate.
std::vector<std::vector<glm::dvec3>> split_polygon_with_holes(
    const std::vector<glm::dvec3>& outer, const std::vector<std::vector<glm::dvec3>>& holes,
    double planarity_tolerance = 1e-6);

/// The triangles of a constrained Delaunay triangulation of the polygon with holes, made of its
/// own vertices and oriented like `outer`: the documented split of a surface that is not planar
/// (each triangle is planar, the polygon is charted on the dominant axis of the outer ring's
/// normal). The holes are not checked against the outer ring's plane; the other errors are
/// those of split_polygon_with_holes (a ring whose chart is not simple among them).
std::vector<std::vector<glm::dvec3>> triangulate_polygon_with_holes(
    const std::vector<glm::dvec3>& outer, const std::vector<std::vector<glm::dvec3>>& holes);

/// split_polygon_with_holes that returns the problem instead of throwing it.
PolygonHolesSplit split_polygon_with_holes_checked(
    const std::vector<glm::dvec3>& outer, const std::vector<std::vector<glm::dvec3>>& holes,
    double planarity_tolerance = 1e-6);

/// Convex pieces of a polygon whose rings (the outer one and any holes) are given by `next`/`prev`
/// links over the points of `chart`, each ring with the inside on its left: a constrained Delaunay
/// triangulation with exact predicates on the doubles (CGAL Epick), the triangles inside, and
/// Hertel-Mehlhorn's merge (a diagonal goes while both its ends stay strictly convex, tested on
/// the neighbours in each end's fan: O(n)); `merge` false keeps the triangles. Pieces are lists
/// of indices into `chart`, counter-clockwise, made of the input's own points. The one
/// implementation for faces (exact/exact_faces.cpp) and polygons with holes. Rings must be
/// simple, apart from each other and without collinear repeats (the callers check).
std::vector<std::vector<int>> convex_pieces(const std::vector<std::array<double, 2>>& chart,
                                            const std::vector<int>& next, const std::vector<int>& prev,
                                            bool merge = true);

}  // namespace shadow::core
