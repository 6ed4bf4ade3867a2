// SPDX-License-Identifier: GPL-3.0-or-later
#include "radiosity/shooter_view.hpp"

#include "radiosity/triangles.hpp"

#include <shadow/error.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadow::radiosity {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::array<double, 6> empty_box() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  return {inf, inf, inf, -inf, -inf, -inf};
}

void add(std::array<double, 6>& b, const glm::dvec3& p) {
  for (int k = 0; k < 3; ++k) b[k] = std::min(b[k], p[k]), b[k + 3] = std::max(b[k + 3], p[k]);
}

void widen(std::array<double, 6>& b) {
  for (int k = 0; k < 3; ++k) {
    const double m = 1e-9 * (std::abs(b[k]) + std::abs(b[k + 3]) + (b[k + 3] - b[k])) + 1e-300;
    b[k] -= m;
    b[k + 3] += m;
  }
}

bool overlap(const std::array<double, 6>& a, const std::array<double, 6>& b) {
  return !(a[0] > b[3] || a[3] < b[0] || a[1] > b[4] || a[4] < b[1] || a[2] > b[5] || a[5] < b[2]);
}

/// `poly` cut to the half-space n . (y - x) >= 0 (Sutherland-Hodgman, doubles).
std::vector<glm::dvec3> clip_front(const std::vector<glm::dvec3>& poly, const glm::dvec3& n, const glm::dvec3& x) {
  std::vector<glm::dvec3> out;
  const std::size_t m = poly.size();
  for (std::size_t i = 0; i < m; ++i) {
    const glm::dvec3& a = poly[i];
    const glm::dvec3& b = poly[(i + 1) % m];
    const double da = glm::dot(n, a - x), db = glm::dot(n, b - x);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

}  // namespace

ShooterView::ShooterView(const Scene& scene, unsigned workers)
    : scene_(scene), query_(scene, workers), exact_count_(std::max(1u, workers), 0) {
  boxes_.resize(scene.faces.size(), empty_box());
  normals_.resize(scene.faces.size(), glm::dvec3(0.0));
  convex_.resize(scene.faces.size(), 0);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.degenerate || face.vertices.size() < 3) continue;
    for (const glm::dvec3& v : face.vertices) add(boxes_[f], v);
    widen(boxes_[f]);
    const glm::dvec3 n = newell_normal(face.vertices);
    if (glm::length(n) > 0) normals_[f] = glm::normalize(n);
    bool convex = true;
    const std::size_t m = face.vertices.size();
    for (std::size_t a = 0; a < m && convex; ++a) {
      const glm::dvec3& p = face.vertices[a];
      convex = glm::dot(glm::cross(face.vertices[(a + 1) % m] - p, face.vertices[(a + 2) % m] - face.vertices[(a + 1) % m]),
                        normals_[f]) > 0;
    }
    convex_[f] = convex ? 1 : 0;
  }
}

void ShooterView::set_shooter(std::size_t face, const std::vector<glm::dvec3>& polygon,
                              std::vector<std::vector<glm::dvec3>> pieces) {
  face_ = face;
  pieces_ = std::move(pieces);
  polygon_ = polygon;
  source_box_ = empty_box();
  for (const glm::dvec3& v : polygon) add(source_box_, v);
  const glm::dvec3 n = newell_normal(polygon);
  source_normal_ = glm::length(n) > 0 ? glm::normalize(n) : glm::dvec3(0.0);
  source_point_ = polygon.empty() ? glm::dvec3(0.0) : polygon[0];
  Light light;
  light.type = LightType::Area;
  light.polygon = polygon;
  light.intensity = 1.0 / kPi;  // irradiance pi L F = F
  light.name = "source";
  try {
    query_.set_light(light, true);
    exact_ok_ = true;
  } catch (const InputError&) {
    // A sliver the exact planner cannot use as a light: unoccluded contour only (its power is
    // negligible; docs/radiosity.md).
    exact_ok_ = false;
  }
}

