// SPDX-License-Identifier: GPL-3.0-or-later
// Clipping and projection of casters with lazy exact values (Epeck): the route for faces that
// are not exactly planar in the input and are lifted onto their plane. Exact throughout.
// Include only from src/exact/*.cpp (CGAL).
#pragma once

#include "geometry/box_sides.hpp"
#include "geometry/clip_convex.hpp"
#include "geometry/exact_facing.hpp"
#include "exact/exact_faces.hpp"

#include <array>
#include <vector>

namespace shadow::exact {


/// A light in homogeneous form l = (x, y, z, w): (L, 1) for a point light, (d, 0) for a
/// directional light with d pointing toward it. Exact (the input doubles are exact rationals).
struct ExactLight {
  std::array<FT, 4> l;
  [[nodiscard]] bool is_point() const { return !CGAL::is_zero(l[3]); }
};

/// A scene light in that form: (position, 1) for a point light, (to_light, 0) for a directional one.
inline ExactLight to_exact_light(const Light& light) {
  if (light.type == LightType::Point) return {{FT(light.position.x), FT(light.position.y), FT(light.position.z), FT(1)}};
  return {{FT(light.to_light.x), FT(light.to_light.y), FT(light.to_light.z), FT(0)}};
}

/// The sign of plane_at_light(make_exact_face(face), to_exact_light(light)) for an exactly
/// planar face under a directional light, without building the exact face: the sign of
/// det[next - corner, prev - corner, d] (negated for a flipped face), on intervals first and in
/// rationals when they hold 0 (a wall edge-on to the sun). The year's series decides half its
/// receivers (the back-facing ones) by this alone.
inline int directional_facing_sign(const std::vector<glm::dvec3>& vertices, const core::FacePrep& prep,
                                   const glm::dvec3& d) {
  const int sign = geometry::exact_facing_sign(vertices[prep.corner[1]], vertices[prep.corner[2]], vertices[prep.corner[0]], d);
  return prep.flipped ? -sign : sign;
}

/// s~(l) = n . l_xyz + offset * l_w: positive when the light is on the front side of the plane.
inline FT plane_at_light(const ExactFace& face, const ExactLight& light) {
  return face.normal.x() * light.l[0] + face.normal.y() * light.l[1] +
         face.normal.z() * light.l[2] + face.offset * light.l[3];
}

/// Sutherland-Hodgman clip of a convex polygon of any exact point type P to value(p) >= 0, for
/// an affine `value` (geometry/clip_convex.hpp). Vertices with value exactly 0 are kept;
/// crossings, lerp(a, b, t) = a + t (b - a) at t = value(a) / (value(a) - value(b)), are made
/// only where the value changes sign strictly, so no duplicates arise. The exact half-space clip
/// of 3D planes, chart half-planes and homogeneous points (clip_convex_to_window below cuts by a
/// polygon's edges, deciding sides with Epeck's orientation predicate instead of a value's sign,
/// and clip_by_signs makes its crossings).
template <class P, class Value, class Lerp>
void clip_by_value(std::vector<P>& poly, Value&& value_of, Lerp&& lerp, std::vector<P>& scratch) {
  if (poly.empty()) return;
  const std::size_t n = poly.size();
  std::vector<FT> value(n);
  std::vector<int> side(n);
  for (std::size_t a = 0; a < n; ++a) {
    value[a] = value_of(poly[a]);
    side[a] = static_cast<int>(CGAL::sign(value[a]));
  }
  auto side_of = [&](std::size_t a) { return side[a]; };
  switch (geometry::clip_case(n, side_of)) {
    case geometry::ClipCase::Inside: return;  // wholly inside (or on the boundary)
    case geometry::ClipCase::Empty: poly.clear(); return;  // nothing strictly inside: no area
    case geometry::ClipCase::Cut: break;
  }
  geometry::clip_convex(poly, side_of, [&](std::size_t a, std::size_t b) {
    return lerp(poly[a], poly[b], value[a] / (value[a] - value[b]));
  }, scratch);
  poly.swap(scratch);
}

/// clip_by_value for 3D points and the affine function f: keeps f >= 0.
inline void clip_convex(std::vector<Point3>& poly, const Affine3& f, std::vector<Point3>& scratch) {
  clip_by_value(poly, f, [](const Point3& a, const Point3& b, const FT& t) { return a + t * (b - a); }, scratch);
}

/// Sutherland-Hodgman clip of a convex polygon to s >= 0 for an affine s whose exact signs at the
/// vertices are already known (`sign`, any type convertible to -1, 0, +1): s is evaluated (lazily)
/// only on the edges that cross, at t = s(a) / (s(a) - s(b)).
template <class P, class Signs, class S>
void clip_by_signs(std::vector<P>& poly, const Signs& sign, S&& s, std::vector<P>& scratch) {
  geometry::clip_convex(poly, [&](std::size_t a) { return static_cast<int>(sign[a]); },
                        [&](std::size_t a, std::size_t b) {
                          const FT sa = s(poly[a]), sb = s(poly[b]);
                          return poly[a] + (sa / (sa - sb)) * (poly[b] - poly[a]);
                        }, scratch);
  poly.swap(scratch);
}

/// Clip of a convex polygon to the front of the receiver's plane (s >= 0) when the exact signs of
/// s at its vertices are already known.
inline void clip_front(std::vector<Point3>& poly, const std::vector<CGAL::Sign>& sign, const Affine3& s,
                std::vector<Point3>& scratch) {
  clip_by_signs(poly, sign, s, scratch);
}

/// Sutherland-Hodgman clip of a convex 2D polygon to x_c >= m (keep_greater) or x_c <= m; the
/// crossings get m exactly in coordinate c.
inline void clip_convex_2d(std::vector<Point2>& poly, int c, double m, bool keep_greater,
                    std::vector<Point2>& scratch) {
  if (poly.empty()) return;
  const std::size_t n = poly.size();
  std::vector<int> in(n);
  for (std::size_t a = 0; a < n; ++a) {
    const CGAL::Comparison_result r = CGAL::compare(poly[a][c], FT(m));
    in[a] = keep_greater ? static_cast<int>(r) : -static_cast<int>(r);  // +1 inside, -1 outside
  }
  auto side = [&](std::size_t a) { return in[a]; };
  switch (geometry::clip_case(n, side)) {
    case geometry::ClipCase::Inside: return;
    case geometry::ClipCase::Empty: poly.clear(); return;
    case geometry::ClipCase::Cut: break;
  }
  const int o = 1 - c;
  geometry::clip_convex(poly, side, [&](std::size_t a, std::size_t b) {
    const Point2& pa = poly[a];
    const Point2& pb = poly[b];
    const FT other = pa[o] + (FT(m) - pa[c]) * (pb[o] - pa[o]) / (pb[c] - pa[c]);
    return c == 0 ? Point2(FT(m), other) : Point2(other, FT(m));
  }, scratch);
  poly.swap(scratch);
}

/// Sutherland-Hodgman clip of a convex 2D polygon to the convex counter-clockwise polygon
/// `window` (each edge's left side, closed), exact: Epeck's orientation predicate decides the
/// sides (filtered: no lazy number per vertex, as clip_by_value's value would make), and
/// clip_by_signs makes the crossings. Vertices on a window edge are kept; the result may repeat
/// a point (no area is lost or added).
inline void clip_convex_to_window(std::vector<Point2>& poly, const Polygon2& window, std::vector<Point2>& scratch) {
  std::vector<int> in;
  for (auto e = window.edges_begin(); e != window.edges_end() && !poly.empty(); ++e) {
    const Point2& p = e->source();
    const Point2& q = e->target();
    in.resize(poly.size());
    for (std::size_t a = 0; a < poly.size(); ++a) in[a] = static_cast<int>(CGAL::orientation(p, q, poly[a]));  // +1 left
    switch (geometry::clip_case(poly.size(), [&](std::size_t a) { return in[a]; })) {
      case geometry::ClipCase::Inside: continue;
      case geometry::ClipCase::Empty: poly.clear(); continue;
      case geometry::ClipCase::Cut: break;
    }
    const FT ex = q.x() - p.x(), ey = q.y() - p.y();
    clip_by_signs(poly, in, [&](const Point2& u) { return ex * (u.y() - p.y()) - ey * (u.x() - p.x()); }, scratch);
  }
}

/// The set of half-spaces a caster is clipped to for one receiver, and the projection.
struct ReceiverFrame {
  int axis = 2;
  FT light_side;                  ///< s~(l) > 0
  Affine3 front;                  ///< s(p) >= 0: in front of the receiver's plane
  std::array<Affine3, 4> sides;   ///< the prism/pyramid over the chart bounding box
  std::array<FT, 2> shift;        ///< directional: l_c / s~(l) for the chart axes c = i, j
};

inline ReceiverFrame make_frame(const ExactFace& face, const core::FacePrep& prep, const ExactLight& light,
                         const FT& light_side) {
  ReceiverFrame frame;
  const int k = prep.axis;
  frame.axis = k;
  frame.light_side = light_side;
  frame.front = Affine3{face.normal, face.offset};
  if (light.is_point()) {  // directional lights are clipped to the box in 2D instead
    const std::array<FT, 4> plane{face.normal.x(), face.normal.y(), face.normal.z(), face.offset};
    const auto sides = geometry::box_sides(plane, light.l, light_side, core::chart_i(k), core::chart_j(k), prep.chart_min.data(),
                                 prep.chart_max.data());
    for (int t = 0; t < 4; ++t)
      frame.sides[t] = Affine3{Vector3(sides[t][0], sides[t][1], sides[t][2]), sides[t][3]};
  }
  if (!light.is_point()) {
    frame.shift = {light.l[core::chart_i(k)] / light_side, light.l[core::chart_j(k)] / light_side};
  }
  return frame;
}

/// Projects a point (strictly between the receiver's plane and the light) from the light onto
/// the receiver's plane and returns its chart coordinates:  X = (s~ Y - s(Y) l) / (s~ - s(Y) l_w).
inline Point2 project_to_chart(const Point3& y, const ReceiverFrame& frame, const ExactLight& light) {
  const FT s = frame.front(y);
  const int i = core::chart_i(frame.axis), j = core::chart_j(frame.axis);
  if (!light.is_point()) return Point2(y[i] - s * frame.shift[0], y[j] - s * frame.shift[1]);
  const FT w = frame.light_side - s;
  return Point2((frame.light_side * y[i] - s * light.l[i]) / w,
                (frame.light_side * y[j] - s * light.l[j]) / w);
}

/// Where edge a-b (s(a) and s(b) of strictly opposite signs) crosses the receiver's plane, in
/// chart coordinates. Points on the plane are their own projection: computing them through the
/// projection formula would give the same value, but through an s that is exactly zero with an
/// interval around it, and every later comparison of such points would need exact arithmetic.
inline Point2 crossing_in_chart(const Point3& a, const Point3& b, const ReceiverFrame& frame) {
  const FT sa = frame.front(a), sb = frame.front(b);
  const FT t = sa / (sa - sb);
  const int i = core::chart_i(frame.axis), j = core::chart_j(frame.axis);
  return Point2(a[i] + t * (b[i] - a[i]), a[j] + t * (b[j] - a[j]));
}

/// Projects the part of a convex polygon in front of the receiver (s >= 0, exact signs given)
/// into the chart, in order: vertices in front are projected, vertices on the plane and
/// crossings of the plane are their own chart points.
inline void project_front_part(const std::vector<Point3>& poly, const std::vector<CGAL::Sign>& sign,
                        const ReceiverFrame& frame, const ExactLight& light, std::vector<Point2>& out) {
  const std::size_t n = poly.size();
  out.clear();
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    if (sign[a] == CGAL::POSITIVE) out.push_back(project_to_chart(poly[a], frame, light));
    if (sign[a] == CGAL::ZERO) out.push_back(to_chart(poly[a], frame.axis));
    if ((sign[a] == CGAL::POSITIVE && sign[b] == CGAL::NEGATIVE) ||
        (sign[a] == CGAL::NEGATIVE && sign[b] == CGAL::POSITIVE))
      out.push_back(crossing_in_chart(poly[a], poly[b], frame));
  }
}

}  // namespace shadow::exact
