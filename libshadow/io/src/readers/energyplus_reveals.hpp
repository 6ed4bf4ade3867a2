// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: windows and doors set back from the plane of their base surface (a reveal), as
// EnergyPlus models them: where an opening lies against its wall, and the reveal's sides.
// docs/energyplus.md, "Windows in reveals".
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace shadow::scene_readers {

/// The deepest reveal read (metres, along the wall's normal): an opening offset further from its
/// base surface's plane is an error. Real walls are thinner; a larger offset is a drawing error.
inline constexpr double kMaxRevealDepth = 1.0;

/// Where an opening lies with respect to its base surface's plane.
struct OpeningPlacement {
  enum Kind {
    InPlane,  ///< every vertex within `allowed` of the plane: cut out as drawn
    SetBack,  ///< parallel to the plane, behind it (inside the wall) by `offset`: in a reveal
    Proud,    ///< parallel to the plane, in front of it (outside) by `offset`
    TooDeep,  ///< parallel, but offset by more than kMaxRevealDepth
    Skew,     ///< not parallel to the plane: `vertex` is `distance` off it
  } kind = InPlane;
  /// The mean signed distance of the vertices from the plane, + outward (along the wall's
  /// normal): negative for SetBack, positive for Proud.
  double offset = 0.0;
  /// Skew: the vertex farthest from the plane and its distance.
  glm::dvec3 vertex{0.0};
  double distance = 0.0;
  /// SetBack, Proud: the opening's outline moved along the normal into the plane (the hole cut
  /// out of the wall); InPlane: the opening as drawn.
  std::vector<glm::dvec3> outline;
};

/// Classifies `opening` against the plane through `origin` with unit normal `normal` (its base
/// surface's, pointing out). An opening is parallel when its vertices' distances from the plane
/// differ by at most `allowed` (the planarity tolerance times the wall's size).
OpeningPlacement place_opening(const std::vector<glm::dvec3>& opening, const glm::dvec3& origin,
                               const glm::dvec3& normal, double allowed);

/// The reveal's sides of an opening set back from its wall: for each edge of the opening, the
/// quadrilateral joining it to the same edge of `outline` (the hole in the wall's plane), in the
/// opening's vertex order: the jambs, head and sill of a rectangular window. Sides of zero area
/// (an edge seen end on) are left out.
std::vector<std::vector<glm::dvec3>> reveal_sides(const std::vector<glm::dvec3>& opening,
                                                  const std::vector<glm::dvec3>& outline);

}  // namespace shadow::scene_readers
