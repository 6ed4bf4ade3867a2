// SPDX-License-Identifier: GPL-3.0-or-later
// The casters' images on a plane's chart (planes/plane_steps.hpp): each face's convex pieces or
// closed convex solid clipped to the light's side of the plane and the window, projected exactly
// by Blinn's matrix (see plane_shadows.cpp).
#include "planes/plane_steps.hpp"

#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "core/culling.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "runtime/parallel.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"

#include <shadow/validation.hpp>
#include <shadow/shadows.hpp>

#include <CGAL/Interval_nt.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace shadow::planes::steps {
namespace {

mpq_class dot4(const Q4& a, const Q4& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]; }

/// Value of the affine function (a, b) at a point: a.x + b.
mpq_class affine(const Q4& f, const Q3& x) { return f[0] * x[0] + f[1] * x[1] + f[2] * x[2] + f[3]; }

/// Sutherland-Hodgman clip of a convex polygon to f >= 0 (geometry/clip_convex.hpp: crossings
/// only at strict sign changes, so no duplicate vertices). Returns whether anything was cut away.
bool clip(std::vector<Q3>& poly, const Q4& f) {
  const std::size_t n = poly.size();
  if (n == 0) return false;
  std::vector<mpq_class> value(n);
  for (std::size_t a = 0; a < n; ++a) value[a] = affine(f, poly[a]);
  auto side = [&](std::size_t a) { return sgn(value[a]); };
  const geometry::ClipCase what = geometry::clip_case(n, side);
  if (what == geometry::ClipCase::Inside) return false;
  std::vector<Q3> out;
  if (what == geometry::ClipCase::Cut)
    geometry::clip_convex(poly, side, [&](std::size_t a, std::size_t b) {
      const mpq_class t = value[a] / (value[a] - value[b]);
      Q3 x;
      for (int c = 0; c < 3; ++c) x[c] = poly[a][c] + t * (poly[b][c] - poly[a][c]);
      return x;
    }, out);
  poly.swap(out);
  return true;
}

}  // namespace

bool clip_axis(std::vector<Q2>& poly, int c, const mpq_class& m, bool upper) {
  const std::size_t n = poly.size();
  if (n == 0) return false;
  auto side = [&](std::size_t a) { return upper ? -cmp(poly[a][c], m) : cmp(poly[a][c], m); };
  const geometry::ClipCase what = geometry::clip_case(n, side);
  if (what == geometry::ClipCase::Inside) return false;
  std::vector<Q2> out;
  if (what == geometry::ClipCase::Cut)
    geometry::clip_convex(poly, side, [&](std::size_t a, std::size_t b) {
      const mpq_class t = (m - poly[a][c]) / (poly[b][c] - poly[a][c]);
      Q2 x;
      x[c] = m;
      x[1 - c] = poly[a][1 - c] + t * (poly[b][1 - c] - poly[a][1 - c]);
      return x;
    }, out);
  poly.swap(out);
  return true;
}

mpq_class twice_area(const std::vector<Q2>& poly) {
  mpq_class sum = 0;
  const std::size_t n = poly.size();
  for (std::size_t a = 1; a + 1 < n; ++a)
    sum += (poly[a][0] - poly[0][0]) * (poly[a + 1][1] - poly[0][1]) - (poly[a + 1][0] - poly[0][0]) * (poly[a][1] - poly[0][1]);
  return sum;
}

