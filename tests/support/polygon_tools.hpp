// SPDX-License-Identifier: GPL-3.0-or-later
// Double-precision polygon helpers for tests, independent of the library's exact core.
#pragma once

#include <glm/vec3.hpp>

#include <random>
#include <vector>

namespace shadow::test {

using Polygon3 = std::vector<glm::dvec3>;

/// Newell normal (twice the area vector) of a closed polygon.
glm::dvec3 newell_normal(const Polygon3& polygon);

/// Area of a planar polygon.
double polygon_area(const Polygon3& polygon);

/// Axis dropped by the 2D chart of a polygon (the dominant axis of its normal).
int dominant_axis(const glm::dvec3& normal);

/// True if `p` (on the polygon's plane) is inside the polygon; `boundary_distance` receives its
/// distance to the polygon's boundary.
bool inside_polygon(const Polygon3& polygon, const glm::dvec3& p, double* boundary_distance = nullptr);

/// Up to `count` random points inside the polygon at least `margin` from its boundary
/// (rejection sampling; thin polygons may yield fewer).
std::vector<glm::dvec3> sample_interior(const Polygon3& polygon, int count, double margin,
                                        std::mt19937_64& rng);

}  // namespace shadow::test
