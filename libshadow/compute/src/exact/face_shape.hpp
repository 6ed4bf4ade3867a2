// SPDX-License-Identifier: GPL-3.0-or-later
// Exact geometric checks on input faces, for validation (implemented with CGAL in
// exact_faces.cpp; this header stays free of CGAL).
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace shadow::detail {

enum class FaceShape {
  Simple,            ///< non-zero area and a simple (non-self-intersecting) boundary
  ZeroArea,          ///< exactly zero area: collinear or coincident vertices
  SelfIntersecting,  ///< the boundary crosses or touches itself
};

/// Classifies a face's boundary exactly, in the 2D chart that drops the dominant axis of its
/// exact Newell normal. Vertices must be finite, with consecutive duplicates removed.
/// Decided with Epick's exact predicates on the input doubles and an interval filter on the
/// normal (the lazy exact normal only where the filter cannot decide); the same answers as
/// classify_face_shape_exact on every input, many times cheaper.
FaceShape classify_face_shape(const std::vector<glm::dvec3>& vertices);

/// The same classification computed wholly with Epeck's lazy exact numbers: the reference that
/// classify_face_shape is tested against (and shadow-bench times it against).
FaceShape classify_face_shape_exact(const std::vector<glm::dvec3>& vertices);

/// What cut_openings returns: the surface left once its openings are cut out, or the problem.
struct OpeningsCut {
  /// Polygons with holes: regions[r][0] is an outer ring, regions[r][1..] its holes. Every vertex
  /// is one of the input vertices (nothing is computed); outer rings run the same way round as
  /// `surface`, holes the other way.
  std::vector<std::vector<std::vector<glm::dvec3>>> regions;
  bool surface_not_simple = false;  ///< `surface` has zero area or crosses itself: nothing cut
  int not_simple = -1;              ///< an opening with zero area or crossing itself, or -1
  int outside = -1;                 ///< an opening not wholly inside `surface`, or -1
  int overlap_first = -1;           ///< two openings whose insides overlap, or -1
  int overlap_second = -1;
  /// Some opening sticks out of `surface`, or two openings overlap, by no more than `tolerance`
  /// (rounding in the model's coordinates): accepted, and the cut is then exact only up to
  /// those slivers (new vertices where edges cross are put on the surface's plane in doubles).
  bool within_tolerance = false;
};

/// Cuts the openings (windows, doors) out of the planar polygon `surface`, exactly: `surface`
/// and the openings are charted on the dominant axis of the surface's Newell normal (the caller
/// has checked that the openings lie in its plane) and subtracted with exact Boolean operations
/// on the input doubles. An opening may touch the surface's boundary (a door on the floor line)
/// and other openings, but must lie inside the closed surface and not overlap another opening,
/// except by slivers no thicker than `tolerance` (a length in the chart: twice the area of each
/// piece outside, or of each overlap, over its perimeter).
OpeningsCut cut_openings(const std::vector<glm::dvec3>& surface,
                         const std::vector<std::vector<glm::dvec3>>& openings, double tolerance = 0.0);

}  // namespace shadow::detail