Pair make_pair(const Scene& scene, std::size_t plane_id, std::size_t light_id, const core::SceneFrame& frame,
               double window, bool shear) {
  Pair P;
  P.plane_id = plane_id;
  P.light_id = light_id;
  P.window = window;
  const Plane& plane = scene.planes[plane_id];
  // An extended light's plane shadow is its centre's (docs/area-lights.md).
  const Light light = shadow::detail::centre_light(scene.lights[light_id]);
  P.normal = plane.normal;
  P.point_on = plane.point;
  P.n = {mpq_class(plane.normal.x), mpq_class(plane.normal.y), mpq_class(plane.normal.z)};
  P.c = -(P.n[0] * plane.point.x + P.n[1] * plane.point.y + P.n[2] * plane.point.z);
  P.p = {P.n[0], P.n[1], P.n[2], P.c};
  P.point = light.type == LightType::Point;
  const glm::dvec3 lv = P.point ? light.position : light.to_light;
  P.l = {mpq_class(lv.x), mpq_class(lv.y), mpq_class(lv.z), mpq_class(P.point ? 1 : 0)};
  P.pl = dot4(P.p, P.l);
  if (sgn(P.pl) == 0) return P;  // the light lies in the plane (or shines along it): no shadow
  P.casts = true;
  if (sgn(P.pl) < 0) {  // receive on the light's side
    for (mpq_class& x : P.p) x = -x;
    P.pl = -P.pl;
    P.turn = -1;
  }
  // Blinn's matrix, rows: M[r] . x = pl x_r - l_r (p . x).
  for (int r = 0; r < 4; ++r)
    for (int col = 0; col < 4; ++col) P.M[r][col] = (r == col ? P.pl : mpq_class(0)) - P.l[r] * P.p[col];
  // The plane's chart and the window in it.
  const glm::dvec3 an = glm::abs(plane.normal);
  P.k = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
  P.i = core::chart_i(P.k);
  P.j = core::chart_j(P.k);
  P.lo[0] = frame.centre[P.i] - window;
  P.lo[1] = frame.centre[P.j] - window;
  P.hi[0] = frame.centre[P.i] + window;
  P.hi[1] = frame.centre[P.j] + window;
  P.bound = {mpq_class(P.lo[0]), mpq_class(P.hi[0]), mpq_class(P.lo[1]), mpq_class(P.hi[1])};
  // Prism or pyramid from the light over the window: for a bound x_c >= m the plane through the
  // bound's line on the receiving plane and the light is pl (x_c - m) - (l_c - m l_w) s(x) = 0.
  P.sides = geometry::box_sides(P.p, P.l, P.pl, P.i, P.j, P.lo, P.hi);
  for (int col = 0; col < 4; ++col) P.level[col] = -P.p[col];
  P.level[3] += P.pl;
  for (int c = 0; c < 3; ++c) P.p_nonzero[c] = sgn(P.p[c]) != 0;
  P.ratio = {P.l[P.i] / P.pl, P.l[P.j] / P.pl};
  if (shear && !P.point) {
    const double di = lv[P.i], dj = lv[P.j];
    // Not within about 6 degrees of the chart's axis k (for the ground, the vertical: shadows
    // longer than a tenth of the height).
    if (std::hypot(di, dj) > 0.1 * glm::length(lv)) {
      P.sheared = true;
      P.lead = std::abs(di) >= std::abs(dj) ? 0 : 1;
      P.slope = P.lead == 0 ? dj / di : di / dj;
    }
  }
  return P;
}

namespace {

/// A chart point into the pair's tile frame (in place).
void to_frame(const Pair& P, Q2& x, mpq_class& scratch) {
  if (!P.sheared) return;
  scratch = P.slope * x[P.lead];
  x[1 - P.lead] -= scratch;
}

}  // namespace

Q2 from_frame(const Pair& P, const mpq_class& u0, const mpq_class& u1) {
  Q2 x{u0, u1};
  if (P.sheared) x[1 - P.lead] += P.slope * x[P.lead];
  return x;
}

