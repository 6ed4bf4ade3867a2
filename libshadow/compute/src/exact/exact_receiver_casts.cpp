// SPDX-License-Identifier: GPL-3.0-or-later
// The exact receiver job's casts (exact/exact_receiver_job.hpp): a convex solid's hull, a face
// by the leaf or the lazy route, a whole outline, each kept as a shadow polygon for the union:
// clipped to the receiver's chart box (Epeck casts, and a tile's rational ones), or, as the
// areas-only route's rational casts, kept whole when they reach the box (reaches_chart_box).
#include "exact/exact_receiver_job.hpp"

#include "core/light_space_grid.hpp"
#include "core/solid_outlines.hpp"

#include <CGAL/convex_hull_2.h>

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <optional>
#include <utility>

namespace shadow::exact::receiver_job {

void ExactReceiverJob::clip_to_chart_box(std::vector<Point2>& poly) {
  for (int c = 0; c < 2; ++c) {
    clip_convex_2d(poly, c, fp_.chart_min[c], true, w_.scratch2);
    clip_convex_2d(poly, c, fp_.chart_max[c], false, w_.scratch2);
  }
}

void ExactReceiverJob::clip_to_chart_box_q(QPointList& poly) {
  // A face's casts are measured inside its box or its convex pieces as windows
  // (measure_in_box_window, measure_in_scaled_pieces): a clip would only make rationals (and
  // their gcds: most of a georeferenced model's time). A tile's box is its region's edge:
  // clipped to it.
  if (!boxed_casts()) {
    // Not clipped, but dropped when its clip would leave no area (the same casts counted and
    // the same receivers unshadowed as with the clip).
    if (!reaches_chart_box(poly)) poly.clear();
    return;
  }
  const ScaledChart& chart = scaled_chart();
  // Most casts lie inside the box (the ground's): decided on the intervals, nothing to clip.
  bool inside = true;
  for (std::size_t v = 0; v < poly.size() && inside; ++v) {
    const IPoint2& i = poly[v].i;  // of the unscaled chart
    inside = i.x.inf() >= fp_.chart_min[0] && i.x.sup() <= fp_.chart_max[0] && i.y.inf() >= fp_.chart_min[1] &&
             i.y.sup() <= fp_.chart_max[1];
  }
  if (inside) return;
  for (int c = 0; c < 2; ++c) {
    clip_convex_2d(poly, c, chart.lo(c), chart.ilo(c), true, w_.qscratch, w_.qside, chart.scale_interval());
    clip_convex_2d(poly, c, chart.hi(c), chart.ihi(c), false, w_.qscratch, w_.qside, chart.scale_interval());
  }
}

bool ExactReceiverJob::reaches_chart_box(const QPointList& poly) {
  // Two convex polygons whose interiors do not meet are separated by the line of a side of one
  // of them: a side of the box (every vertex of the cast on or beyond it), or an edge of the
  // cast (every corner of the box on or beyond its line). Intervals first, exact when they
  // cannot tell; a vertex strictly inside the box settles it at once.
  if (poly.size() < 3) return false;
  const ScaledChart& chart = scaled_chart();
  bool beyond[4] = {true, true, true, true};
  for (std::size_t v = 0; v < poly.size(); ++v) {
    const QPoint2& p = poly[v];
    const int x0 = compare(p.x, p.i.x, chart.lo(0), chart.ilo(0)), x1 = compare(p.x, p.i.x, chart.hi(0), chart.ihi(0));
    const int y0 = compare(p.y, p.i.y, chart.lo(1), chart.ilo(1)), y1 = compare(p.y, p.i.y, chart.hi(1), chart.ihi(1));
    if (x0 > 0 && x1 < 0 && y0 > 0 && y1 < 0) return true;
    beyond[0] = beyond[0] && x0 <= 0;
    beyond[1] = beyond[1] && x1 >= 0;
    beyond[2] = beyond[2] && y0 <= 0;
    beyond[3] = beyond[3] && y1 >= 0;
  }
  if (beyond[0] || beyond[1] || beyond[2] || beyond[3]) return false;
  const CGAL::Sign turn = area_sign(poly, w_.qs, w_.qarea);
  if (turn == CGAL::ZERO) return false;  // flat: no area anywhere
  const QPointList& corners = box_corners();
  CGAL::Protect_FPU_rounding<true> guard;
  for (std::size_t a = 0; a < poly.size(); ++a) {
    const QPoint2& p = poly[a];
    const QPoint2& q = poly[a + 1 == poly.size() ? 0 : a + 1];
    bool separates = true;
    for (std::size_t c = 0; c < corners.size() && separates; ++c) {
      const CGAL::Sign side = orientation<false>(p, p.i, q, q.i, corners[c], corners[c].i, w_.qs);
      separates = side == CGAL::ZERO || side != turn;  // on the line, or outside the cast
    }
    if (separates) return false;
  }
  return true;
}

const QPointList& ExactReceiverJob::box_corners() {
  if (!box_corners_ready_) {
    const ScaledChart& chart = scaled_chart();
    w_.qbox.clear();
    for (int c = 0; c < 4; ++c) {  // counter-clockwise from (lo, lo)
      const int cx = c == 1 || c == 2 ? 1 : 0, cy = c >= 2 ? 1 : 0;
      QPoint2& p = w_.qbox.emplace_back();
      p.x = cx ? chart.hi(0) : chart.lo(0);
      p.y = cy ? chart.hi(1) : chart.lo(1);
      p.i = {cx ? chart.ihi(0) : chart.ilo(0), cy ? chart.ihi(1) : chart.ilo(1)};  // (of the unscaled chart)
    }
    box_corners_ready_ = true;
  }
  return w_.qbox;
}

void ExactReceiverJob::cast_convex_solid(int solid) {
  w_.casters.mark_solid_done(solid);
  const core::ConvexSolid& cs = (*ctx_.solids)[solid];
  w_.vertex_sign.resize(cs.vertices.size());
  bool any_front = false, any_behind = false;
  for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
    w_.vertex_sign[v] = input_side(cs.vertices[v]);
    any_front |= w_.vertex_sign[v] == CGAL::POSITIVE;
    any_behind |= w_.vertex_sign[v] == CGAL::NEGATIVE;
  }
  if (!any_front) return;
  if (q_mode_) {
    ScaledChart& projector = scaled_chart();
    // A solid across the receiver's plane passed the culler on its whole: the part behind may
    // lie in the prism over the chart box while the front part's shadow misses the box (about a
    // fifth of the solids cast on an instant of the year). Its clip would be empty: no exact
    // points, crossings or hull for it.
    if (any_behind && projector.misses_box(cs.vertices, w_.vertex_sign, cs.edges)) return;
    QPointList& pts = w_.qpoly;
    if (!hull_from_outline(solid, pts)) {
      pts.clear();
      for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
        if (w_.vertex_sign[v] == CGAL::POSITIVE) projector.project(cs.vertices[v], pts.emplace_back());
        if (w_.vertex_sign[v] == CGAL::ZERO) projector.chart(cs.vertices[v], pts.emplace_back());
      }
      // Crossings only where some vertex is behind: the edges are not even read otherwise.
      for (std::size_t e = 0; any_behind && e < cs.edges.size(); ++e) {
        const auto& [a, b] = cs.edges[e];
        const CGAL::Sign sa = w_.vertex_sign[a], sb = w_.vertex_sign[b];
        if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
          projector.crossing(cs.vertices[a], cs.vertices[b], pts.emplace_back());
      }
      convex_hull(pts, w_.qscratch, w_.qorder, w_.qchain, w_.qs);
      pts.swap(w_.qscratch);
    }
    clip_to_chart_box_q(pts);
    if (pts.size() < 3) return;
    if (area_sign(pts, w_.qs, w_.qarea) != CGAL::POSITIVE) return;  // flat: edge-on solid
    note_cover_q(pts);
    for (QPoint2& p : pts) w_.qshadows.push_back_swap(p);  // pts is scratch from here on
    w_.qfirst.push_back(w_.qshadows.size());
    ++stats_.casting_pairs;
    return;
  }
  LeafProjector& projector = leaf_projector();
  w_.poly2.clear();
  for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
    if (w_.vertex_sign[v] == CGAL::POSITIVE) w_.poly2.push_back(projector.project(cs.vertices[v]));
    if (w_.vertex_sign[v] == CGAL::ZERO) w_.poly2.push_back(projector.chart(cs.vertices[v]));
  }
  for (std::size_t e = 0; any_behind && e < cs.edges.size(); ++e) {  // (as above)
    const auto& [a, b] = cs.edges[e];
    const CGAL::Sign sa = w_.vertex_sign[a], sb = w_.vertex_sign[b];
    if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
      w_.poly2.push_back(projector.crossing(cs.vertices[a], cs.vertices[b]));
  }
  w_.scratch2.clear();
  CGAL::convex_hull_2(w_.poly2.begin(), w_.poly2.end(), std::back_inserter(w_.scratch2), Kernel());
  w_.poly2.swap(w_.scratch2);
  clip_to_chart_box(w_.poly2);
  if (w_.poly2.size() < 3) return;
  Polygon2 projected(w_.poly2.begin(), w_.poly2.end());
  if (CGAL::sign(polygon_area(projected)) != CGAL::POSITIVE) return;  // flat: edge-on solid
  note_cover(projected);
  shadows_.push_back(std::move(projected));
  ++stats_.casting_pairs;
}

