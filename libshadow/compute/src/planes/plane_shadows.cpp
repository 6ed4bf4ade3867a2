// SPDX-License-Identifier: GPL-3.0-or-later
// Exact shadows on planes through Blinn's projection matrix.
//
// For a plane p = (n, c) and a light l, a point of the plane is in shadow when its segment to the
// light meets a face strictly on the light's side of the plane. Every caster is clipped to that
// side (s = p.(x, 1) > 0 once p is turned toward the light) and to the prism or pyramid from the
// light over a square window on the plane (a point light at the height of some geometry casts a
// shadow without end), then mapped by the exact rational matrix M = (p.l) I - l p^T with the
// homogeneous divide, and the images are united exactly.
//
// A caster is a face's convex piece, or a whole closed convex solid (a box) when all of it lies
// between the plane and the light: it then casts the convex hull of its projected vertices.
// Casters are projected in parallel (plain GMP rationals, which threads may share for reading);
// the images are then cut along a grid of tiles fixed by the images alone (never by the thread
// count), each tile is united on its own thread, and the tiles' regions are joined back by
// their shared border edges. Under a directional light the images are united in the chart
// sheared along the shadows, so that tiles are strips that long shadows seldom cross. See
// docs/algorithm.md, "Shadows on planes (Blinn)".
//
// This path shares no clipping or projection code with the per-face engine on purpose: a face
// lying in a plane must come out of both with the same shadow, and the tests check that. It
// shares only the search for convex solids (exact/convex_solids.hpp).
#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "core/culling.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "core/parallel.hpp"
#include "planes/plane_shadows.hpp"
#include "exact/regions.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"

#include <shadow/validation.hpp>
#include <shadow/shadows.hpp>

#include <CGAL/Interval_nt.h>
#include <CGAL/version.h>

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

