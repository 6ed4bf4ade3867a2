// SPDX-License-Identifier: GPL-3.0-or-later
// The exact point oracles of shadow/testing.hpp: a segment (or ray) against every face's closed
// polygon in exact rationals. Deliberately independent of the engine (no Atherton clipping, no
// projection, no Boolean operations): a second method to check the engine against.
#include <shadow/error.hpp>
#include <shadow/testing.hpp>

#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <array>
#include <limits>
#include <utility>
#include <cmath>
#include <string>
#include <vector>

namespace shadow::testing {
namespace {

using Q = CGAL::Exact_rational;
using V3 = std::array<Q, 3>;

V3 exact(const glm::dvec3& p) { return {Q(p.x), Q(p.y), Q(p.z)}; }

Q dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// A face as the engine computes on it: the exact plane n . x + c = 0 through the vertex average
/// with the exact Newell normal (pointing to the front), and the outline in the chart that drops
/// axis k (the input doubles' chart coordinates, which the engine's lift keeps).
struct ExactFace {
  V3 n;
  Q c;
  int k = 2;
  std::vector<std::array<Q, 2>> chart;
  bool degenerate = false;
};

ExactFace exact_face(const std::vector<glm::dvec3>& vertices) {
  ExactFace f;
  const std::size_t m = vertices.size();
  std::vector<V3> v;
  v.reserve(m);
  for (const glm::dvec3& p : vertices) v.push_back(exact(p));
  f.n = {Q(0), Q(0), Q(0)};
  V3 sum = {Q(0), Q(0), Q(0)};
  for (std::size_t a = 0; a < m; ++a) {
    const V3& u = v[a];
    const V3& w = v[(a + 1) % m];
    f.n[0] += (u[1] - w[1]) * (u[2] + w[2]);
    f.n[1] += (u[2] - w[2]) * (u[0] + w[0]);
    f.n[2] += (u[0] - w[0]) * (u[1] + w[1]);
    for (int i = 0; i < 3; ++i) sum[i] += u[i];
  }
  if (m < 3 || (CGAL::is_zero(f.n[0]) && CGAL::is_zero(f.n[1]) && CGAL::is_zero(f.n[2]))) {
    f.degenerate = true;
    return f;
  }
  f.c = -dot(f.n, sum) / Q(static_cast<int>(m));
  const Q ax = CGAL::abs(f.n[0]), ay = CGAL::abs(f.n[1]), az = CGAL::abs(f.n[2]);
  f.k = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
  const int i = (f.k + 1) % 3, j = (f.k + 2) % 3;
  for (const V3& p : v) f.chart.push_back({p[i], p[j]});
  return f;
}

int orientation(const std::array<Q, 2>& a, const std::array<Q, 2>& b, const std::array<Q, 2>& p) {
  return CGAL::sign((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
}

/// Closed point-in-polygon in the chart: the boundary counts as inside. Crossing parity with
/// the half-open rule, all comparisons exact.
bool in_closed_chart_polygon(const std::vector<std::array<Q, 2>>& poly, const std::array<Q, 2>& p) {
  bool inside = false;
  const std::size_t m = poly.size();
  for (std::size_t a = 0, b = m - 1; a < m; b = a++) {
    const auto& u = poly[a];
    const auto& w = poly[b];
    const int o = orientation(u, w, p);
    if (o == 0 && CGAL::min(u[0], w[0]) <= p[0] && p[0] <= CGAL::max(u[0], w[0]) &&
        CGAL::min(u[1], w[1]) <= p[1] && p[1] <= CGAL::max(u[1], w[1]))
      return true;  // on the edge
    if ((u[1] > p[1]) != (w[1] > p[1])) {
      // The edge crosses the horizontal line through p; is the crossing right of p? The sign
      // of the orientation, made independent of the edge's direction.
      const int side = (w[1] > u[1]) ? o : -o;
      if (side > 0) inside = !inside;
    }
  }
  return inside;
}

std::array<Q, 2> chart_of(const ExactFace& f, const V3& p) {
  return {p[(f.k + 1) % 3], p[(f.k + 2) % 3]};
}

bool on_exact_face(const ExactFace& f, const V3& p) {
  if (f.degenerate || !CGAL::is_zero(dot(f.n, p) + f.c)) return false;
  return in_closed_chart_polygon(f.chart, chart_of(f, p));
}

/// The light as seen from the scene: position or direction, exactly.
struct ExactLight {
  bool point = false;
  V3 where;  // position (point light) or direction toward the light
};

ExactLight exact_light(const Scene& scene, std::size_t light_id) {
  if (light_id >= scene.lights.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "light " + std::to_string(light_id) + " is not a scene light (" +
                     std::to_string(scene.lights.size()) + " lights)");
  const Light& l = scene.lights[light_id];
  const glm::dvec3 v = l.type == LightType::Point ? l.position : l.to_light;
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) ||
      (l.type == LightType::Directional && v == glm::dvec3(0.0)))
    throw InputError(SourceLocation{"shadow::testing", ""}, "light " + std::to_string(light_id) + " ('" + l.name +
                     "') has a non-finite or zero " + (l.type == LightType::Point ? "position" : "direction"));
  return {l.type == LightType::Point, exact(v)};
}

/// The face's front looks strictly toward the light.
bool faces_light(const ExactFace& f, const ExactLight& light) {
  if (f.degenerate) return false;
  return CGAL::is_positive(light.point ? dot(f.n, light.where) + f.c : dot(f.n, light.where));
}

/// Does face f block the open segment p -> light (open ray for a directional light)?
bool blocks(const ExactFace& f, const V3& p, const ExactLight& light) {
  if (f.degenerate) return false;
  V3 d = light.where;
  if (light.point)
    for (int i = 0; i < 3; ++i) d[i] -= p[i];
  const Q nd = dot(f.n, d);
  if (CGAL::is_zero(nd)) return false;  // parallel: misses the plane or lies in it (edge-on)
  const Q t = -(dot(f.n, p) + f.c) / nd;
  if (!CGAL::is_positive(t)) return false;
  if (light.point && t >= Q(1)) return false;
  V3 hit;
  for (int i = 0; i < 3; ++i) hit[i] = p[i] + t * d[i];
  return in_closed_chart_polygon(f.chart, chart_of(f, hit));
}

void check_face_id(const Scene& scene, std::size_t face_id) {
  if (face_id >= scene.faces.size())
    throw InputError(SourceLocation{"shadow::testing", ""}, "face " + std::to_string(face_id) + " is not a scene face (" +
                     std::to_string(scene.faces.size()) + " faces)");
}

}  // namespace

/// Outward-rounded double bounds of an exact value.
struct Box {
  glm::dvec3 lo, hi;
};

struct ExactOracle::Impl {
  const Scene* scene = nullptr;
  std::vector<ExactFace> faces;
  std::vector<Box> boxes;  // of each face's polygon on its exact plane (the lifted vertices)

