// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: triangles of planar polygons for radiosity's elements and quadrature (doubles).
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace shadow::radiosity {

using Triangle = std::array<glm::dvec3, 3>;

/// Newell's normal of a polygon (length twice its area for a planar one).
glm::dvec3 newell_normal(const std::vector<glm::dvec3>& polygon);

double triangle_area(const Triangle& t);

/// Interior point c (0, 1, 2) of the degree-2 triangle rule, (4 t[c] + t[c+1] + t[c+2]) / 6:
/// halfway from the centroid to corner c.
inline glm::dvec3 interior_point(const Triangle& t, int c) {
  return (4.0 * t[c] + t[(c + 1) % 3] + t[(c + 2) % 3]) / 6.0;
}

/// Whether `p` (on the plane of `polygon`, whose normal is `normal`, any length) lies inside it:
/// the even-odd rule in the chart that drops the normal's largest axis.
bool inside_polygon(const std::vector<glm::dvec3>& polygon, const glm::dvec3& normal, const glm::dvec3& p);

/// The triangles of a simple planar polygon (ear clipping in its dominant chart), each with the
/// polygon's orientation; triangles of zero area are left out.
std::vector<Triangle> triangulate(const std::vector<glm::dvec3>& polygon);

/// Appends `t` split by longest-edge bisection until no piece has more area than `max_area` nor
/// an edge longer than `max_edge` (a limit <= 0: none).
void refine(const Triangle& t, double max_area, std::vector<Triangle>& out, double max_edge = 0.0);

/// Gauss-Legendre nodes and weights on [0, 1] with `order` points.
void gauss_legendre01(int order, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace shadow::radiosity