bool ExactReceiverJob::hull_from_outline(int solid, QPointList& hull) {
  // Only for a solid wholly in front of the receiver's plane: its points are then its projected
  // vertices alone, and the outline's corners are the corners of their hull.
  for (const CGAL::Sign sign : w_.vertex_sign)
    if (sign != CGAL::POSITIVE) return false;
  const core::SolidOutlines* outlines = grid_ != nullptr ? grid_->outlines() : nullptr;
  if (outlines == nullptr || !outlines->of(ctx_.solids)) return false;
  const core::SolidOutlines::Outline outline = outlines->outline(static_cast<std::size_t>(solid));
  if (outline.size < 3) return false;
  // The projection onto the receiver's plane along the light is an affine map of the plane
  // across the light (core/solid_outlines.hpp), and the outline is certain for the exact
  // projection: strictly convex, every other vertex strictly inside. So the exact hull of the
  // projected vertices is the corners' images in the outline's order, or in the reverse order
  // where the map turns the plane over. (The map is flat only for a receiver edge-on to the
  // light, which casts nothing and never gets here: three images on a line send the solid to
  // convex_hull all the same.)
  const core::ConvexSolid& cs = (*ctx_.solids)[static_cast<std::size_t>(solid)];
  ScaledChart& projector = scaled_chart();
  hull.clear();
  for (std::size_t c = 0; c < outline.size; ++c) projector.project(cs.vertices[outline.data[c]], hull.emplace_back());
  CGAL::Protect_FPU_rounding<true> guard;
  const CGAL::Sign turn = orientation<false>(hull[0], hull[0].i, hull[1], hull[1].i, hull[2], hull[2].i, w_.qs);
  if (turn == CGAL::ZERO) return false;
  if (turn == CGAL::NEGATIVE) std::reverse(hull.begin(), hull.end());
  // From the least point (x, then y), as convex_hull gives it: the same polygon, vertex for vertex.
  std::size_t least = 0;
  for (std::size_t c = 1; c < hull.size(); ++c) {
    const QPoint2 &p = hull[c], &q = hull[least];
    const int cx = compare(p.x, p.i.x, q.x, q.i.x);
    if (cx < 0 || (cx == 0 && compare(p.y, p.i.y, q.y, q.i.y) < 0)) least = c;
  }
  std::rotate(hull.begin(), hull.begin() + static_cast<std::ptrdiff_t>(least), hull.end());
  return true;
}

