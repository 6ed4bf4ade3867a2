// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/triangles.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstddef>

namespace shadow::radiosity {

glm::dvec3 newell_normal(const std::vector<glm::dvec3>& polygon) {
  glm::dvec3 n(0.0);
  const std::size_t m = polygon.size();
  if (m == 0) return n;
  // Relative to the first vertex: georeferenced coordinates keep their digits.
  for (std::size_t i = 0; i < m; ++i) n += glm::cross(polygon[i] - polygon[0], polygon[(i + 1) % m] - polygon[0]);
  return n;
}

bool inside_polygon(const std::vector<glm::dvec3>& polygon, const glm::dvec3& normal, const glm::dvec3& p) {
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(normal[a]) > std::abs(normal[k])) k = a;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  bool in = false;
  for (std::size_t a = 0, b = polygon.size() - 1; a < polygon.size(); b = a++) {
    const glm::dvec3 &u = polygon[a], &v = polygon[b];
    if ((u[j] > p[j]) != (v[j] > p[j]) && p[i] < (v[i] - u[i]) * (p[j] - u[j]) / (v[j] - u[j]) + u[i]) in = !in;
  }
  return in;
}

double triangle_area(const Triangle& t) { return 0.5 * glm::length(glm::cross(t[1] - t[0], t[2] - t[0])); }

namespace {

/// Twice the signed area of (a, b, c) in the chart that drops axis k, positive when
/// counter-clockwise seen along +k (sign flipped with `flip`).
double cross2(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int k, bool flip) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const double v = (b[i] - a[i]) * (c[j] - a[j]) - (b[j] - a[j]) * (c[i] - a[i]);
  return flip ? -v : v;
}

}  // namespace

std::vector<Triangle> triangulate(const std::vector<glm::dvec3>& polygon) {
  std::vector<Triangle> out;
  if (polygon.size() < 3) return out;
  const glm::dvec3 n = newell_normal(polygon);
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) > std::abs(n[k])) k = a;
  const bool flip = n[k] < 0;
  std::vector<std::size_t> ring(polygon.size());
  for (std::size_t i = 0; i < ring.size(); ++i) ring[i] = i;
  const double scale = glm::length(n);
  auto keep = [&](std::size_t a, std::size_t b, std::size_t c) {
    const Triangle t{polygon[a], polygon[b], polygon[c]};
    if (triangle_area(t) > 1e-14 * scale) out.push_back(t);
  };
  std::size_t guard = 0;
  while (ring.size() > 3 && guard < 4 * polygon.size() * polygon.size()) {
    ++guard;
    bool cut = false;
    for (std::size_t i = 0; i < ring.size() && !cut; ++i) {
      const std::size_t ia = ring[(i + ring.size() - 1) % ring.size()], ib = ring[i], ic = ring[(i + 1) % ring.size()];
      const glm::dvec3 &a = polygon[ia], &b = polygon[ib], &c = polygon[ic];
      const double turn = cross2(a, b, c, k, flip);
      if (turn < 0) continue;  // a reflex corner is no ear
      bool empty = true;
      if (turn > 0)
        for (std::size_t p : ring) {
          if (p == ia || p == ib || p == ic) continue;
          const glm::dvec3& q = polygon[p];
          if (cross2(a, b, q, k, flip) >= 0 && cross2(b, c, q, k, flip) >= 0 && cross2(c, a, q, k, flip) >= 0) {
            empty = false;
            break;
          }
        }
      if (!empty) continue;
      if (turn > 0) keep(ia, ib, ic);  // a straight corner is dropped without a triangle
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      cut = true;
    }
    if (!cut) break;
  }
  if (ring.size() == 3) {
    keep(ring[0], ring[1], ring[2]);
  } else if (ring.size() > 3) {
    // No ear found (a polygon that is not quite simple after rounding): a fan of what is left.
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) keep(ring[0], ring[i], ring[i + 1]);
  }
  return out;
}

void refine(const Triangle& t, double max_area, std::vector<Triangle>& out, double max_edge) {
  // The longest edge (i, i + 1) is halved; the two halves keep the orientation.
  int i = 0;
  double best = -1;
  for (int e = 0; e < 3; ++e) {
    const double len = glm::length(t[(e + 1) % 3] - t[e]);
    if (len > best) best = len, i = e;
  }
  const bool small_enough = !(max_area > 0) || triangle_area(t) <= max_area;
  const bool short_enough = !(max_edge > 0) || best <= max_edge;
  if (small_enough && short_enough) {
    out.push_back(t);
    return;
  }
  const glm::dvec3& a = t[i];
  const glm::dvec3& b = t[(i + 1) % 3];
  const glm::dvec3& c = t[(i + 2) % 3];
  const glm::dvec3 m = 0.5 * (a + b);
  refine({a, m, c}, max_area, out, max_edge);
  refine({m, b, c}, max_area, out, max_edge);
}

void gauss_legendre01(int order, std::vector<double>& nodes, std::vector<double>& weights) {
  nodes.assign(static_cast<std::size_t>(order), 0.0);
  weights.assign(static_cast<std::size_t>(order), 0.0);
  constexpr double kPi = 3.14159265358979323846;
  for (int i = 0; i < order; ++i) {
    // Newton's iteration on P_n from Tricomi's first guess.
    double x = std::cos(kPi * (i + 0.75) / (order + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= order; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (order == 1) p1 = x, p0 = 1.0;
      dp = order * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= order; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    dp = order * (x * p1 - p0) / (x * x - 1.0);
    nodes[static_cast<std::size_t>(i)] = 0.5 * (1.0 - x);
    weights[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - x * x) * dp * dp);  // 2/((1-x^2)P'^2), halved
  }
}

}  // namespace shadow::radiosity