ShooterView::Seen ShooterView::classify(const SurfacePoint& point, const glm::dvec3& nr,
                                       const std::vector<glm::dvec3>& poly) const {
  const glm::dvec3& x = point.position;
  std::array<double, 6> box = empty_box();
  for (const glm::dvec3& y : poly) add(box, y);
  add(box, x);
  widen(box);
  // The pyramid from x over the source: its side planes (normals pointing inward).
  const std::size_t m = poly.size();
  glm::dvec3 centre(0.0);
  for (const glm::dvec3& y : poly) centre += y / static_cast<double>(m);
  std::vector<glm::dvec3> sides(m);
  for (std::size_t a = 0; a < m; ++a) {
    glm::dvec3 n = glm::cross(poly[a] - x, poly[(a + 1) % m] - x);
    if (glm::dot(n, centre - x) < 0) n = -n;
    sides[a] = n;
  }
  // A face can hide part of the source only if it enters the open pyramid: strictly in front of
  // the source's plane and of the receiver's, and inside every side plane. A face all of whose
  // vertices are on the far side of (or on) one of these planes is culled; the tolerance, 1e-12
  // of the distances, lets a face that only touches the pyramid (a wall meeting the floor) go.
  auto outside = [&](const std::vector<glm::dvec3>& v) {
    // The face clipped by each plane in turn (doubles); what is left within the tolerance of a
    // plane counts as outside, so that a face that only touches the pyramid is culled.
    std::vector<glm::dvec3> rest = v, next;
    auto cut = [&](const glm::dvec3& n, const glm::dvec3& o) {
      const double nl = glm::length(n);
      next.clear();
      const std::size_t k = rest.size();
      auto dist = [&](const glm::dvec3& p) {
        return glm::dot(n, p - o) - 1e-12 * nl * (glm::length(p - o) + glm::length(o - x));
      };
      for (std::size_t i = 0; i < k; ++i) {
        const glm::dvec3& p = rest[i];
        const glm::dvec3& q = rest[(i + 1) % k];
        const double dp = dist(p), dq = dist(q);
        if (dp > 0) next.push_back(p);
        if ((dp > 0) != (dq > 0)) next.push_back(p + (q - p) * (dp / (dp - dq)));
      }
      rest.swap(next);
      return rest.size() >= 3;
    };
    if (!cut(source_normal_, source_point_) || !cut(nr, x)) return true;
    for (const glm::dvec3& n : sides)
      if (!cut(n, x)) return true;
    return false;
  };
  // Or the other way round: x and the source on one side of (or on) the face's plane (every
  // wall of a convex room for the others).
  auto separates = [&](std::size_t o) {
    const glm::dvec3& n = normals_[o];
    const glm::dvec3& p0 = scene_.faces[o].vertices[0];
    const double tol = 1e-12 * (glm::length(x - p0) + glm::length(source_point_ - p0));
    double lo = glm::dot(n, x - p0), hi = lo;
    for (const glm::dvec3& y : poly) {
      const double d = glm::dot(n, y - p0);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return lo >= -tol || hi <= tol;
  };
  // A convex face that every segment from x to a source vertex crosses well inside (away from
  // its edges by 1e-9 of the lengths) hides the whole source: the pyramid is the convex hull of
  // those segments.
  auto hides_all = [&](std::size_t o) {
    if (!convex_[o]) return false;
    const std::vector<glm::dvec3>& v = scene_.faces[o].vertices;
    const glm::dvec3& n = normals_[o];
    const double sx = glm::dot(n, x - v[0]);
    for (const glm::dvec3& y : poly) {
      const double sy = glm::dot(n, y - v[0]);
      if (!((sx > 0 && sy < 0) || (sx < 0 && sy > 0))) return false;
      const double t = sx / (sx - sy);
      if (!(t > 1e-9 && t < 1 - 1e-9)) return false;
      const glm::dvec3 q = x + t * (y - x);
      const double margin = 1e-9 * (glm::length(y - x) + glm::length(q - v[0]));
      for (std::size_t a = 0; a < v.size(); ++a) {
        const glm::dvec3 edge = v[(a + 1) % v.size()] - v[a];
        const double len = glm::length(edge);
        if (!(glm::dot(glm::cross(edge, q - v[a]), n) > margin * len)) return false;
      }
    }
    return true;
  };
  bool blocked = false;
  for (std::size_t o = 0; o < boxes_.size(); ++o) {
    if (o == face_ || o == point.face_id || normals_[o] == glm::dvec3(0.0) || !overlap(boxes_[o], box)) continue;
    if (separates(o) || outside(scene_.faces[o].vertices)) continue;
    if (hides_all(o)) return Seen::None;
    blocked = true;
  }
  return blocked ? Seen::Part : Seen::All;
}

double ShooterView::contour(const glm::dvec3& x, const glm::dvec3& nr, const std::vector<glm::dvec3>& poly) {
  const std::vector<glm::dvec3> part = clip_front(poly, nr, x);
  if (part.size() < 3) return 0.0;
  std::vector<glm::dvec3> r(part.size());
  for (std::size_t i = 0; i < part.size(); ++i) r[i] = part[i] - x;
  return std::max(0.0, -0.5 * detail::lambert_contour(r, nr) / kPi);
}

double ShooterView::evaluate(unsigned worker, const SurfacePoint& point) const {
  const glm::dvec3& x = point.position;
  const glm::dvec3& nr = normals_[point.face_id];
  if (nr == glm::dvec3(0.0) || source_normal_ == glm::dvec3(0.0)) return 0.0;
  // The point must be in front of the source, and the source (in part) in front of the point.
  if (glm::dot(source_normal_, x - source_point_) <= 0.0) return 0.0;
  bool any_front = false;
  for (const glm::dvec3& y : polygon_) any_front = any_front || glm::dot(nr, y - x) > 0.0;
  if (!any_front) return 0.0;
  const Seen seen = classify(point, nr, polygon_);
  if (seen == Seen::All) return contour(x, nr, polygon_);
  if (seen == Seen::None) return 0.0;
  // Part of the source may be hidden: its pieces, each seen whole or hidden whole, sum in
  // doubles; where one is itself in part hidden, the exact machinery takes the whole source.
  if (!pieces_.empty()) {
    double sum = 0.0;
    bool partial = false;
    for (const std::vector<glm::dvec3>& piece : pieces_) {
      const Seen s = classify(point, nr, piece);
      if (s == Seen::Part) {
        partial = true;
        break;
      }
      if (s == Seen::All) sum += contour(x, nr, piece);
    }
    if (!partial) return sum;
  }
  if (!exact_ok_) return contour(x, nr, polygon_);
  ++exact_count_[worker];
  return query_.evaluate(worker, point).second;
}

std::size_t ShooterView::exact_evaluations() const {
  std::size_t n = 0;
  for (std::size_t c : exact_count_) n += c;
  return n;
}

}  // namespace shadow::radiosity
