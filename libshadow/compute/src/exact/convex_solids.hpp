// SPDX-License-Identifier: GPL-3.0-or-later
// Finding the closed convex solids among a scene's faces (boxes, say): needs exact predicates,
// so it lives here; the core::ConvexSolid struct itself is in core/convex_solid.hpp (the fast path uses it).
#pragma once

#include "core/convex_solid.hpp"
#include "core/face_prep.hpp"
#include "runtime/uninit_vector.hpp"

#include <shadow/scene.hpp>

#include <cstddef>
#include <vector>

namespace shadow::exact {

/// Finds the closed convex solids among each mesh's faces: faces joined by shared edges (equal
/// vertex coordinates), every edge used exactly twice in opposite directions, and every vertex
/// of the solid on or behind every face's plane (decided with exact predicates). Only exactly
/// planar faces take part. `solid_of[f]` receives the solid of face f, or -1.
/// The solids come in the order of their union-find roots (see convex_solids.cpp); the per-solid
/// work runs on `threads` threads (0: every hardware thread), with the same result for any count.
///
/// With `closed_outward`, the parts that close up but are not convex are also told (sized to
/// the faces): +1 for a face of a closed, embedded solid whose vertex order turns its normal
/// outward, -1 when it turns it inward; +2 and -2 the same for a part open only along border
/// loops that each lie in one horizontal plane (walls and roof without a floor), closed by caps
/// facing down from the solid, so valid only under a light above the horizon; 0 otherwise (see
/// closed_part_orientation: exactly planar faces, every other edge used twice in opposite
/// directions, a valid manifold surface mesh that does not intersect itself, decided with exact
/// predicates). Under a directional light such a solid's faces turned away from the light add
/// nothing to its shadow (docs/algorithm.md, "Closed solids cast through the faces facing the
/// light").
std::vector<core::ConvexSolid> find_convex_solids(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                            std::vector<int>& solid_of, unsigned threads = 0,
                                            std::vector<signed char>* closed_outward = nullptr);

/// Below this many corners number_vertices runs on one thread.
inline constexpr std::size_t kParallelNumberingCorners = 4096;

/// The vertices of the faces that take part in the search (exactly planar, not degenerate), by
/// exact coordinates (-0.0 as 0.0), numbered in order of first use: `corner_vertex` (sized to
/// their corners) gets each corner's id, faces in order; `vertex_position` each id's position.
/// On `threads` threads (0: every hardware thread) from kParallelNumberingCorners corners on,
/// with the same ids for any count.
void number_vertices(const Scene& scene, const std::vector<core::FacePrep>& prep,
                     runtime::UninitVector<int>& corner_vertex, runtime::UninitVector<glm::dvec3>& vertex_position,
                     unsigned threads);

/// The previous implementation (ordered maps, one thread), kept as the reference that tests
/// and shadow-bench compare find_convex_solids with: the same solids in the same order.
std::vector<core::ConvexSolid> find_convex_solids_reference(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                                      std::vector<int>& solid_of);

}  // namespace shadow::exact
