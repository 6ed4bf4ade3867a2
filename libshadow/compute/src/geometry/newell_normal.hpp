// SPDX-License-Identifier: GPL-3.0-or-later
// Newell's normal of a closed polygon: 2 x its signed area vector, for any number type (double,
// long double, GMP, CGAL's exact numbers). Written once; each caller keeps its own summation
// (plain running sum in doubles, balanced trees for lazy exact values) and its own origin.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <vector>

namespace shadow::geometry {

/// The term of edge (u, v) in Newell's sum, componentwise:
/// ((u_y - v_y)(u_z + v_z), (u_z - v_z)(u_x + v_x), (u_x - v_x)(u_y + v_y)).
template <class T>
std::array<T, 3> newell_term(const T& ux, const T& uy, const T& uz, const T& vx, const T& vy, const T& vz) {
  return {(uy - vy) * (uz + vz), (uz - vz) * (ux + vx), (ux - vx) * (uy + vy)};
}

/// newell_term for glm vectors (same operations, same order).
template <class T, glm::qualifier Q>
glm::vec<3, T, Q> newell_term(const glm::vec<3, T, Q>& u, const glm::vec<3, T, Q>& v) {
  return glm::vec<3, T, Q>((u.y - v.y) * (u.z + v.z), (u.z - v.z) * (u.x + v.x), (u.x - v.x) * (u.y + v.y));
}

/// Newell's normal (not normalised: its length is twice the area) as a running sum in order.
template <class T, glm::qualifier Q>
glm::vec<3, T, Q> newell_normal(const std::vector<glm::vec<3, T, Q>>& polygon) {
  glm::vec<3, T, Q> n(T(0));
  const std::size_t count = polygon.size();
  for (std::size_t a = 0; a < count; ++a) n += newell_term(polygon[a], polygon[(a + 1) % count]);
  return n;
}

/// Newell's normal with every vertex taken relative to `origin` (usually the first vertex): the
/// sums then stay small, so a small face far from the origin keeps its normal's direction.
template <class T, glm::qualifier Q>
glm::vec<3, T, Q> newell_normal(const std::vector<glm::vec<3, T, Q>>& polygon, const glm::vec<3, T, Q>& origin) {
  glm::vec<3, T, Q> n(T(0));
  const std::size_t count = polygon.size();
  for (std::size_t a = 0; a < count; ++a)
    n += newell_term(polygon[a] - origin, polygon[(a + 1) % count] - origin);
  return n;
}

}  // namespace shadow::geometry
