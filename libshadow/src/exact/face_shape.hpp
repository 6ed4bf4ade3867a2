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
FaceShape classify_face_shape(const std::vector<glm::dvec3>& vertices);

}  // namespace shadow::detail
