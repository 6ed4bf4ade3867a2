// SPDX-License-Identifier: GPL-3.0-or-later
#include "support/polygon_tools.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadow::test {

glm::dvec3 newell_normal(const Polygon3& p) {
  glm::dvec3 n(0.0);
  const glm::dvec3 o = p.empty() ? glm::dvec3(0.0) : p[0];  // local frame for accuracy
  for (std::size_t a = 0; a < p.size(); ++a) {
    const glm::dvec3 u = p[a] - o, v = p[(a + 1) % p.size()] - o;
    n += glm::dvec3((u.y - v.y) * (u.z + v.z), (u.z - v.z) * (u.x + v.x), (u.x - v.x) * (u.y + v.y));
  }
  return n;
}

double polygon_area(const Polygon3& polygon) { return 0.5 * glm::length(newell_normal(polygon)); }

int dominant_axis(const glm::dvec3& n) {
  const glm::dvec3 a = glm::abs(n);
  if (a.x >= a.y && a.x >= a.z) return 0;
  return a.y >= a.z ? 1 : 2;
}

namespace {
double segment_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}
}  // namespace

bool inside_polygon(const Polygon3& polygon, const glm::dvec3& p, double* boundary_distance) {
  const int k = dominant_axis(newell_normal(polygon));
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  bool inside = false;
  double distance = std::numeric_limits<double>::max();
  const std::size_t n = polygon.size();
  for (std::size_t a = 0, b = n - 1; a < n; b = a++) {
    const glm::dvec3& u = polygon[a];
    const glm::dvec3& v = polygon[b];
    if ((u[j] > p[j]) != (v[j] > p[j]) &&
        p[i] < (v[i] - u[i]) * (p[j] - u[j]) / (v[j] - u[j]) + u[i])
      inside = !inside;
    distance = std::min(distance, segment_distance(p, u, v));
  }
  if (boundary_distance) *boundary_distance = distance;
  return inside;
}

std::vector<glm::dvec3> sample_interior(const Polygon3& polygon, int count, double margin,
                                        std::mt19937_64& rng) {
  std::vector<glm::dvec3> points;
  if (polygon.size() < 3) return points;
  const glm::dvec3 normal = newell_normal(polygon);
  const int k = dominant_axis(normal);
  if (normal[k] == 0) return points;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  glm::dvec3 lo = polygon[0], hi = polygon[0];
  for (const glm::dvec3& v : polygon) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  std::uniform_real_distribution<double> ui(lo[i], hi[i]), uj(lo[j], hi[j]);
  const glm::dvec3 o = polygon[0];
  for (int attempt = 0; attempt < 40 * count && static_cast<int>(points.size()) < count; ++attempt) {
    glm::dvec3 p(0.0);
    p[i] = ui(rng);
    p[j] = uj(rng);
    // On the plane: normal . (p - o) = 0.
    p[k] = o[k] - (normal[i] * (p[i] - o[i]) + normal[j] * (p[j] - o[j])) / normal[k];
    double d = 0;
    if (inside_polygon(polygon, p, &d) && d >= margin) points.push_back(p);
  }
  return points;
}

}  // namespace shadow::test