void ExactReceiverJob::cast_face(std::size_t q) {
  const core::FacePrep& qp = (*ctx_.prep)[q];
  const Face& qface = ctx_.scene->faces[q];
  w_.vertex_sign.resize(qface.vertices.size());
  bool any_front = false;
  if (point_light_) {
    // A caster whose plane contains the light is edge-on to it and casts nothing; projecting
    // it would divide by zero where it touches the light.
    const bool edge_on =
        qp.exactly_planar
            ? CGAL::orientation(epick(qface.vertices[qp.corner[1]]), epick(qface.vertices[qp.corner[2]]),
                                epick(qface.vertices[qp.corner[0]]), epick(light_in_.position)) == CGAL::COPLANAR
            : CGAL::is_zero(plane_at_light(w_.face(ctx_, q), light_));
    if (edge_on) return;
  }
  // Two routes to the same exact polygons: exact leaves straight from the input doubles when
  // both faces are exactly planar (the common case), lazy Epeck values for lifted faces.
  const bool leaves = fp_.exactly_planar && qp.exactly_planar;
  const ExactFace* Q = nullptr;
  const ReceiverFrame* frame = nullptr;
  if (leaves) {
    for (std::size_t v = 0; v < qface.vertices.size(); ++v) {
      w_.vertex_sign[v] = input_side(qface.vertices[v]);
      any_front |= w_.vertex_sign[v] == CGAL::POSITIVE;
    }
  } else {
    Q = &w_.face(ctx_, q);
    frame = &exact_frame();
    for (std::size_t v = 0; v < Q->vertices.size(); ++v) {
      w_.vertex_sign[v] = CGAL::sign(frame->front(Q->vertices[v]));
      any_front |= w_.vertex_sign[v] == CGAL::POSITIVE;
    }
  }
  if (!any_front) return;  // nothing strictly in front of the receiver
  const bool wholly_in_front =
      leaves && qp.convex_pieces.size() >= kWholeFaceFromPieces &&
      std::all_of(w_.vertex_sign.begin(), w_.vertex_sign.end(), [](CGAL::Sign s) { return s == CGAL::POSITIVE; });
  if (wholly_in_front && point_light_ && cast_whole_outline_from_point(qp, qface)) return;
  if (wholly_in_front && !point_light_) {
    // A non-convex caster wholly in front under a directional light: its projection is an
    // affine image of the face, a simple polygon, so it can cast as one polygon instead of
    // one per convex piece (pieces share edges, which makes the union slow). Only when that
    // polygon lies inside the chart box: cutting it to the box afterwards (an intersection
    // of the union) cost more than the pieces on long combs.
    if (q_mode_) {
      ScaledChart& chart = scaled_chart();
      QPointList& pts = w_.qpoly;
      pts.clear();
      bool inside = true;
      for (int v : qp.chart_ring) {
        chart.project(qface.vertices[v], pts.emplace_back());
        const QPoint2& p = pts.back();
        for (int c = 0; c < 2 && inside; ++c) {
          const EQ& x = c == 0 ? p.x : p.y;
          const IA& ix = c == 0 ? p.i.x : p.i.y;
          inside = compare(x, ix, chart.lo(c), chart.ilo(c)) >= 0 && compare(x, ix, chart.hi(c), chart.ihi(c)) <= 0;
        }
        if (!inside) break;
      }
      if (inside) {
        if (add_shadow_q(pts)) {
          ++stats_.casting_pairs;
          q_outline_cast_ = true;  // not convex: no clip to a non-box chart's pieces
        }
        return;
      }
    } else {
      w_.poly2.clear();
      bool inside = true;
      for (int v : qp.chart_ring) {
        w_.poly2.push_back(leaf_projector().project(qface.vertices[v]));
        const Point2& p = w_.poly2.back();
        for (int c = 0; c < 2 && inside; ++c)
          inside = CGAL::compare(p[c], FT(fp_.chart_min[c])) != CGAL::SMALLER &&
                   CGAL::compare(p[c], FT(fp_.chart_max[c])) != CGAL::LARGER;
        if (!inside) break;
      }
      if (inside) {
        if (add_shadow(w_.poly2)) ++stats_.casting_pairs;
        return;
      }
    }
  }
  bool cast = false;
  for (const std::vector<int>& piece : qp.convex_pieces) {
    w_.piece_sign.clear();
    bool piece_front = false;
    for (int v : piece) {
      w_.piece_sign.push_back(w_.vertex_sign[v]);
      piece_front |= w_.vertex_sign[v] == CGAL::POSITIVE;
    }
    if (!piece_front) continue;
    if (q_mode_ && leaves) {
      scaled_chart().project_piece_parallel(qface.vertices, piece, w_.piece_sign, w_.qpoly);
      clip_to_chart_box_q(w_.qpoly);
      cast |= add_shadow_q(w_.qpoly);
      continue;
    }
    if (leaves)
      leaf_projector().project_piece(qface.vertices, piece, w_.piece_sign, w_.poly2);
    else
      project_piece_lazy(*Q, piece, *frame);
    if (!point_light_) clip_to_chart_box(w_.poly2);
    if (q_mode_) {  // a lifted caster: its exact values as rational points, scaled
      w_.qpoly.clear();
      const ScaledChart& chart = scaled_chart();
      for (const Point2& p : w_.poly2) {
        const auto& e = CGAL::exact(p);
        QPoint2& q = w_.qpoly.emplace_back();
        q.x = e.x();
        q.y = e.y();
        q.update_intervals();  // of the unscaled chart, as QPoint2{x, y} makes them
        chart.scale_point(q);
      }
      cast |= add_shadow_q(w_.qpoly);
      continue;
    }
    cast |= add_shadow(w_.poly2);
  }
  if (cast) ++stats_.casting_pairs;
}