  bool unblocked(const V3& p, const Box& p_box, const ExactLight& light, const Light& l) const {
    // The segment's (or ray's) box: from p's box to the light's position, or to infinity along
    // each axis the direction moves on.
    Box s = p_box;
    for (int a = 0; a < 3; ++a) {
      if (l.type == LightType::Point) {
        s.lo[a] = std::min(s.lo[a], l.position[a]);
        s.hi[a] = std::max(s.hi[a], l.position[a]);
      } else if (l.to_light[a] > 0) {
        s.hi[a] = std::numeric_limits<double>::infinity();
      } else if (l.to_light[a] < 0) {
        s.lo[a] = -std::numeric_limits<double>::infinity();
      }
    }
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const Box& b = boxes[f];
      if (s.hi.x < b.lo.x || s.hi.y < b.lo.y || s.hi.z < b.lo.z || s.lo.x > b.hi.x || s.lo.y > b.hi.y ||
          s.lo.z > b.hi.z)
        continue;  // disjoint boxes: the segment cannot meet the face
      if (blocks(faces[f], p, light)) return false;
    }
    return true;
  }
};

ExactOracle::ExactOracle(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  impl_->scene = &scene;
  for (const Face& face : scene.faces) {
    ExactFace f = exact_face(face.vertices);
    Box box{glm::dvec3(std::numeric_limits<double>::infinity()), glm::dvec3(-std::numeric_limits<double>::infinity())};
    if (!f.degenerate) {
      const int i = (f.k + 1) % 3, j = (f.k + 2) % 3;
      for (const auto& c : f.chart) {
        V3 v;
        v[i] = c[0];
        v[j] = c[1];
        v[f.k] = -(f.c + f.n[i] * c[0] + f.n[j] * c[1]) / f.n[f.k];
        for (int a = 0; a < 3; ++a) {
          const std::pair<double, double> iv = CGAL::to_interval(v[a]);
          box.lo[a] = std::min(box.lo[a], iv.first);
          box.hi[a] = std::max(box.hi[a], iv.second);
        }
      }
    }
    impl_->faces.push_back(std::move(f));
    impl_->boxes.push_back(box);
  }
}