namespace {

/// Whether s(x) < 0 for certain, from doubles: s = n . (x - point) evaluated with a bound on its
/// rounding error (8 units in the last place of the sum of magnitudes, far more than the five
/// roundings need). Undecided (false) near zero, on underflow and on overflow.
bool surely_behind(const Pair& P, const glm::dvec3& x) {
  const glm::dvec3 d = x - P.point_on;
  const double s = P.turn * glm::dot(P.normal, d);
  const double magnitude = std::abs(P.normal.x * d.x) + std::abs(P.normal.y * d.y) + std::abs(P.normal.z * d.z);
  if (!(magnitude > 1e-280) || !std::isfinite(magnitude)) return false;
  return s < -8 * std::numeric_limits<double>::epsilon() * magnitude;
}

/// A chart point for the convex hull: the exact point and an interval of doubles around each
/// coordinate (below and above its double), which decides most comparisons without rationals.
struct HullPoint {
  const Q2* q = nullptr;
  double lo[2] = {0, 0}, hi[2] = {0, 0};
};

/// Exact comparison of two chart points by (x, y), filtered by their intervals.
bool less_xy(const HullPoint& a, const HullPoint& b) {
  for (int c = 0; c < 2; ++c) {
    if (a.hi[c] < b.lo[c]) return true;
    if (b.hi[c] < a.lo[c]) return false;
    const int order = cmp((*a.q)[c], (*b.q)[c]);
    if (order != 0) return order < 0;
  }
  return false;
}

/// Exact sign of the orientation of (a, b, c), filtered by interval arithmetic.
int orientation(const HullPoint& a, const HullPoint& b, const HullPoint& c) {
  using I = CGAL::Interval_nt<true>;  // protects its own rounding mode
  const I ax(a.lo[0], a.hi[0]), ay(a.lo[1], a.hi[1]);
  const I det = (I(b.lo[0], b.hi[0]) - ax) * (I(c.lo[1], c.hi[1]) - ay) - (I(b.lo[1], b.hi[1]) - ay) * (I(c.lo[0], c.hi[0]) - ax);
  if (det.inf() > 0) return 1;
  if (det.sup() < 0) return -1;
  const Q2 &p = *a.q, &q = *b.q, &r = *c.q;
  return sgn(mpq_class((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])));
}

/// The convex hull of chart points, exactly (Andrew's monotone chain, no collinear or repeated
/// vertices): counter-clockwise from the least point by (x, y), into `out`. Fewer than three
/// vertices when the points do not bound an area. Replaces CGAL's hull on lazy numbers built
/// from the rationals (the numbers' construction was most of the hull's cost).
void convex_hull(const std::vector<Q2>& points, std::vector<HullPoint>& order, std::vector<Q2>& out) {
  order.clear();
  out.clear();
  if (points.empty()) return;
  for (const Q2& q : points) {
    HullPoint h;
    h.q = &q;
    for (int c = 0; c < 2; ++c) {
      h.lo[c] = below(q[c]);
      h.hi[c] = above(q[c]);
    }
    order.push_back(h);
  }
  std::sort(order.begin(), order.end(), less_xy);
  std::vector<const HullPoint*> chain;
  chain.reserve(2 * order.size());
  auto extend = [&](const HullPoint& p, std::size_t floor) {
    while (chain.size() >= floor + 2 && orientation(*chain[chain.size() - 2], *chain.back(), p) <= 0) chain.pop_back();
    chain.push_back(&p);
  };
  for (const HullPoint& p : order) extend(p, 0);  // lower hull, left to right
  const std::size_t lower = chain.size();
  for (std::size_t a = order.size() - 1; a-- > 0;) extend(order[a], lower - 1);  // upper hull, right to left
  // The chain ends where it began; two vertices or fewer when the points bound no area.
  for (std::size_t a = 0; a + 1 < chain.size(); ++a) out.push_back(*chain[a]->q);
}

/// Turns chart polygons into images: projection, window, culling. One per worker thread.
class Caster {
 public:
  Caster(const Pair& P, std::vector<Image>& out, bool& reaches) : P_(P), out_(out), reaches_(reaches) {}

