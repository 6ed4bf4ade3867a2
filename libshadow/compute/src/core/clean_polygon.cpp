// SPDX-License-Identifier: GPL-3.0-or-later
// clean_double_polygon (core/face_prep.hpp): the output contract's check on a fragment of doubles,
// shared by the exact and the fast path. It needs exact predicates on doubles only, so it uses
// CGAL's Epick (filtered predicates, no exact constructions), as fast/ does; no CGAL type leaves
// this file.
#include "core/face_prep.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace shadow::core {

bool clean_double_polygon(std::vector<glm::dvec3>& polygon, int k) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<glm::dvec3> kept;
  kept.reserve(polygon.size());
  for (const glm::dvec3& v : polygon)
    if (kept.empty() || v != kept.back()) kept.push_back(v);
  while (kept.size() > 1 && kept.back() == kept.front()) kept.pop_back();
  polygon.swap(kept);
  if (polygon.size() < 3) return false;
  for (const glm::dvec3& v : polygon)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
  const int i = chart_i(k), j = chart_j(k);
  CGAL::Polygon_2<K> chart;
  for (const glm::dvec3& v : polygon) chart.push_back(K::Point_2(v[i], v[j]));
  // Distinct chart points (a repeat is a touch, not simple), then a simplicity sweep.
  std::vector<K::Point_2> sorted(chart.vertices_begin(), chart.vertices_end());
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  if (!chart.is_simple()) return false;
  if (chart.orientation() == CGAL::COLLINEAR) return false;
  // Non-zero area is not enough for a user's double arithmetic: a triangle of 1e-33 m^2 with
  // distinct vertices has an exact area but a shoelace in doubles gets 0 or noise. Ask that the
  // shoelace relative to the first vertex, in doubles, is non-zero beyond its rounding bound
  // ((n + 4) eps times the sum of its terms' magnitudes).
  double twice_area = 0, magnitude = 0;
  const glm::dvec3& o = polygon[0];
  for (std::size_t a = 1; a + 1 < polygon.size(); ++a) {
    const double ux = polygon[a][i] - o[i], uy = polygon[a][j] - o[j];
    const double vx = polygon[a + 1][i] - o[i], vy = polygon[a + 1][j] - o[j];
    twice_area += ux * vy - uy * vx;
    magnitude += std::abs(ux * vy) + std::abs(uy * vx);
  }
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double slack = (static_cast<double>(polygon.size()) + 4) * eps;
  if (!(std::abs(twice_area) > slack * magnitude)) return false;
  // The same area from absolute coordinates, as Newell's formula (the usual way to take a
  // polygon's normal) computes it: far from the origin (georeferenced models at 4e6 m) a sliver
  // narrower than an ulp of its coordinates passes the test above but cancels to a zero normal
  // here. Such a cell is no polygon for its readers.
  double newell = 0, newell_magnitude = 0;
  for (std::size_t a = 0; a < polygon.size(); ++a) {
    const glm::dvec3& u = polygon[a];
    const glm::dvec3& v = polygon[(a + 1) % polygon.size()];
    const double term = (u[i] - v[i]) * (u[j] + v[j]);
    newell += term;
    newell_magnitude += std::abs(term);
  }
  return std::abs(newell) > slack * newell_magnitude;
}

}  // namespace shadow::core
