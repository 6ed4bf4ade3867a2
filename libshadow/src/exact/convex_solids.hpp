// SPDX-License-Identifier: GPL-3.0-or-later
// Finding the closed convex solids among a scene's faces (boxes, say): needs exact predicates,
// so it lives here; the core::ConvexSolid struct itself is in core/convex_solid.hpp (the fast path uses it).
#pragma once

#include "core/convex_solid.hpp"
#include "core/face_prep.hpp"

#include <shadow/scene.hpp>

#include <vector>

namespace shadow::exact {

/// Finds the closed convex solids among each mesh's faces: faces joined by shared edges (equal
/// vertex coordinates), every edge used exactly twice in opposite directions, and every vertex
/// of the solid on or behind every face's plane (decided with exact predicates). Only exactly
/// planar faces take part. `solid_of[f]` receives the solid of face f, or -1.
std::vector<core::ConvexSolid> find_convex_solids(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                            std::vector<int>& solid_of);

}  // namespace shadow::exact