  /// A face's convex piece, vertices exact.
  void piece(std::vector<Q3>& poly) {
    const std::size_t n = poly.size();
    s_.resize(n);
    bool any_front = false, all_between = true;
    for (std::size_t a = 0; a < n; ++a) {
      s_[a] = affine(P_.p, poly[a]);
      const int side = sgn(s_[a]);
      any_front |= side > 0;
      all_between &= side >= 0 && (!P_.point || cmp(s_[a], P_.pl) < 0);
    }
    // Strictly on the light's side of the plane: the closure of s > 0 when s > 0 somewhere.
    if (!any_front) return;
    if (all_between) {
      // Nothing to cut in 3D: w = p.l - l_w s > 0 at every vertex, so the window's prism or
      // pyramid sides become the window's edges in the chart (side(x) = w (x_c - m)).
      chart_.clear();
      for (std::size_t a = 0; a < n; ++a) chart_.push_back(project(poly[a], s_[a]));
      finish(window_clip());
      return;
    }
    clip(poly, P_.p);
    // Nothing at or beyond a point light's level casts (it lies outside the pyramid anyway):
    // cut it first so that only what really projects outside the window counts as cut by it.
    if (P_.point) clip(poly, P_.level);
    bool cut_by_window = false;
    for (const Q4& side : P_.sides) cut_by_window |= clip(poly, side);
    if (poly.size() < 3) {
      reaches_ |= cut_by_window;
      return;
    }
    chart_.clear();
    for (const Q3& x : poly) {
      const Q4 h{x[0], x[1], x[2], mpq_class(1)};
      const mpq_class w = dot4(P_.M[3], h);
      // w = 0 only at the lamp itself: this face's plane contains the light, it is edge-on.
      if (sgn(w) == 0) return;
      chart_.push_back({mpq_class(dot4(P_.M[P_.i], h) / w), mpq_class(dot4(P_.M[P_.j], h) / w)});
    }
    finish(cut_by_window);
  }

  /// A closed convex solid: true when it cast as one (all of it between the plane and the
  /// light), false when its faces must cast one by one.
  bool solid(const core::ConvexSolid& cs) {
    const std::size_t n = cs.vertices.size();
    s_.resize(n);
    bool any_front = false;
    for (std::size_t a = 0; a < n; ++a) {
      const glm::dvec3& v = cs.vertices[a];
      // s = p.(v, 1), skipping the plane's zero coefficients (the ground: s = z).
      s_[a] = P_.p[3];
      for (int c = 0; c < 3; ++c)
        if (P_.p_nonzero[c]) {
          coordinate_ = v[c];
          term_ = P_.p[c] * coordinate_;
          s_[a] += term_;
        }
      const int side = sgn(s_[a]);
      if (side < 0 || (P_.point && cmp(s_[a], P_.pl) >= 0)) return false;
      any_front |= side > 0;
    }
    if (!any_front) return true;  // lies in the plane: casts nothing
    // Its shadow is the projection of the solid, which is convex (w > 0 throughout) and the
    // projection of its vertices' hull: a ray that meets the solid meets its boundary.
    hull_in_.resize(n);
    for (std::size_t a = 0; a < n; ++a) {
      const glm::dvec3& v = cs.vertices[a];
      if (P_.point) {
        hull_in_[a] = project({mpq_class(v.x), mpq_class(v.y), mpq_class(v.z)}, s_[a]);
        continue;
      }
      // A directional light: w = p.l, and the image is x - (l / p.l) s, the same rational.
      for (int c = 0; c < 2; ++c) {
        hull_in_[a][c] = v[c == 0 ? P_.i : P_.j];
        term_ = P_.ratio[c] * s_[a];
        hull_in_[a][c] -= term_;
      }
    }
    convex_hull(hull_in_, hull_order_, chart_);
    // Three hull points or more bound a positive area, counter-clockwise, and a window clip that
    // keeps three points keeps a vertex strictly inside: no orientation to test.
    finish(window_clip(), chart_.size() >= 3);
    return true;
  }

 private:
  /// Blinn's map of a point with s = p.x known: (pl x - l s) / (pl - l_w s) in the chart.
  Q2 project(const Q3& x, const mpq_class& s) const {
    const mpq_class w = P_.pl - P_.l[3] * s;
    return {mpq_class((P_.pl * x[P_.i] - P_.l[P_.i] * s) / w), mpq_class((P_.pl * x[P_.j] - P_.l[P_.j] * s) / w)};
  }

