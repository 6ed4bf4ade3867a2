// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/shaft.hpp"

#include "radiosity/triangles.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace shadow::radiosity {

ShaftCuller::ShaftCuller(const Scene& scene) : scene_(scene) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  boxes_.assign(scene.faces.size(), {inf, inf, inf, -inf, -inf, -inf});
  normals_.assign(scene.faces.size(), glm::dvec3(0.0));
  convex_.assign(scene.faces.size(), 0);
  std::array<double, 4> all = {inf, inf, -inf, -inf};
  std::size_t usable = 0;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) continue;
    const glm::dvec3 n = newell_normal(face.vertices);
    if (!(glm::length(n) > 0.0)) continue;
    normals_[f] = glm::normalize(n);
    const std::vector<glm::dvec3>& v = face.vertices;
    bool convex = true;
    for (std::size_t a = 0; a < v.size() && convex; ++a)
      convex = glm::dot(glm::cross(v[(a + 1) % v.size()] - v[a], v[(a + 2) % v.size()] - v[(a + 1) % v.size()]),
                        normals_[f]) > 0;
    convex_[f] = convex ? 1 : 0;
    for (const glm::dvec3& p : v)
      for (int k = 0; k < 3; ++k) boxes_[f][k] = std::min(boxes_[f][k], p[k]), boxes_[f][k + 3] = std::max(boxes_[f][k + 3], p[k]);
    all = {std::min(all[0], boxes_[f][0]), std::min(all[1], boxes_[f][1]), std::max(all[2], boxes_[f][3]),
           std::max(all[3], boxes_[f][4])};
    ++usable;
  }
  if (usable == 0) return;
  // About one face per cell, at most 512 cells a side.
  const double w = std::max(all[2] - all[0], 1e-300), h = std::max(all[3] - all[1], 1e-300);
  cell_ = std::max(std::sqrt(w * h / static_cast<double>(usable)), std::max(w, h) / 512.0);
  grid_x0_ = all[0];
  grid_y0_ = all[1];
  grid_nx_ = std::min<std::size_t>(512, static_cast<std::size_t>(w / cell_) + 1);
  grid_ny_ = std::min<std::size_t>(512, static_cast<std::size_t>(h / cell_) + 1);
  cells_.assign(grid_nx_ * grid_ny_, {});
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    if (normals_[f] == glm::dvec3(0.0)) continue;
    const std::size_t i0 = cell_x(boxes_[f][0]), i1 = cell_x(boxes_[f][3]);
    const std::size_t j0 = cell_y(boxes_[f][1]), j1 = cell_y(boxes_[f][4]);
    for (std::size_t j = j0; j <= j1; ++j)
      for (std::size_t i = i0; i <= i1; ++i) cells_[j * grid_nx_ + i].push_back(f);
  }
}

std::size_t ShaftCuller::cell_x(double x) const {
  const double c = std::floor((x - grid_x0_) / cell_);
  return c <= 0 ? 0 : std::min(grid_nx_ - 1, static_cast<std::size_t>(c));
}

std::size_t ShaftCuller::cell_y(double y) const {
  const double c = std::floor((y - grid_y0_) / cell_);
  return c <= 0 ? 0 : std::min(grid_ny_ - 1, static_cast<std::size_t>(c));
}

bool ShaftCuller::hides_all(std::size_t f, const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) const {
  if (!convex_[f]) return false;
  const std::vector<glm::dvec3>& v = scene_.faces[f].vertices;
  const glm::dvec3& n = normals_[f];
  for (const glm::dvec3& x : a)
    for (const glm::dvec3& y : b) {
      const double sx = glm::dot(n, x - v[0]), sy = glm::dot(n, y - v[0]);
      if (!((sx > 0 && sy < 0) || (sx < 0 && sy > 0))) return false;
      const double t = sx / (sx - sy);
      if (!(t > 1e-9 && t < 1 - 1e-9)) return false;
      const glm::dvec3 q = x + t * (y - x);
      const double margin = 1e-9 * (glm::length(y - x) + glm::length(q - v[0]));
      for (std::size_t e = 0; e < v.size(); ++e) {
        const glm::dvec3 edge = v[(e + 1) % v.size()] - v[e];
        if (!(glm::dot(glm::cross(edge, q - v[e]), n) > margin * glm::length(edge))) return false;
      }
    }
  return true;
}

bool ShaftCuller::candidates(const std::vector<glm::dvec3>& a, std::size_t a_face, const std::vector<glm::dvec3>& b,
                             std::size_t b_face, Scratch& s, std::vector<std::size_t>& out) const {
  out.clear();
  if (cells_.empty()) return false;
  if (s.seen.size() != scene_.faces.size()) s.seen.assign(scene_.faces.size(), 0), s.query = 0;
  if (++s.query == 0) std::fill(s.seen.begin(), s.seen.end(), 0), s.query = 1;
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
  const std::size_t i0 = cell_x(box[0] - tol), i1 = cell_x(box[3] + tol);
  const std::size_t j0 = cell_y(box[1] - tol), j1 = cell_y(box[4] + tol);
  for (std::size_t j = j0; j <= j1; ++j)
    for (std::size_t i = i0; i <= i1; ++i)
      for (std::size_t f : cells_[j * grid_nx_ + i]) {
        if (s.seen[f] == s.query) continue;
        s.seen[f] = s.query;
        if (f == a_face || f == b_face) continue;
        if (consider(f, box, tol, s)) {
          if (hides_all(f, a, b)) {
            out.clear();
            return true;
          }
          out.push_back(f);
        }
      }
  // A fixed order whatever the grid's: the candidates' shadows are cut in this order.
  std::sort(out.begin(), out.end());
  return false;
}