namespace shadow {
namespace planes {
namespace {

using Q4 = std::array<mpq_class, 4>;  // homogeneous point or plane, exact
using Q3 = std::array<mpq_class, 3>;
using Q2 = std::array<mpq_class, 2>;  // a point of the plane's chart (axes i, j)

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

/// The same clip in the chart, to the axis bound x_c >= m (upper: x_c <= m). The crossing gets m
/// exactly in coordinate c. Returns whether anything was cut away.
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

/// Twice the signed area of a chart polygon (counter-clockwise positive).
mpq_class twice_area(const std::vector<Q2>& poly) {
  mpq_class sum = 0;
  const std::size_t n = poly.size();
  for (std::size_t a = 1; a + 1 < n; ++a)
    sum += (poly[a][0] - poly[0][0]) * (poly[a + 1][1] - poly[0][1]) - (poly[a + 1][0] - poly[0][0]) * (poly[a][1] - poly[0][1]);
  return sum;
}

/// One caster's image on the plane's chart: a convex polygon, counter-clockwise, of positive
/// area. Plain GMP rationals (not lazy CGAL numbers), so the tile threads may read it at once.
struct Image {
  std::vector<Q2> vertices;   ///< in the pair's tile frame (Pair::sheared)
  std::array<double, 4> box;  ///< lo_0, lo_1, hi_0, hi_1: doubles that enclose the exact box
};

double below(const mpq_class& q) { return std::nextafter(q.get_d(), -std::numeric_limits<double>::infinity()); }
double above(const mpq_class& q) { return std::nextafter(q.get_d(), std::numeric_limits<double>::infinity()); }

/// One plane and one light, exactly: the plane turned toward the light, Blinn's matrix, the
/// chart and the window.
struct Pair {
  std::size_t plane_id = 0, light_id = 0;
  double window = 0;
  bool casts = false;  ///< false when the light lies in the plane (or shines along it)
  bool point = false;
  Q3 n;                ///< the plane's normal as given (not turned)
  mpq_class c;
  Q4 p, l;             ///< the plane turned toward the light; the light (x, 1) or (d, 0)
  mpq_class pl;        ///< p . l > 0
  std::array<Q4, 4> M;
  int k = 2, i = 0, j = 1;
  double lo[2] = {0, 0}, hi[2] = {0, 0};
  std::array<mpq_class, 4> bound;  ///< lo[0], hi[0], lo[1], hi[1] exactly
  std::array<Q4, 4> sides;         ///< the prism or pyramid over the window
  Q4 level;                        ///< p.l - p.x >= 0 (point lights)
  std::array<bool, 3> p_nonzero{};  ///< which of p's first three coefficients are not zero
  std::array<mpq_class, 2> ratio;   ///< l_i / p.l and l_j / p.l (directional lights)
  glm::dvec3 normal{0.0}, point_on{0.0};  ///< the plane as given, for the double filter
  double turn = 1;                        ///< -1 when p is the plane turned around
  /// The tile frame: images are united in coordinates (u_0, u_1) of the chart sheared along the
  /// shadows of a directional light, u_lead = x_lead and u_other = x_other - slope x_lead, with
  /// slope = l_other / l_lead (|slope| <= 1, a double taken exactly). Every shadow runs along
  /// u_lead there (to within the slope's rounding), so that tiles cut along u_other are strips
  /// that a low sun's long shadows seldom cross, and the cuts stay lines of one exact double
  /// coordinate (what keeps CGAL's filters deciding points on them). A shear has determinant 1:
  /// areas and orientations are the chart's. Point lights (shadows in every direction) and a
  /// light within about 6 degrees of the chart's axis k keep the chart (sheared false).
  bool sheared = false;
  int lead = 0;
  mpq_class slope = 0;
};

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

/// A chart point into the pair's tile frame (in place).
void to_frame(const Pair& P, Q2& x, mpq_class& scratch) {
  if (!P.sheared) return;
  scratch = P.slope * x[P.lead];
  x[1 - P.lead] -= scratch;
}

/// A tile-frame point back to the chart.
Q2 from_frame(const Pair& P, const mpq_class& u0, const mpq_class& u1) {
  Q2 x{u0, u1};
  if (P.sheared) x[1 - P.lead] += P.slope * x[P.lead];
  return x;
}

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

/// What casts: a face (its convex pieces) or a closed convex solid, in the order of the faces.
struct Unit {
  int solid = -1;  ///< index into the solids, or -1 for a face on its own
  std::size_t face = 0;
};

/// The casts of units [first, last) for one pair, in unit order.
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

constexpr std::size_t kMaxTilesPerAxis = 16;

/// The tile grid of a pair: inner cuts along its tile frame's two axes (Pair::sheared; infinite
/// outer bounds).
struct Grid {
  std::array<std::vector<double>, 2> cuts;  ///< strictly increasing, finite
  [[nodiscard]] std::size_t columns() const { return cuts[0].size() + 1; }
  [[nodiscard]] std::size_t rows() const { return cuts[1].size() + 1; }
  [[nodiscard]] std::size_t tiles() const { return columns() * rows(); }
};

/// Cuts at quantiles of the images' centres along the tile frame's axes, so that tiles hold
/// similar numbers of images (about images / per_tile tiles), and tiles at least
/// Tiling::tile_over_image times as wide as the median image along each axis (an image cut into
/// many pieces costs more than the tiles save): an axis along which images are long (u_lead of a
/// sheared frame under a low sun) gets fewer cuts and the other more. Depends on the images
/// only, never on the thread count.
Grid make_grid(const std::vector<Image>& images, const Tiling& tiling) {
  Grid grid;
  if (images.size() < tiling.tile_from || tiling.per_tile == 0) return grid;
  const double wanted = static_cast<double>(images.size()) / static_cast<double>(tiling.per_tile);
  std::array<std::vector<double>, 2> centre;
  std::size_t fit[2];
  std::vector<double> extent(images.size());
  for (int axis = 0; axis < 2; ++axis) {
    for (std::size_t a = 0; a < images.size(); ++a) extent[a] = images[a].box[axis + 2] - images[a].box[axis];
    std::nth_element(extent.begin(), extent.begin() + static_cast<std::ptrdiff_t>(extent.size() / 2), extent.end());
    const double median_extent = extent[extent.size() / 2];
    centre[axis].resize(images.size());
    for (std::size_t a = 0; a < images.size(); ++a) centre[axis][a] = 0.5 * images[a].box[axis] + 0.5 * images[a].box[axis + 2];
    std::sort(centre[axis].begin(), centre[axis].end());
    const double spread = centre[axis].back() - centre[axis].front();
    const double wide = tiling.tile_over_image > 0 ? spread / (tiling.tile_over_image * median_extent) : 1e6;
    fit[axis] = wide >= 1 && std::isfinite(wide) ? static_cast<std::size_t>(std::min(wide, 1e6)) : 1;
  }
  // The square grid's share per axis; what one axis cannot take (fit) goes to the other. Every
  // count is in [1, kMaxTilesPerAxis] (share's range, fit >= 1).
  const auto share = [](double of) {
    return static_cast<std::size_t>(std::clamp(std::round(of), 1.0, static_cast<double>(kMaxTilesPerAxis)));
  };
  std::size_t count[2];
  count[0] = std::min(share(std::sqrt(wanted)), fit[0]);
  count[1] = std::min(share(wanted / static_cast<double>(count[0])), fit[1]);
  count[0] = std::min(std::max(count[0], share(wanted / static_cast<double>(count[1]))), fit[0]);
  for (int axis = 0; axis < 2; ++axis) {
    const std::vector<double>& sorted = centre[axis];
    const std::size_t g = count[axis];
    for (std::size_t c = 1; c < g; ++c) {
      const double cut = sorted[c * sorted.size() / g];
      if (std::isfinite(cut) && (grid.cuts[axis].empty() || cut > grid.cuts[axis].back())) grid.cuts[axis].push_back(cut);
    }
  }
  return grid;
}

/// An edge of a tile's region lying on one of the tile's inner borders.
struct BorderEdge {
  std::size_t line = 0;  ///< which cut: axis * 65536 + cut index
  bool high = false;     ///< the edge lies on the tile's upper border along that axis
  mpq_class from, to;    ///< its extent along the other axis, from < to
  std::size_t region = 0;  ///< the region, numbered within the pair (tile offsets added later)
};

/// What one tile of one pair gives: polygons in 3D, exact chart area, edges on its borders.
struct TileResult {
  std::vector<std::vector<glm::dvec3>> polygons;
  std::vector<std::size_t> region_id;  ///< within the tile
  std::vector<double> polygon_area;
  std::size_t regions = 0;
  mpq_class chart_area = 0;
  std::vector<BorderEdge> border;
};

/// Spreads the low 16 bits of v to the even bits (Morton code).
std::uint32_t spread(std::uint32_t v) {
  v &= 0xffff;
  v = (v | (v << 8)) & 0x00ff00ff;
  v = (v | (v << 4)) & 0x0f0f0f0f;
  v = (v | (v << 2)) & 0x33333333;
  v = (v | (v << 1)) & 0x55555555;
  return v;
}

/// `members` in Z order of their boxes' centres (ties by index). CGAL's aggregated join merges
/// its inputs by divide and conquer in the order given: in space order each partial union
/// swallows the edges inside it before the next merge, instead of carrying every edge (and
/// every crossing of the long shadows of a low sun) up to the last merge.
std::vector<std::size_t> spatial_order(const std::vector<Image>& images, std::vector<std::size_t> members) {
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-lo[0], -lo[1]};
  std::vector<std::array<double, 2>> centre(members.size());
  for (std::size_t a = 0; a < members.size(); ++a)
    for (int axis = 0; axis < 2; ++axis) {
      const std::array<double, 4>& box = images[members[a]].box;
      centre[a][axis] = 0.5 * box[axis] + 0.5 * box[axis + 2];
      lo[axis] = std::min(lo[axis], centre[a][axis]);
      hi[axis] = std::max(hi[axis], centre[a][axis]);
    }
  std::vector<std::pair<std::uint32_t, std::size_t>> keyed(members.size());
  for (std::size_t a = 0; a < members.size(); ++a) {
    std::uint32_t cell[2];
    for (int axis = 0; axis < 2; ++axis) {
      const double span = hi[axis] - lo[axis];
      const double t = span > 0 && std::isfinite(span) ? (centre[a][axis] - lo[axis]) / span : 0.0;
      cell[axis] = static_cast<std::uint32_t>(std::clamp(t, 0.0, 1.0) * 65535.0);
    }
    keyed[a] = {spread(cell[0]) | (spread(cell[1]) << 1), members[a]};
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t a = 0; a < members.size(); ++a) members[a] = keyed[a].second;
  return members;
}

using ApproxKernel = exact::Kernel::Approximate_kernel;
using ExactKernel = exact::Kernel::Exact_kernel;

// lazy_point and exact_of reach into CGAL 5.5's lazy representations (Lazy_rep_0 built with
// both values, Lazy_rep::is_lazy and exact_unsafe): checked there; any other CGAL takes the
// public, slower route (the same values).
#if CGAL_VERSION_NR >= 1050500000 && CGAL_VERSION_NR < 1050600000
#define SHADOW_PLANES_LAZY_INTERNALS 1
#else
#define SHADOW_PLANES_LAZY_INTERNALS 0
#endif

#if SHADOW_PLANES_LAZY_INTERNALS
/// The tightest interval of doubles around a rational: a point when it is a double, else the
/// double below and the double above (mpq_get_d truncates toward zero). What CGAL's conversion
/// gives, without its MPFR division.
CGAL::Interval_nt<false> enclosure(const mpq_class& q) {
  const double d = q.get_d();
  const int sign = sgn(q);
  if (mpz_popcount(q.get_den_mpz_t()) == 1 && cmp(q, d) == 0) return {d, d};  // a dyadic rational may be a double
  const double away = std::nextafter(d, sign > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
  return sign > 0 ? CGAL::Interval_nt<false>(d, away) : CGAL::Interval_nt<false>(away, d);
}
#endif

/// An exact chart point as a lazy point whose exact value is known from the start (one node,
/// no lazy coordinates): CGAL evaluates it without a DAG, and exact_of reads it back directly.
exact::Point2 lazy_point(const Q2& q) {
#if SHADOW_PLANES_LAZY_INTERNALS
  using PointRep = CGAL::Lazy_rep_0<ApproxKernel::Point_2, ExactKernel::Point_2, exact::Kernel::E2A>;
  return exact::Point2(new PointRep(ApproxKernel::Point_2(enclosure(q[0]), enclosure(q[1])), ExactKernel::Point_2(q[0], q[1])));
#else
  return exact::Point2(exact::FT(q[0]), exact::FT(q[1]));
#endif
}

/// CGAL::exact(p), without std::call_once when the exact value is already known (glibc's
/// pthread_once makes a futex system call every time it runs an initialisation, even an
/// empty one). Only for lazy points that no other thread touches. CGAL 5.5's Lazy keeps its
/// representation private; Handle::for_compact_container is the public way to it.
const ExactKernel::Point_2& exact_of(const exact::Point2& p) {
#if SHADOW_PLANES_LAZY_INTERNALS
  using Rep = CGAL::Lazy_rep<ApproxKernel::Point_2, ExactKernel::Point_2, exact::Kernel::E2A>;
  const auto* rep = static_cast<const Rep*>(static_cast<CGAL::Rep*>(static_cast<const CGAL::Handle&>(p).for_compact_container()));
  return rep->is_lazy() ? CGAL::exact(p) : rep->exact_unsafe();
#else
  return CGAL::exact(p);
#endif
}

/// Twice the signed area of a polygon, exactly, from its vertices' exact rational coordinates
/// (the shoelace; the same value as exact::polygon_area's, without a lazy node per term).
mpq_class exact_twice_area(const exact::Polygon2& polygon) {
  static_assert(std::is_same_v<std::decay_t<decltype(CGAL::exact(std::declval<exact::FT>()))>, mpq_class>,
                "the exact kernel's numbers are GMP rationals");
  const std::size_t n = polygon.size();
  mpq_class twice(0), term;
  for (std::size_t a = 0; a < n; ++a) {
    const auto& p = exact_of(polygon[a]);
    const auto& q = exact_of(polygon[(a + 1) % n]);
    term = p.x() * q.y();
    twice += term;
    term = q.x() * p.y();
    twice -= term;
  }
  return twice;
}

/// exact::area_3d for twice an exact chart area: sqrt(area^2 x scale), the rational rounded to
/// 256 bits before the root (exact::sqrt_to_double), so bit for bit the same double.
double area_3d(const mpq_class& twice_chart_area, const mpq_class& scale_squared) {
  if (sgn(twice_chart_area) == 0) return 0.0;
  const mpq_class squared = twice_chart_area * twice_chart_area * scale_squared / 4;
  return exact::sqrt_mpq_to_double(squared.get_mpq_t());
}

/// Unites the images of one tile (clipped to it) and writes its regions back onto the plane.
void unite_tile(const Scene& scene, const Pair& P, const std::vector<Image>& images, const Grid& grid,
                const std::vector<std::size_t>& members, std::size_t tile, TileResult& out) {
  const std::size_t column = tile % grid.columns(), row = tile / grid.columns();
  const std::size_t cell_of[2] = {column, row};
  // The tile's finite bounds: lower[axis] is cut[cell - 1], upper[axis] is cut[cell].
  bool has_lower[2], has_upper[2];
  mpq_class lower[2], upper[2];
  double lower_d[2], upper_d[2];
  for (int axis = 0; axis < 2; ++axis) {
    const std::vector<double>& cuts = grid.cuts[axis];
    const std::size_t cell = cell_of[axis];
    has_lower[axis] = cell > 0;
    has_upper[axis] = cell < cuts.size();
    lower_d[axis] = has_lower[axis] ? cuts[cell - 1] : -std::numeric_limits<double>::infinity();
    upper_d[axis] = has_upper[axis] ? cuts[cell] : std::numeric_limits<double>::infinity();
    if (has_lower[axis]) lower[axis] = cuts[cell - 1];
    if (has_upper[axis]) upper[axis] = cuts[cell];
  }
  std::vector<exact::Polygon2> pieces;
  std::vector<Q2> poly;
  for (std::size_t m : spatial_order(images, members)) {
    const Image& image = images[m];
    poly = image.vertices;
    bool cut = false;
    for (int axis = 0; axis < 2; ++axis) {
      if (image.box[axis] <= lower_d[axis]) cut |= clip_axis(poly, axis, lower[axis], false);
      if (image.box[axis + 2] >= upper_d[axis]) cut |= clip_axis(poly, axis, upper[axis], true);
    }
    if (poly.size() < 3) continue;
    // A cut along an image's edge leaves a flat sliver (or nothing); an image not cut has a
    // positive area.
    if (cut && sgn(twice_area(poly)) <= 0) continue;
    exact::Polygon2 piece;
    for (const Q2& x : poly) piece.push_back(lazy_point(x));
    pieces.push_back(std::move(piece));
  }
  if (pieces.empty()) return;
  exact::PolygonSet2 shadow;
  shadow.join(pieces.begin(), pieces.end());
  std::vector<exact::PolygonWithHoles2> regions;
  shadow.polygons_with_holes(std::back_inserter(regions));
  out.regions = regions.size();

  // Back to 3D on the plane (as given, not turned): x_k = -(c + n_i x_i + n_j x_j) / n_k.
  // Everything below works on the vertices' exact rational coordinates, taken from each lazy
  // point once (CGAL::exact), never on new lazy numbers: each lazy node evaluated exactly costs
  // a std::call_once (and, in glibc, a futex wake system call), and areas, border edges and
  // cells built as lazy expressions were a third of a tile's time.
  const int i = P.i, j = P.j, k = P.k;
  const mpq_class scale_squared = (P.n[0] * P.n[0] + P.n[1] * P.n[1] + P.n[2] * P.n[2]) / (P.n[k] * P.n[k]);
  const bool flipped = scene.planes[P.plane_id].normal[k] < 0;  // the chart sees the plane clockwise
  // A plane normal to axis k (the ground): x_k is one number, -c / n_k, the same double as the
  // general expression gives (0 x_i and 0 x_j add exact zeros, intervals included).
  const bool level = sgn(P.n[i]) == 0 && sgn(P.n[j]) == 0;
  const double level_k = level ? exact::round_mpq_to_double(mpq_class(-P.c / P.n[k]).get_mpq_t()) : 0.0;
  mpq_class chart_area = 0, twice;
  std::vector<exact::Polygon2> cells;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const exact::Polygon2& outer = regions[r].outer_boundary();
    // Edges on the tile's inner borders: where this region may continue in the next tile.
    const std::size_t n = outer.size();
    for (std::size_t a = 0; a < n; ++a) {
      const auto& source = exact_of(outer[a]);
      const auto& target = exact_of(outer[(a + 1) % n]);
      for (int axis = 0; axis < 2; ++axis) {
        const mpq_class& sa = axis == 0 ? source.x() : source.y();
        const mpq_class& ta = axis == 0 ? target.x() : target.y();
        if (sa != ta) continue;  // not parallel to that border
        for (int high = 0; high < 2; ++high) {
          if (!(high ? has_upper[axis] : has_lower[axis]) || sa != (high ? upper[axis] : lower[axis])) continue;
          mpq_class from(axis == 0 ? source.y() : source.x());
          mpq_class to(axis == 0 ? target.y() : target.x());
          if (from > to) std::swap(from, to);
          const std::size_t cut = cell_of[axis] - (high ? 0 : 1);
          out.border.push_back({static_cast<std::size_t>(axis) * 65536 + cut, high == 1, from, to, r});
        }
      }
    }
    // Simple cells, and the region's exact twice area as the sum of theirs (they tile it).
    cells.clear();
    const bool whole = regions[r].number_of_holes() == 0 && !exact::has_repeated_vertex(outer);
    if (!whole) exact::append_simple_cells(regions[r], cells);
    const std::size_t count = whole ? 1 : cells.size();
    for (std::size_t c = 0; c < count; ++c) {
      const exact::Polygon2& cell = whole ? outer : cells[c];
      twice = exact_twice_area(cell);
      chart_area += twice;
      std::vector<glm::dvec3> polygon;
      polygon.reserve(cell.size());
      for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
        glm::dvec3 x;
        if (P.sheared) {  // back from the tile frame, exactly, then each coordinate's double
          const auto& e = exact_of(*v);
          const Q2 q = from_frame(P, e.x(), e.y());
          x[i] = exact::round_mpq_to_double(q[0].get_mpq_t());
          x[j] = exact::round_mpq_to_double(q[1].get_mpq_t());
          x[k] = level ? level_k : exact::round_mpq_to_double(mpq_class(-(P.c + P.n[i] * q[0] + P.n[j] * q[1]) / P.n[k]).get_mpq_t());
          polygon.push_back(x);
          continue;
        }
        // Each coordinate the double nearest to its exact value (CGAL::to_double would give the
        // midpoint of whatever interval the lazy number holds at that moment).
        const auto& e = exact_of(*v);
        x[i] = exact::round_mpq_to_double(e.x().get_mpq_t());
        x[j] = exact::round_mpq_to_double(e.y().get_mpq_t());
        x[k] = level ? level_k : exact::round_mpq_to_double(mpq_class(-(P.c + P.n[i] * e.x() + P.n[j] * e.y()) / P.n[k]).get_mpq_t());
        polygon.push_back(x);
      }
      if (flipped == (sgn(twice) > 0)) std::reverse(polygon.begin(), polygon.end());
      out.polygons.push_back(std::move(polygon));
      out.region_id.push_back(r);
      out.polygon_area.push_back(area_3d(twice, scale_squared));
    }
  }
  out.chart_area = chart_area / 2;
}

/// Union-find over the regions of a pair.
struct Components {
  std::vector<std::size_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
  std::size_t find(std::size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the first region
  }
};

/// The tiles' results, in tile order, as one PlaneShadow: regions that share a stretch of
/// border (not a mere point) are one region, as the untiled union would have made them.
void assemble(const Pair& P, std::vector<TileResult>& tiles, PlaneShadow& out) {
  std::vector<std::size_t> offset(tiles.size() + 1, 0);
  for (std::size_t t = 0; t < tiles.size(); ++t) offset[t + 1] = offset[t] + tiles[t].regions;
  Components components(offset.back());
  std::vector<BorderEdge> border;
  for (std::size_t t = 0; t < tiles.size(); ++t)
    for (BorderEdge& e : tiles[t].border) {
      e.region += offset[t];
      border.push_back(std::move(e));
    }
  std::sort(border.begin(), border.end(), [](const BorderEdge& a, const BorderEdge& b) {
    if (a.line != b.line) return a.line < b.line;
    return cmp(a.from, b.from) < 0;
  });
  // Edges of one side of a line never overlap one another; an edge of the other side that
  // starts before this one ends overlaps it along a stretch of positive length.
  for (std::size_t a = 0; a < border.size(); ++a)
    for (std::size_t b = a + 1; b < border.size() && border[b].line == border[a].line && border[b].from < border[a].to; ++b)
      if (border[b].high != border[a].high) components.join(border[a].region, border[b].region);
  std::vector<std::size_t> number(offset.back(), 0);
  std::size_t regions = 0;
  for (std::size_t r = 0; r < offset.back(); ++r) number[r] = components.find(r) == r ? regions++ : number[components.find(r)];
  mpq_class chart_area = 0;
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    TileResult& tile = tiles[t];
    chart_area += tile.chart_area;
    for (std::size_t c = 0; c < tile.polygons.size(); ++c) {
      out.polygons.push_back(std::move(tile.polygons[c]));
      out.region_id.push_back(number[offset[t] + tile.region_id[c]]);
      out.polygon_area.push_back(tile.polygon_area[c]);
    }
  }
  const exact::FT nk(P.n[P.k]);
  const exact::FT scale_squared = exact::FT(P.n[0] * P.n[0] + P.n[1] * P.n[1] + P.n[2] * P.n[2]) / (nk * nk);
  out.area = exact::area_3d(exact::FT(chart_area), scale_squared);
}

