// SPDX-License-Identifier: GPL-3.0-or-later
// Openings set back from their wall (energyplus_reveals.hpp): the hole is the opening moved
// along the wall's normal into the wall's plane, and the reveal joins the two outlines.
#include "readers/energyplus_reveals.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace shadow::scene_readers {
namespace {

double dot(const glm::dvec3& a, const glm::dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// `p` moved along `normal` into the plane; the coordinate along the normal's dominant axis is
/// then solved from the plane's equation, so that a wall along an axis gets the wall's own
/// coordinate exactly and the other two stay as drawn (the hole's chart points are then the
/// opening's own doubles, as cut_openings charts on that axis).
glm::dvec3 into_plane(const glm::dvec3& p, const glm::dvec3& origin, const glm::dvec3& normal) {
  glm::dvec3 q = p - dot(p - origin, normal) * normal;
  const glm::dvec3 a(std::abs(normal.x), std::abs(normal.y), std::abs(normal.z));
  const int k = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  // Exact zeros in the normal keep those coordinates as drawn.
  if (normal[i] == 0.0) q[i] = p[i];
  if (normal[j] == 0.0) q[j] = p[j];
  q[k] = origin[k] - (normal[i] * (q[i] - origin[i]) + normal[j] * (q[j] - origin[j])) / normal[k];
  return q;
}

}  // namespace

OpeningPlacement place_opening(const std::vector<glm::dvec3>& opening, const glm::dvec3& origin,
                               const glm::dvec3& normal, double allowed) {
  OpeningPlacement placement;
  if (opening.empty()) return placement;
  double lowest = 0.0, highest = 0.0, sum = 0.0, farthest = -1.0;
  for (std::size_t v = 0; v < opening.size(); ++v) {
    const double d = dot(opening[v] - origin, normal);
    lowest = v == 0 ? d : std::min(lowest, d);
    highest = v == 0 ? d : std::max(highest, d);
    sum += d;
    if (std::abs(d) > farthest) {
      farthest = std::abs(d);
      placement.vertex = opening[v];
      placement.distance = std::abs(d);
    }
  }
  if (!(farthest > allowed)) {
    placement.kind = OpeningPlacement::InPlane;
    placement.outline = opening;
    return placement;
  }
  if (!(highest - lowest <= allowed)) {
    placement.kind = OpeningPlacement::Skew;
    return placement;
  }
  placement.offset = sum / static_cast<double>(opening.size());
  if (!(std::abs(placement.offset) <= kMaxRevealDepth)) {
    placement.kind = OpeningPlacement::TooDeep;
    return placement;
  }
  placement.kind = placement.offset < 0 ? OpeningPlacement::SetBack : OpeningPlacement::Proud;
  for (const glm::dvec3& p : opening) placement.outline.push_back(into_plane(p, origin, normal));
  return placement;
}

std::vector<std::vector<glm::dvec3>> reveal_sides(const std::vector<glm::dvec3>& opening,
                                                  const std::vector<glm::dvec3>& outline) {
  std::vector<std::vector<glm::dvec3>> sides;
  const std::size_t n = std::min(opening.size(), outline.size());
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    if (opening[a] == opening[b] || outline[a] == outline[b]) continue;  // a repeated vertex: no side
    // Outline edge a -> b in the wall's plane, back along the opening's edge b -> a.
    sides.push_back({outline[a], outline[b], opening[b], opening[a]});
  }
  return sides;
}

}  // namespace shadow::scene_readers