template <class Visit>
void ShaftCuller::walk(const glm::dvec3& p, std::size_t p_face, const glm::dvec3& q, std::size_t q_face, Scratch& s,
                       const Visit& visit) const {
  if (cells_.empty()) return;
  if (s.seen.size() != scene_.faces.size()) s.seen.assign(scene_.faces.size(), 0), s.query = 0;
  if (++s.query == 0) std::fill(s.seen.begin(), s.seen.end(), 0), s.query = 1;
  const glm::dvec3 d = q - p;
  const double eps = 1e-9 * glm::length(d);
  const std::array<double, 6> box = {std::min(p.x, q.x), std::min(p.y, q.y), std::min(p.z, q.z),
                                     std::max(p.x, q.x), std::max(p.y, q.y), std::max(p.z, q.z)};
  // The parameter in (0, 1) where the segment crosses face f well inside, or -1.
  auto crossing = [&](std::size_t f) {
    const std::array<double, 6>& fb = boxes_[f];
    if (fb[3] < box[0] || fb[4] < box[1] || fb[5] < box[2] || fb[0] > box[3] || fb[1] > box[4] || fb[2] > box[5])
      return -1.0;
    const std::vector<glm::dvec3>& v = scene_.faces[f].vertices;
    const glm::dvec3& n = normals_[f];
    const double sp = glm::dot(n, p - v[0]), sq = glm::dot(n, q - v[0]);
    if (!((sp > eps && sq < -eps) || (sp < -eps && sq > eps))) return -1.0;
    const double t = sp / (sp - sq);
    return inside_polygon(v, n, p + t * d) ? t : -1.0;
  };
  // Amanatides and Woo's walk over the cells the segment's plan passes through.
  std::size_t i = cell_x(p.x), j = cell_y(p.y);
  const std::size_t iq = cell_x(q.x), jq = cell_y(q.y);
  const int step_i = d.x > 0 ? 1 : -1, step_j = d.y > 0 ? 1 : -1;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double delta_i = d.x != 0 ? cell_ / std::abs(d.x) : inf, delta_j = d.y != 0 ? cell_ / std::abs(d.y) : inf;
  double next_i = d.x != 0 ? (grid_x0_ + (static_cast<double>(i) + (d.x > 0 ? 1 : 0)) * cell_ - p.x) / d.x : inf;
  double next_j = d.y != 0 ? (grid_y0_ + (static_cast<double>(j) + (d.y > 0 ? 1 : 0)) * cell_ - p.y) / d.y : inf;
  for (;;) {
    for (std::size_t f : cells_[j * grid_nx_ + i]) {
      if (s.seen[f] == s.query) continue;
      s.seen[f] = s.query;
      if (f == p_face || f == q_face) continue;
      const double t = crossing(f);
      if (t >= 0.0 && visit(f, t)) return;
    }
    // Every step moves towards q's cell, so the walk ends there whatever the rounding; `visit`
    // may stop it once the cells left start beyond what it has found (their entry parameter).
    if (!visit(SIZE_MAX, std::min(next_i, next_j))) {
      if (i != iq && (j == jq || next_i < next_j)) {
        i = static_cast<std::size_t>(static_cast<long long>(i) + step_i);
        next_i += delta_i;
        continue;
      }
      if (j != jq) {
        j = static_cast<std::size_t>(static_cast<long long>(j) + step_j);
        next_j += delta_j;
        continue;
      }
    }
    return;
  }
}

bool ShaftCuller::blocked(const glm::dvec3& p, std::size_t p_face, const glm::dvec3& q, std::size_t q_face,
                          Scratch& s) const {
  bool hit = false;
  walk(p, p_face, q, q_face, s, [&](std::size_t f, double) { return f != SIZE_MAX && (hit = true); });
  return hit;
}

std::size_t ShaftCuller::first_hit(const glm::dvec3& p, std::size_t p_face, const glm::dvec3& q, Scratch& s) const {
  std::size_t best = SIZE_MAX;
  double best_t = std::numeric_limits<double>::infinity();
  walk(p, p_face, q, SIZE_MAX, s, [&](std::size_t f, double t) {
    if (f == SIZE_MAX) return t > best_t;  // the next cell starts beyond the nearest crossing
    if (t < best_t || (t == best_t && f < best)) best_t = t, best = f;
    return false;
  });
  return best;
}

bool ShaftCuller::consider(std::size_t f, const std::array<double, 6>& box, double tol, const Scratch& s) const {
    const std::array<double, 6>& fb = boxes_[f];
    if (fb[3] < box[0] - tol || fb[4] < box[1] - tol || fb[5] < box[2] - tol || fb[0] > box[3] + tol ||
        fb[1] > box[4] + tol || fb[2] > box[5] + tol)
      return false;
    const std::vector<glm::dvec3>& v = scene_.faces[f].vertices;
    // Both polygons on one side of the face's plane (or on it): it cannot stand between.
    const glm::dvec3& n = normals_[f];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const glm::dvec3& p : s.points) {
      const double d = glm::dot(n, p - v[0]);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    if (lo >= -tol || hi <= tol) return false;
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
    return !outside;
}

}  // namespace shadow::radiosity
