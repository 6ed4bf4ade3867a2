// SPDX-License-Identifier: GPL-3.0-or-later
// Unit vectors in doubles: `unit` for directions that are known to be non-zero (any finite scale),
// `unit_or_zero` where a zero vector must stay zero (display, shading).
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace shadow::geometry {

/// A unit vector along v for any finite non-zero v, even when |v|^2 under- or overflows
/// (to_light = (1e-200, 0, 1e-200) is a valid direction).
inline glm::dvec3 unit(glm::dvec3 v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return glm::normalize(v / m);
}

/// v / |v|, or zero when v has no usable direction (zero, or |v| not finite).
inline glm::dvec3 unit_or_zero(const glm::dvec3& v) {
  const double length = glm::length(v);
  if (!std::isfinite(length) || length == 0.0) return glm::dvec3(0.0);
  return v / length;
}

}  // namespace shadow::geometry