bool ExactReceiverJob::cast_whole_outline_from_point(const core::FacePrep& qp, const Face& qface) {
  LeafProjector& projector = leaf_projector();
  w_.poly2.clear();
  bool inside = true;
  for (int v : qp.chart_ring) {
    if (!projector.project_central(qface.vertices[v], w_.poly2.emplace_back())) return false;
    const Point2& p = w_.poly2.back();
    for (int c = 0; c < 2 && inside; ++c)
      inside = CGAL::compare(p[c], FT(fp_.chart_min[c])) != CGAL::SMALLER &&
               CGAL::compare(p[c], FT(fp_.chart_max[c])) != CGAL::LARGER;
  }
  if (!inside) return cast_outline_cut_to_pyramid(qp, qface);
  if (add_shadow(w_.poly2)) ++stats_.casting_pairs;
  return true;
}

bool ExactReceiverJob::cast_outline_cut_to_pyramid(const core::FacePrep& qp, const Face& qface) {
  const int k = qp.axis, ci = core::chart_i(k), cj = core::chart_j(k);
  const std::vector<glm::dvec3>& vs = qface.vertices;
  // The caster's exact plane n . x + d = 0 from its convex corner; x_k = -(n_i u + n_j v + d) / n_k.
  const glm::dvec3& c = vs[qp.corner[1]];
  const glm::dvec3& next = vs[qp.corner[2]];
  const glm::dvec3& prev = vs[qp.corner[0]];
  mpq_class e[3], f[3], n[3];
  for (int a = 0; a < 3; ++a) {
    e[a] = mpq_class(next[a]) - mpq_class(c[a]);
    f[a] = mpq_class(prev[a]) - mpq_class(c[a]);
  }
  n[0] = e[1] * f[2] - e[2] * f[1];
  n[1] = e[2] * f[0] - e[0] * f[2];
  n[2] = e[0] * f[1] - e[1] * f[0];
  if (sgn(n[k]) == 0) return false;  // a chart that sees the plane edge-on (the pieces then)
  const mpq_class d = -(n[0] * c.x + n[1] * c.y + n[2] * c.z);
  // The pyramid's part of the caster's plane, in its chart: the outline's bounding box cut by
  // each side a . x + b >= 0 with x_k substituted (a line A u + B v + C >= 0).
  double lo[2] = {vs[qp.chart_ring[0]][ci], vs[qp.chart_ring[0]][cj]}, hi[2] = {lo[0], lo[1]};
  for (int v : qp.chart_ring) {
    lo[0] = std::min(lo[0], vs[v][ci]);
    hi[0] = std::max(hi[0], vs[v][ci]);
    lo[1] = std::min(lo[1], vs[v][cj]);
    hi[1] = std::max(hi[1], vs[v][cj]);
  }
  std::vector<std::array<mpq_class, 2>> window{{mpq_class(lo[0]), mpq_class(lo[1])}, {mpq_class(hi[0]), mpq_class(lo[1])},
                                               {mpq_class(hi[0]), mpq_class(hi[1])}, {mpq_class(lo[0]), mpq_class(hi[1])}};
  std::vector<std::array<mpq_class, 2>> cut;
  std::vector<mpq_class> value;
  for (const LeafProjector::Side& side : leaf_projector().pyramid_sides()) {
    const mpq_class A = side.a[ci] - side.a[k] * n[ci] / n[k];
    const mpq_class B = side.a[cj] - side.a[k] * n[cj] / n[k];
    const mpq_class C = side.b - side.a[k] * d / n[k];
    value.resize(window.size());
    for (std::size_t a = 0; a < window.size(); ++a) value[a] = A * window[a][0] + B * window[a][1] + C;
    auto side_of = [&](std::size_t a) { return sgn(value[a]); };
    switch (geometry::clip_case(window.size(), side_of)) {
      case geometry::ClipCase::Inside: continue;
      case geometry::ClipCase::Empty: return true;  // nothing of the caster in the pyramid
      case geometry::ClipCase::Cut: break;
    }
    geometry::clip_convex(window, side_of, [&](std::size_t a, std::size_t b) {
      const mpq_class t = value[a] / (value[a] - value[b]);
      return std::array<mpq_class, 2>{window[a][0] + t * (window[b][0] - window[a][0]),
                                      window[a][1] + t * (window[b][1] - window[a][1])};
    }, cut);
    window.swap(cut);
    if (window.size() < 3) return true;
  }
  Polygon2 clip;
  for (const auto& p : window) clip.push_back(Point2(FT(p[0]), FT(p[1])));
  if (CGAL::sign(polygon_area(clip)) == CGAL::ZERO) return true;  // the pyramid only grazes it
  if (clip.orientation() == CGAL::CLOCKWISE) clip.reverse_orientation();
  Polygon2 outline;
  for (int v : qp.chart_ring) outline.push_back(Point2(vs[v][ci], vs[v][cj]));
  if (outline.orientation() == CGAL::CLOCKWISE) outline.reverse_orientation();
  PolygonSet2 parts(outline);
  parts.intersection(clip);
  std::vector<PolygonWithHoles2> inside;
  parts.polygons_with_holes(std::back_inserter(inside));
  LeafProjector& projector = leaf_projector();
  bool cast = false;
  mpq_class y[3];
  for (const PolygonWithHoles2& part : inside) {
    w_.poly2.clear();
    for (auto v = part.outer_boundary().vertices_begin(); v != part.outer_boundary().vertices_end(); ++v) {
      const auto& exact = CGAL::exact(*v);
      y[ci] = exact.x();
      y[cj] = exact.y();
      y[k] = -(n[ci] * y[ci] + n[cj] * y[cj] + d) / n[k];
      w_.poly2.push_back(projector.project_central(y));
    }
    cast |= add_shadow(w_.poly2);
  }
  if (cast) ++stats_.casting_pairs;
  return true;
}

