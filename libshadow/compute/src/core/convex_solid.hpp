// SPDX-License-Identifier: GPL-3.0-or-later
// A closed convex solid among a scene's faces (boxes, say). A solid casts one polygon: the convex
// hull of its projected vertices, instead of one polygon per face whose projections share edges
// exactly and make the exact union expensive. Found by exact/convex_solids.hpp; used by the exact
// and the fast path alike, hence plain numbers here.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace shadow::core {

/// A closed convex polyhedron made of scene faces (a box, say), fronts outward. Whatever a
/// ray crosses it through, it crosses its boundary, so the solid can cast as one polygon: the
/// convex hull of its projected vertices (clipped to the receiver's front), instead of one
/// polygon per face whose projections share edges and make the union expensive.
struct ConvexSolid {
  std::vector<glm::dvec3> vertices;         ///< unique vertices
  std::vector<std::array<int, 2>> edges;    ///< unique edges (indices into vertices)
};

}  // namespace shadow::core
