// SPDX-License-Identifier: GPL-3.0-or-later
// The scene as culling sees it: every face in a local frame (the scene's centre subtracted) with
// a unit normal and the bounds of its errors (docs/numeric-contract.md, "Culling"), and boxes
// around faces in that frame. Made once per scene; every light's culling reads it.
#pragma once

#include "core/face_prep.hpp"
#include "runtime/uninit_vector.hpp"

#include <shadow/scene.hpp>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <limits>
#include <vector>

namespace shadow::core {


/// A face in a local frame (scene centre subtracted) with a unit normal, for culling. Plain
/// data without defaults: make_cull_scene sets every field of every face on the thread of its
/// block, so that a million faces' 64 MB are not first written (zeroed) on one thread before.
struct CullFace {
  std::size_t first, count;  ///< range in CullScene::vertices
  glm::dvec3 normal;         ///< unit normal (front side); 0 for a degenerate face
  /// Rigorous bound on |normal - the exact unit Newell normal| (up to 2: direction unknown).
  /// Large for thin faces, whose rounded edge vectors lose the normal's direction.
  double normal_error;
  double offset;  ///< plane: normal . p + offset = 0 (local frame)
  /// How far the exact engine may move a vertex of this face: faces that are planar only within
  /// tolerance are lifted onto their exact plane; culling must allow for it. 0 if exactly planar.
  double slack;
};

/// Whether the face's normal, times `outward` (+1 its front, -1 its back), certainly points away
/// from `to_light` (a unit vector): the normal's direction is known within normal_error, and the
/// two unit vectors' rounding and dot product are within 16 eps. (False for a degenerate face,
/// whose error is 2.)
inline bool certainly_turned_away(const CullFace& face, const glm::dvec3& to_light, double outward = 1.0) {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  return outward * glm::dot(face.normal, to_light) < -(face.normal_error + 16 * eps);
}

struct CullScene {
  glm::dvec3 origin{0.0};
  double diameter = 1.0;
  /// The faces' vertices in the local frame, and the faces. Filled on every thread by
  /// make_cull_scene (UninitVector: their pages first touched there).
  runtime::UninitVector<glm::dvec3> vertices;
  runtime::UninitVector<CullFace> faces;
  /// Per face, when some face is on a closed solid that is not convex (else empty): +1 when its
  /// normal points out of the solid, -1 when into it, +2 and -2 the same on a solid closed by
  /// horizontal caps facing down (walls and roofs without a floor: valid under a light above
  /// the horizon only), 0 when it is on none (exact::find_convex_solids' closed_outward). Under
  /// a directional light the solid's faces turned away from it cast nothing that its faces
  /// turned to it do not (ReceiverCuller).
  std::vector<signed char> closed_outward;
};

/// A box in the local frame (CullScene's) around some faces' vertices, with the largest of their
/// slacks: what ReceiverCuller::may_cast_any needs to rule out every one of those faces at once.
struct LocalBounds {
  glm::dvec3 lo{0.0}, hi{0.0};
  double slack = 0;
};

/// Each face's LocalBounds (a degenerate face's too: it is never asked for), on `threads`
/// threads. They do not depend on the light: a series makes them once for all its suns.
std::vector<LocalBounds> face_bounds(const CullScene& scene, unsigned threads = 1);

/// The centre and diagonal of the faces' bounding box (origin and 1 for a scene without faces).
struct SceneFrame {
  glm::dvec3 centre{0.0};
  double diagonal = 1.0;
};
/// With `threads` > 1 the box is found by blocks of faces on that many threads, merged in order:
/// the same box (every coordinate, -0.0 as one thread finds it) for any count.
SceneFrame scene_frame(const Scene& scene, unsigned threads = 1);

/// The faces in a local frame (scene centre subtracted), with unit normals; the faces divided
/// among `threads` threads (0 counts as 1; the result does not depend on it).
CullScene make_cull_scene(const Scene& scene, const std::vector<FacePrep>& prep, unsigned threads = 1);

}  // namespace shadow::core