void ExactReceiverJob::project_piece_lazy(const ExactFace& Q, const std::vector<int>& piece, const ReceiverFrame& frame) {
  w_.poly.clear();
  for (int v : piece) w_.poly.push_back(Q.vertices[v]);
  if (point_light_) {
    // The pyramid over the chart box keeps the central projection finite.
    clip_front(w_.poly, w_.piece_sign, frame.front, w_.scratch);
    for (const Affine3& side : frame.sides) clip_convex(w_.poly, side, w_.scratch);
    w_.poly2.clear();
    for (const Point3& y : w_.poly) w_.poly2.push_back(project_to_chart(y, frame, light_));
  } else {
    project_front_part(w_.poly, w_.piece_sign, frame, light_, w_.poly2);
  }
}

bool ExactReceiverJob::add_shadow(const std::vector<Point2>& poly) {
  if (poly.size() < 3) return false;
  Polygon2 projected(poly.begin(), poly.end());
  const CGAL::Sign orientation = CGAL::sign(polygon_area(projected));
  if (orientation == CGAL::ZERO) return false;  // the caster is edge-on to the light
  if (orientation == CGAL::NEGATIVE) projected.reverse_orientation();
  note_cover(projected);
  shadows_.push_back(std::move(projected));
  return true;
}

void ExactReceiverJob::note_cover(const Polygon2& shadow) {
  if (polygons_ || !fp_.chart_is_box || tile_ || covered_) return;
  const double twice = core::twice_area_about_box_corner(fp_, shadow.size(), [&](std::size_t a) {
    const auto& p = shadow.vertex(a);
    return std::array<double, 2>{CGAL::to_double(p.x()), CGAL::to_double(p.y())};
  });
  if (!near_box_area(twice) || !shadow.is_convex()) return;
  covered_ = polygon_area(shadow) == w_.face(ctx_, face_id_).chart_area;
}

