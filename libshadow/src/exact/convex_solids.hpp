// SPDX-License-Identifier: GPL-3.0-or-later
// Closed convex solids among a scene's faces (boxes, say). A solid casts one polygon: the convex
// hull of its projected vertices, instead of one polygon per face whose projections share edges
// exactly and make the exact union expensive.
#pragma once

#include "exact/face_prep.hpp"

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace shadow::exact {

/// A closed convex polyhedron made of scene faces (a box, say), fronts outward. Whatever a
/// ray crosses it through, it crosses its boundary, so the solid can cast as one polygon: the
/// convex hull of its projected vertices (clipped to the receiver's front), instead of one
/// polygon per face whose projections share edges and make the union expensive.
struct ConvexSolid {
  std::vector<glm::dvec3> vertices;         ///< unique vertices
  std::vector<std::array<int, 2>> edges;    ///< unique edges (indices into vertices)
};

/// Finds the closed convex solids among each mesh's faces: faces joined by shared edges (equal
/// vertex coordinates), every edge used exactly twice in opposite directions, and every vertex
/// of the solid on or behind every face's plane (decided with exact predicates). Only exactly
/// planar faces take part. `solid_of[f]` receives the solid of face f, or -1.
std::vector<ConvexSolid> find_convex_solids(const Scene& scene, const std::vector<FacePrep>& prep,
                                            std::vector<int>& solid_of);

}  // namespace shadow::exact