/// Units of this many casters are one work item of the projection phase.
constexpr std::size_t kUnitsPerItem = 128;

}  // namespace
}  // namespace planes

namespace planes {

std::vector<PlaneShadow> plane_shadows(const Scene& scene, const std::vector<core::FacePrep>& prep,
                                       const std::vector<core::ConvexSolid>& solids, const std::vector<int>& solid_of,
                                       const ShadowOptions& options, const Tiling& tiling) {
  const std::vector<std::size_t> light_ids = shadow::detail::resolve_lights(scene, options.lights);
  const unsigned threads = core::resolve_threads(core::checked_threads(options.threads));
  if (!(options.plane_window >= 0 && options.plane_window <= max_coordinate))
    throw InputError({"", "ShadowOptions::plane_window"},
                     "must be in [0, 2^500 (about 3.27e150)], got " + shadow::detail::format_number(options.plane_window));
  if (scene.planes.empty() || light_ids.empty()) return {};

  const core::SceneFrame frame = core::scene_frame(scene);
  const double window = options.plane_window > 0 ? options.plane_window : 10.0 * frame.diagonal;
  for (std::size_t plane_id = 0; plane_id < scene.planes.size(); ++plane_id) {
    const double own = scene.planes[plane_id].window > 0 ? scene.planes[plane_id].window : window;
    // The window's corners must be finite numbers to become exact rationals.
    const glm::dvec3 lo = frame.centre - own, hi = frame.centre + own;
    if (!std::isfinite(own) || !std::isfinite(lo.x + lo.y + lo.z) || !std::isfinite(hi.x + hi.y + hi.z))
      throw InputError({"", "planes[" + std::to_string(plane_id) + "].window"},
                       "the plane-shadow window is too large to represent (" + std::to_string(own) + ")");
  }

  // What casts, in face order: a solid at its first face, every other face on its own.
  std::vector<std::vector<std::size_t>> solid_faces(solids.size());
  std::vector<Unit> units;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const int s = tiling.solids && f < solid_of.size() ? solid_of[f] : -1;
    if (s < 0) {
      units.push_back({-1, f});
      continue;
    }
    std::vector<std::size_t>& faces = solid_faces[static_cast<std::size_t>(s)];
    if (faces.empty()) units.push_back({s, f});
    faces.push_back(f);
  }