ExactOracle::~ExactOracle() = default;
ExactOracle::ExactOracle(ExactOracle&&) noexcept = default;
ExactOracle& ExactOracle::operator=(ExactOracle&&) noexcept = default;

bool ExactOracle::is_lit(glm::dvec3 point, std::size_t light_id) const {
  const ExactLight light = exact_light(*impl_->scene, light_id);
  const V3 p = exact(point);
  for (const ExactFace& f : impl_->faces)
    if (on_exact_face(f, p) && !faces_light(f, light)) return false;
  return impl_->unblocked(p, Box{point, point}, light, impl_->scene->lights[light_id]);
}

bool ExactOracle::is_lit_on_face(std::size_t face_id, glm::dvec3 point, std::size_t light_id) const {
  check_face_id(*impl_->scene, face_id);
  const ExactLight light = exact_light(*impl_->scene, light_id);
  const ExactFace& f = impl_->faces[face_id];
  if (f.degenerate)
    throw InputError(SourceLocation{"shadow::testing", ""}, "face " + std::to_string(face_id) + " is degenerate (zero area)");
  if (!faces_light(f, light)) return false;
  // Onto the plane along axis k, keeping the chart coordinates (the engine's lift).
  V3 p = exact(point);
  const int i = (f.k + 1) % 3, j = (f.k + 2) % 3;
  p[f.k] = -(f.c + f.n[i] * p[i] + f.n[j] * p[j]) / f.n[f.k];
  Box p_box{point, point};
  const std::pair<double, double> iv = CGAL::to_interval(p[f.k]);
  p_box.lo[f.k] = iv.first;
  p_box.hi[f.k] = iv.second;
  return impl_->unblocked(p, p_box, light, impl_->scene->lights[light_id]);
}

bool ExactOracle::on_face(std::size_t face_id, glm::dvec3 point) const {
  check_face_id(*impl_->scene, face_id);
  return on_exact_face(impl_->faces[face_id], exact(point));
}

bool is_lit(const Scene& scene, glm::dvec3 point, std::size_t light_id) {
  return ExactOracle(scene).is_lit(point, light_id);
}

bool is_lit_on_face(const Scene& scene, std::size_t face_id, glm::dvec3 point, std::size_t light_id) {
  return ExactOracle(scene).is_lit_on_face(face_id, point, light_id);
}

bool on_face(const Scene& scene, std::size_t face_id, glm::dvec3 point) {
  return ExactOracle(scene).on_face(face_id, point);
}

}  // namespace shadow::testing
