// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/shaft.hpp"

#include "radiosity/triangles.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadow::radiosity {

ShaftCuller::ShaftCuller(const Scene& scene) : scene_(scene) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  boxes_.assign(scene.faces.size(), {inf, inf, inf, -inf, -inf, -inf});
  normals_.assign(scene.faces.size(), glm::dvec3(0.0));
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) continue;
    const glm::dvec3 n = newell_normal(face.vertices);
    if (!(glm::length(n) > 0.0)) continue;
    normals_[f] = glm::normalize(n);
    for (const glm::dvec3& v : face.vertices)
      for (int k = 0; k < 3; ++k) boxes_[f][k] = std::min(boxes_[f][k], v[k]), boxes_[f][k + 3] = std::max(boxes_[f][k + 3], v[k]);
    by_x_.push_back(f);
    widest_x_ = std::max(widest_x_, boxes_[f][3] - boxes_[f][0]);
  }
  std::sort(by_x_.begin(), by_x_.end(), [&](std::size_t p, std::size_t q) { return boxes_[p][0] < boxes_[q][0]; });
  for (std::size_t f : by_x_) lower_x_.push_back(boxes_[f][0]);
}

void ShaftCuller::candidates(const std::vector<glm::dvec3>& a, std::size_t a_face, const std::vector<glm::dvec3>& b,
                             std::size_t b_face, Scratch& s, std::vector<std::size_t>& out) const {
  out.clear();
  s.points.assign(a.begin(), a.end());
  s.points.insert(s.points.end(), b.begin(), b.end());
  const std::size_t m = s.points.size();
  std::array<double, 6> box = {s.points[0].x, s.points[0].y, s.points[0].z, s.points[0].x, s.points[0].y, s.points[0].z};
  for (const glm::dvec3& p : s.points)
    for (int k = 0; k < 3; ++k) box[k] = std::min(box[k], p[k]), box[k + 3] = std::max(box[k + 3], p[k]);
  const double size = std::max({box[3] - box[0], box[4] - box[1], box[5] - box[2]});
  const double tol = 1e-12 * (size + std::abs(box[0]) + std::abs(box[1]) + std::abs(box[2]));
  // The hull's facets by brute force: a plane through three of the points that has all of
  // them on one side (at most 8 points here: 56 triples).
  s.planes.clear();
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j)
      for (std::size_t k = j + 1; k < m; ++k) {
        glm::dvec3 n = glm::cross(s.points[j] - s.points[i], s.points[k] - s.points[i]);
        const double len = glm::length(n);
        if (!(len > 1e-12 * size * size)) continue;
        n /= len;
        bool below = true, above = true;
        for (const glm::dvec3& p : s.points) {
          const double d = glm::dot(n, p - s.points[i]);
          below = below && d <= tol;
          above = above && d >= -tol;
        }
        if (below == above) continue;  // not a facet (or every point on the plane: a flat shaft)
        if (above) n = -n;
        s.planes.push_back({n.x, n.y, n.z, glm::dot(n, s.points[i])});
      }
  auto first = std::lower_bound(lower_x_.begin(), lower_x_.end(), box[0] - widest_x_ - tol) - lower_x_.begin();
  for (std::size_t r = static_cast<std::size_t>(first); r < by_x_.size() && lower_x_[r] <= box[3] + tol; ++r) {
    const std::size_t f = by_x_[r];
    if (f == a_face || f == b_face) continue;
    const std::array<double, 6>& fb = boxes_[f];
    if (fb[3] < box[0] - tol || fb[4] < box[1] - tol || fb[5] < box[2] - tol || fb[1] > box[4] + tol ||
        fb[2] > box[5] + tol)
      continue;
    const std::vector<glm::dvec3>& v = scene_.faces[f].vertices;
    // Both polygons on one side of the face's plane (or on it): it cannot stand between.
    const glm::dvec3& n = normals_[f];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const glm::dvec3& p : s.points) {
      const double d = glm::dot(n, p - v[0]);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    if (lo >= -tol || hi <= tol) continue;
    // Every vertex on the outside of (or on) one facet: it misses the open hull.
    bool outside = false;
    for (const std::array<double, 4>& pl : s.planes) {
      bool all = true;
      for (const glm::dvec3& p : v) all = all && pl[0] * p.x + pl[1] * p.y + pl[2] * p.z - pl[3] >= -tol;
      if (all) {
        outside = true;
        break;
      }
    }
    if (!outside) out.push_back(f);
  }
}

}  // namespace shadow::radiosity