  /// Clips chart_ to the window in the order of the 3D sides (i lo, i hi, j lo, j hi).
  bool window_clip() {
    bool cut = false;
    for (int side = 0; side < 4; ++side) cut |= clip_axis(chart_, side / 2, P_.bound[side], side % 2 == 1);
    return cut;
  }

  void finish(bool cut_by_window, bool counter_clockwise = false) {
    reaches_ |= cut_by_window;
    if (chart_.size() < 3) return;
    const int orientation = counter_clockwise ? 1 : sgn(twice_area(chart_));
    if (orientation == 0) return;  // edge-on to the light
    if (orientation < 0) std::reverse(chart_.begin(), chart_.end());
    for (Q2& x : chart_) to_frame(P_, x, term_);  // a shear: still counter-clockwise
    Image image;
    image.box = {below(chart_[0][0]), below(chart_[0][1]), above(chart_[0][0]), above(chart_[0][1])};
    for (const Q2& x : chart_) {
      image.box[0] = std::min(image.box[0], below(x[0]));
      image.box[1] = std::min(image.box[1], below(x[1]));
      image.box[2] = std::max(image.box[2], above(x[0]));
      image.box[3] = std::max(image.box[3], above(x[1]));
    }
    image.vertices = std::move(chart_);
    chart_.clear();
    out_.push_back(std::move(image));
  }

  const Pair& P_;
  std::vector<Image>& out_;
  bool& reaches_;
  std::vector<mpq_class> s_;
  std::vector<Q2> chart_;
  std::vector<Q2> hull_in_;
  mpq_class coordinate_, term_;
  std::vector<HullPoint> hull_order_;
};

}  // namespace

void cast_units(const Scene& scene, const std::vector<core::FacePrep>& prep, const std::vector<core::ConvexSolid>& solids,
                const std::vector<std::vector<std::size_t>>& solid_faces, const std::vector<Unit>& units, std::size_t first,
                std::size_t last, const Pair& P, std::vector<Image>& out, bool& reaches) {
  Caster caster(P, out, reaches);
  std::vector<Q3> vertex, poly;
  auto cast_face = [&](std::size_t q) {
    const core::FacePrep& qp = prep[q];
    if (qp.degenerate) return;
    const Face& face = scene.faces[q];
    // Culled before any exact work: every vertex behind the plane for certain.
    if (std::all_of(face.vertices.begin(), face.vertices.end(), [&](const glm::dvec3& v) { return surely_behind(P, v); }))
      return;
    vertex.resize(face.vertices.size());
    if (qp.exactly_planar) {
      for (std::size_t v = 0; v < face.vertices.size(); ++v)
        vertex[v] = {mpq_class(face.vertices[v].x), mpq_class(face.vertices[v].y), mpq_class(face.vertices[v].z)};
    } else {  // lifted onto its exact plane, as the per-face engine does
      const exact::ExactFace ef = exact::make_exact_face(face.vertices, qp);
      for (std::size_t v = 0; v < ef.vertices.size(); ++v)
        for (int a = 0; a < 3; ++a) vertex[v][a] = CGAL::exact(ef.vertices[v][a]);
    }
    for (const std::vector<int>& piece : qp.convex_pieces) {
      poly.clear();
      for (int v : piece) poly.push_back(vertex[v]);
      caster.piece(poly);
    }
  };
  for (std::size_t u = first; u < last; ++u) {
    const Unit& unit = units[u];
    if (unit.solid < 0) {
      cast_face(unit.face);
      continue;
    }
    const core::ConvexSolid& cs = solids[static_cast<std::size_t>(unit.solid)];
    if (std::all_of(cs.vertices.begin(), cs.vertices.end(), [&](const glm::dvec3& v) { return surely_behind(P, v); }))
      continue;
    if (!caster.solid(cs))
      for (std::size_t q : solid_faces[static_cast<std::size_t>(unit.solid)]) cast_face(q);
  }
}

}  // namespace shadow::planes::steps