  const std::size_t pair_count = scene.planes.size() * light_ids.size();
  std::vector<Pair> pairs(pair_count);
  for (std::size_t item = 0; item < pair_count; ++item) {
    const std::size_t plane_id = item / light_ids.size();
    const double own = scene.planes[plane_id].window;
    pairs[item] = make_pair(scene, plane_id, light_ids[item % light_ids.size()], frame, own > 0 ? own : window, tiling.shear);
  }

  // Projection: every pair's casters in chunks of units, all on the same workers.
  const std::size_t chunks = (units.size() + kUnitsPerItem - 1) / kUnitsPerItem;
  std::vector<std::vector<Image>> chunk_images(pair_count * chunks);
  std::vector<char> chunk_reaches(pair_count * chunks, 0);
  core::parallel_for(pair_count * chunks, threads, [&](unsigned, std::size_t item) {
    const Pair& P = pairs[item / chunks];
    if (!P.casts) return;
    const std::size_t first = (item % chunks) * kUnitsPerItem;
    bool reaches = false;
    cast_units(scene, prep, solids, solid_faces, units, first, std::min(units.size(), first + kUnitsPerItem), P,
               chunk_images[item], reaches);
    chunk_reaches[item] = reaches;
  });

  // Tiles: a grid fixed by each pair's images; each image goes to the tiles its box meets.
  std::vector<std::vector<Image>> images(pair_count);
  std::vector<Grid> grids(pair_count);
  std::vector<std::vector<std::vector<std::size_t>>> members(pair_count);
  std::vector<std::pair<std::size_t, std::size_t>> tile_items;  // (pair, tile)
  std::vector<PlaneShadow> shadows(pair_count);
  for (std::size_t a = 0; a < pair_count; ++a) {
    PlaneShadow& out = shadows[a];
    out.plane_id = pairs[a].plane_id;
    out.light_id = pairs[a].light_id;
    out.window_half_size = pairs[a].window;
    for (std::size_t c = 0; c < chunks; ++c) {
      std::vector<Image>& part = chunk_images[a * chunks + c];
      out.reaches_window |= chunk_reaches[a * chunks + c] != 0;
      for (Image& image : part) images[a].push_back(std::move(image));
      part = {};
    }
    grids[a] = make_grid(images[a], tiling);
    const Grid& grid = grids[a];
    members[a].resize(grid.tiles());
    for (std::size_t m = 0; m < images[a].size(); ++m) {
      const std::array<double, 4>& box = images[a][m].box;
      std::size_t first[2], last[2];  // the columns and rows the box meets (closed bounds)
      for (int axis = 0; axis < 2; ++axis) {
        const std::vector<double>& cuts = grid.cuts[axis];
        first[axis] = static_cast<std::size_t>(std::lower_bound(cuts.begin(), cuts.end(), box[axis]) - cuts.begin());
        last[axis] = static_cast<std::size_t>(std::upper_bound(cuts.begin(), cuts.end(), box[axis + 2]) - cuts.begin());
      }
      for (std::size_t row = first[1]; row <= last[1]; ++row)
        for (std::size_t column = first[0]; column <= last[0]; ++column) members[a][row * grid.columns() + column].push_back(m);
    }
    for (std::size_t t = 0; t < grid.tiles(); ++t)
      if (!members[a][t].empty()) tile_items.emplace_back(a, t);
  }

