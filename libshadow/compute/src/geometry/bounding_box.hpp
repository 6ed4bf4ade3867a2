// SPDX-License-Identifier: GPL-3.0-or-later
// The axis-aligned bounding box of points (a scene's faces, a polygon), with its centre and
// diagonal. Doubles only: every caller wants a frame, not an exact box.
#pragma once

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <limits>

namespace shadow::geometry {

struct BoundingBox {
  glm::dvec3 lo{std::numeric_limits<double>::max()};
  glm::dvec3 hi{std::numeric_limits<double>::lowest()};
  bool any = false;  ///< a point was added

  void add(const glm::dvec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    any = true;
  }
  [[nodiscard]] glm::dvec3 centre() const { return 0.5 * (lo + hi); }
  [[nodiscard]] double diagonal() const { return glm::length(hi - lo); }
};

/// The bounding box of the vertices of `faces` (anything with a `vertices` range of dvec3),
/// skipping the faces for which skip(face) is true.
template <class Faces, class Skip>
BoundingBox faces_bounding_box(const Faces& faces, Skip skip) {
  BoundingBox box;
  for (const auto& face : faces) {
    if (skip(face)) continue;
    for (const glm::dvec3& v : face.vertices) box.add(v);
  }
  return box;
}

/// The bounding box of every face's vertices.
template <class Faces>
BoundingBox faces_bounding_box(const Faces& faces) {
  return faces_bounding_box(faces, [](const auto&) { return false; });
}

}  // namespace shadow::geometry
