// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/contacts.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace shadow::radiosity {
namespace {

using Box = std::array<double, 6>;

Box box_of(const std::vector<glm::dvec3>& v) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Box b = {inf, inf, inf, -inf, -inf, -inf};
  for (const glm::dvec3& p : v)
    for (int k = 0; k < 3; ++k) b[k] = std::min(b[k], p[k]), b[k + 3] = std::max(b[k + 3], p[k]);
  return b;
}

bool overlap(const Box& a, const Box& b, double tol) {
  for (int k = 0; k < 3; ++k)
    if (a[k] > b[k + 3] + tol || b[k] > a[k + 3] + tol) return false;
  return true;
}

/// The segment where polygon `g` meets the plane (n, p0): its vertices on the plane (within
/// tol) and its edges' crossings; false when it only touches it at one point or not at all.
bool meet_plane(const std::vector<glm::dvec3>& g, const glm::dvec3& n, const glm::dvec3& p0, double tol, Segment& s) {
  std::vector<glm::dvec3> on;
  const std::size_t m = g.size();
  for (std::size_t i = 0; i < m; ++i) {
    const glm::dvec3& a = g[i];
    const glm::dvec3& b = g[(i + 1) % m];
    const double da = glm::dot(n, a - p0), db = glm::dot(n, b - p0);
    if (std::abs(da) <= tol) on.push_back(a);
    if ((da > tol && db < -tol) || (da < -tol && db > tol)) on.push_back(a + (b - a) * (da / (da - db)));
  }
  if (on.size() < 2) return false;
  // The two points farthest apart (a convex face meets a plane in one segment; for another
  // face this covers its pieces, which only makes more cuts).
  double best = 0.0;
  for (std::size_t i = 0; i < on.size(); ++i)
    for (std::size_t j = i + 1; j < on.size(); ++j)
      if (glm::length(on[j] - on[i]) > best) best = glm::length(on[j] - on[i]), s = {on[i], on[j]};
  return best > 0.0;
}

}  // namespace

std::vector<std::vector<Segment>> contact_segments(const Scene& scene) {
  const std::size_t n = scene.faces.size();
  std::vector<std::vector<Segment>> out(n);
  std::vector<Box> boxes(n);
  std::vector<glm::dvec3> normals(n, glm::dvec3(0.0));
  for (std::size_t f = 0; f < n; ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) continue;
    boxes[f] = box_of(face.vertices);
    const glm::dvec3 nn = newell_normal(face.vertices);
    if (glm::length(nn) > 0.0) normals[f] = glm::normalize(nn);
  }
  for (std::size_t f = 0; f < n; ++f) {
    if (normals[f] == glm::dvec3(0.0)) continue;
    const Box& bf = boxes[f];
    const double size = std::max({bf[3] - bf[0], bf[4] - bf[1], bf[5] - bf[2]});
    const double tol = 1e-9 * (size + std::abs(bf[0]) + std::abs(bf[1]) + std::abs(bf[2]));
    const glm::dvec3& p0 = scene.faces[f].vertices[0];
    for (std::size_t g = 0; g < n; ++g) {
      if (g == f || normals[g] == glm::dvec3(0.0) || !overlap(bf, boxes[g], tol)) continue;
      if (glm::length(glm::cross(normals[f], normals[g])) < 1e-9) continue;  // parallel: no line
      Segment s;
      if (meet_plane(scene.faces[g].vertices, normals[f], p0, tol, s)) out[f].push_back(s);
    }
  }
  return out;
}

void cut_along(const Triangle& t, const glm::dvec3& normal, const std::vector<Segment>& segments,
               std::vector<Triangle>& out) {
  std::vector<Triangle> pieces = {t}, next;
  const double size = std::max({glm::length(t[1] - t[0]), glm::length(t[2] - t[1]), glm::length(t[0] - t[2])});
  std::vector<glm::dvec3> left, right;
  for (const Segment& s : segments) {
    const glm::dvec3 d = s.b - s.a;
    const double len = glm::length(d);
    if (!(len > 0.0)) continue;
    // Signed distance in the plane from the segment's line (positive to its left).
    auto side = [&](const glm::dvec3& p) { return glm::dot(glm::cross(d, p - s.a), normal) / len; };
    const double eps = 1e-9 * size;
    next.clear();
    for (const Triangle& u : pieces) {
      const std::array<double, 3> h = {side(u[0]), side(u[1]), side(u[2])};
      const bool pos = h[0] > eps || h[1] > eps || h[2] > eps, neg = h[0] < -eps || h[1] < -eps || h[2] < -eps;
      // The segment must reach the triangle: its part along the line where the line crosses u.
      bool reaches = pos && neg;
      if (reaches) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (int i = 0; i < 3; ++i) {
          const glm::dvec3& a = u[i];
          const glm::dvec3& b = u[(i + 1) % 3];
          const double ha = h[i], hb = h[(i + 1) % 3];
          auto add = [&](const glm::dvec3& p) {
            const double along = glm::dot(p - s.a, d) / (len * len);
            lo = std::min(lo, along), hi = std::max(hi, along);
          };
          if (std::abs(ha) <= eps) add(a);
          if ((ha > eps && hb < -eps) || (ha < -eps && hb > eps)) add(a + (b - a) * (ha / (ha - hb)));
        }
        reaches = hi > eps / len && lo < 1.0 - eps / len;
      }
      if (!reaches) {
        next.push_back(u);
        continue;
      }
      left.clear();
      right.clear();
      for (int i = 0; i < 3; ++i) {
        const glm::dvec3& a = u[i];
        const glm::dvec3& b = u[(i + 1) % 3];
        const double ha = h[i], hb = h[(i + 1) % 3];
        if (ha >= -eps) left.push_back(a);
        if (ha <= eps) right.push_back(a);
        if ((ha > eps && hb < -eps) || (ha < -eps && hb > eps)) {
          const glm::dvec3 c = a + (b - a) * (ha / (ha - hb));
          left.push_back(c);
          right.push_back(c);
        }
      }
      for (const std::vector<glm::dvec3>* poly : {&left, &right})
        for (std::size_t k = 1; k + 1 < poly->size(); ++k) {
          const Triangle piece = {(*poly)[0], (*poly)[k], (*poly)[k + 1]};
          if (triangle_area(piece) > 0.0) next.push_back(piece);
        }
    }
    pieces.swap(next);
  }
  out.insert(out.end(), pieces.begin(), pieces.end());
}

}  // namespace shadow::radiosity