  // Unions: every pair's tiles on the same workers, the tiles with the most images first (the
  // workers take items in order: a large tile taken last would leave the others idle). Each
  // tile writes its own result, so the order changes no result.
  std::stable_sort(tile_items.begin(), tile_items.end(), [&](const auto& x, const auto& y) {
    return members[x.first][x.second].size() > members[y.first][y.second].size();
  });
  std::vector<std::vector<TileResult>> tiles(pair_count);
  for (std::size_t a = 0; a < pair_count; ++a) tiles[a].resize(grids[a].tiles());
  core::parallel_for(tile_items.size(), threads, [&](unsigned, std::size_t item) {
    const auto [a, t] = tile_items[item];
    unite_tile(scene, pairs[a], images[a], grids[a], members[a][t], t, tiles[a][t]);
  });
  for (std::size_t a = 0; a < pair_count; ++a)
    if (pairs[a].casts) assemble(pairs[a], tiles[a], shadows[a]);
  return shadows;
}

}  // namespace planes

std::vector<PlaneShadow> planes::compute_plane_shadows(const Scene& scene, const ShadowOptions& options,
                                                       const Tiling& tiling) {
  shadow::detail::check_scene_numbers(scene);  // the scene may never have been validated
  const unsigned threads = core::resolve_threads(core::checked_threads(options.threads));
  std::vector<core::FacePrep> prep(scene.faces.size());
  core::parallel_for(scene.faces.size(), threads, [&](unsigned, std::size_t f) {
    if (scene.faces[f].degenerate || scene.faces[f].vertices.size() < 3) {
      prep[f].degenerate = true;
      return;
    }
    prep[f] = exact::prepare_face(scene.faces[f].vertices);
  });
  std::vector<int> solid_of;
  const std::vector<core::ConvexSolid> solids = exact::find_convex_solids(scene, prep, solid_of, threads);
  return planes::plane_shadows(scene, prep, solids, solid_of, options, tiling);
}

std::vector<PlaneShadow> compute_plane_shadows(const Scene& scene, const ShadowOptions& options) {
  // Nothing counted: 0 of 0, about every 100 ms, so that the callback can stop the call.
  const core::TickScope ticks(options.progress ? std::function<void()>([&] { options.progress(Progress{0, 0}); })
                                               : std::function<void()>());
  return planes::compute_plane_shadows(scene, options, planes::Tiling{});
}

}  // namespace shadow