bool ExactReceiverJob::add_shadow_q(QPointList& poly) {
  if (poly.size() < 3) return false;
  const CGAL::Sign orientation = area_sign(poly, w_.qs, w_.qarea);
  if (orientation == CGAL::ZERO) return false;  // the caster is edge-on to the light
  if (orientation == CGAL::NEGATIVE) std::reverse(poly.begin(), poly.end());
  note_cover_q(poly);
  for (QPoint2& p : poly) w_.qshadows.push_back_swap(p);  // poly is scratch from here on
  w_.qfirst.push_back(w_.qshadows.size());
  return true;
}

void ExactReceiverJob::note_cover_q(const QPointList& poly) {
  // (A tile's shadow is its own: never the face's.)
  if (tile_ || covered_ || poly.size() < 3) return;
  note_cover_of_chart_q(poly);
}

void ExactReceiverJob::note_cover_of_chart_q(const QPointList& poly) {
  // A convex cast (counter-clockwise) that holds every vertex of the chart holds the chart (its
  // convex hull): the shadow is the whole face, as for a box. Only a cast whose box holds the
  // chart's box can (decided on the intervals first); the chart's corners in the scaled chart
  // are made once per job.
  double x0 = poly[0].i.x.inf(), x1 = poly[0].i.x.sup(), y0 = poly[0].i.y.inf(), y1 = poly[0].i.y.sup();
  for (const QPoint2& p : poly) {
    x0 = std::min(x0, p.i.x.inf());
    x1 = std::max(x1, p.i.x.sup());
    y0 = std::min(y0, p.i.y.inf());
    y1 = std::max(y1, p.i.y.sup());
  }
  if (x0 > fp_.chart_min[0] || x1 < fp_.chart_max[0] || y0 > fp_.chart_min[1] || y1 < fp_.chart_max[1]) return;
  if (!chart_corners_ready_) {
    w_.qcorners.clear();
    for (int v : fp_.chart_ring) scaled_chart().chart(face_.vertices[v], w_.qcorners.emplace_back());
    chart_corners_ready_ = true;
  }
  CGAL::Protect_FPU_rounding<true> guard;
  for (std::size_t a = 0; a < poly.size(); ++a) {
    const QPoint2& p = poly[a];
    const QPoint2& q = poly[a + 1 == poly.size() ? 0 : a + 1];
    for (std::size_t c = 0; c < w_.qcorners.size(); ++c) {
      const QPoint2& r = w_.qcorners[c];
      if (orientation<false>(p, p.i, q, q.i, r, r.i, w_.qs) == CGAL::NEGATIVE) return;
    }
  }
  covered_ = true;
}

}  // namespace shadow::exact::receiver_job
