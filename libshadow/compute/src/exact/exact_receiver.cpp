// SPDX-License-Identifier: GPL-3.0-or-later
// The exact per-receiver computation (Atherton-Weiler-Greenberg, made exact): for a receiving
// face P that faces the light,
//
//   shadow(P) = P  intersected with  union over Q of  project_P(Q  clipped to the slab between
//               P's plane and the light),
//
// in exact rationals in P's 2D chart (see engine/shadow_engine.cpp). Named steps: gather casters,
// cast a convex solid, cast a face (leaf or lazy route), clip to the chart box, unite, areas,
// emit fragments.
#include "exact/exact_receiver.hpp"

#include "exact/leaf_projector.hpp"
#include "exact/regions.hpp"
#include "exact/scaled_chart.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <optional>
#include <utility>

namespace shadow::exact {
namespace {

using EK = CGAL::Exact_predicates_inexact_constructions_kernel;

EK::Point_3 epick(const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); }

/// The face's own outline as one fragment (wholly lit or wholly in shadow).
Fragment whole_face_fragment(const Face& face, std::size_t face_id, std::size_t light_id, bool lit,
                             double area, const core::FacePrep& prep, const ExactFace* ef) {
  Fragment fragment;
  fragment.face_id = face_id;
  fragment.light_id = light_id;
  fragment.lit = lit;
  fragment.area = area;
  if (prep.exactly_planar || ef == nullptr) {
    fragment.polygon = face.vertices;
  } else {
    for (const Point3& p : ef->vertices) fragment.polygon.push_back(nearest_doubles(p));
  }
  return fragment;
}

/// A non-convex caster of at least this many convex pieces, wholly in front of the receiver
/// under a directional light and casting inside its chart box, casts its whole outline as one
/// polygon (see cast_face).
constexpr std::size_t kWholeFaceFromPieces = 16;

class ExactReceiverJob {
 public:
  ExactReceiverJob(const ExactContext& ctx, ExactWorker& w, std::size_t face_id, std::size_t light_id,
                   const ExactLight& light, const Light& light_in, const core::LightSpaceGrid* grid, bool polygons,
                   ShadowStats& stats, const core::TileRequest& tiles = {})
      : ctx_(ctx), w_(w), face_id_(face_id), light_id_(light_id), light_(light), light_in_(light_in),
        grid_(grid), polygons_(polygons), emit_(polygons), stats_(stats), face_(ctx.scene->faces[face_id]),
        fp_(tiles.tile ? *tiles.tile : (*ctx.prep)[face_id]), point_light_(light.is_point()),
        tile_(tiles.tile != nullptr), split_above_(tiles.tile ? 0 : tiles.split_above) {}

  ReceiverResult run(int facing) {
    FaceLighting& out = item_.lighting;
    out.face_id = face_id_;
    out.light_id = light_id_;
    out.area = (*ctx_.face_area)[face_id_];
    item_.tile_exact = tile_;
    ++stats_.receivers;
    if (fp_.degenerate) return std::move(item_);  // zero area: nothing to light

    if (facing <= 0) {  // attached shadow: the front looks away from the light (or edge-on)
      ++stats_.back_facing;
      out.shadow_area = out.area;
      if (emit_) emit_whole_face(false);
      return std::move(item_);
    }
    out.faces_light = true;
    // Areas only, a box chart, a directional light, an exactly planar receiver: the casts are kept
    // as plain rational points in the receiver's scaled chart (integers where they can be:
    // exact/scaled_chart.hpp) and united by their boundaries (no Epeck number, no arrangement).
    q_mode_ = !polygons_ && fp_.chart_is_box && !point_light_ && fp_.exactly_planar;
    if (q_mode_) {
      w_.qshadows.clear();
      w_.qfirst.assign(1, 0);
    }

    if (split_above_ > 0 && grid_ && core::tileable(fp_)) {
      // A directional light: decided from the light-space grid's count (an upper bound on the
      // candidates, without culling each of them: for a ground, culling is most of an item).
      const std::size_t potential = grid_->count(face_id_);
      if (potential > split_above_) {
        --stats_.receivers;
        item_.split_candidates = potential;
        return std::move(item_);
      }
    }
    const std::vector<std::size_t>& candidates = gather_casters();
    if (split_above_ > 0 && !grid_ && candidates.size() > split_above_ && core::tileable(fp_)) {
      // Too many casters for one work item: the engine splits the face into tiles (and counts
      // it then), nothing else is done here.
      --stats_.receivers;
      stats_.candidate_pairs -= candidates.size();
      item_.split_candidates = candidates.size();
      return std::move(item_);
    }
    corner0_ = epick(face_.vertices[fp_.corner[1]]);
    corner1_ = epick(face_.vertices[fp_.corner[2]]);
    corner2_ = epick(face_.vertices[fp_.corner[0]]);
    const int own_solid = (*ctx_.solid_of)[face_id_];
    for (std::size_t q : candidates) {
      const int solid = (*ctx_.solid_of)[q];
      if (solid >= 0 && (solid == own_solid || w_.casters.solid_done(solid))) continue;
      if (solid >= 0 && !point_light_ && fp_.exactly_planar) {
        cast_convex_solid(solid);
      } else {
        cast_face(q);
      }
      if (covered_) break;  // one shadow fills the whole box: no other caster can add to it
    }

    if (shadow_count() == 0) {  // nothing in front: wholly lit, no Boolean operation needed
      ++stats_.unshadowed;
      out.lit_area = out.area;
      out.lit_fraction = 1.0;
      item_.tile_unshadowed = tile_;
      if (emit_) emit_whole_face(true);
      return std::move(item_);
    }
    // The receiver's lazy exact face only where a step needs it (the areas come from plain
    // integers for an exactly planar face: ExactWorker::exact_areas).
    unite_and_measure();
    if (emit_) emit_fragments(w_.face(ctx_, face_id_));
    return std::move(item_);
  }

  /// run()'s steps up to the union, for the sun-hours map: the lit region itself. Constructed
  /// with polygons = true, so that the shadow's union is kept as a set.
  LitRegion lit_region(int facing) {
    LitRegion region;
    emit_ = false;
    const ReceiverResult r = run(facing);
    region.lighting = r.lighting;
    if (!r.lighting.faces_light || fp_.degenerate) return region;  // attached shadow: dark
    const ExactFace& P = w_.face(ctx_, face_id_);
    if (!shadow_set_storage_) {  // nothing in front
      region.kind = LitRegion::Kind::Whole;
      region.lit_chart_area = P.chart_area;
      return region;
    }
    region.lit_chart_area = lit_chart_area_;
    region.lit = PolygonSet2(P.chart);
    region.lit.difference(*shadow_set_storage_);
    region.kind = region.lit.is_empty() ? LitRegion::Kind::Dark : LitRegion::Kind::Partial;
    return region;
  }

 private:
  // ---- culling in doubles -------------------------------------------------------------------
  const std::vector<std::size_t>& gather_casters() {
    const core::ReceiverCuller culler(*ctx_.cull, fp_, face_id_, light_in_);
    const std::vector<std::size_t>& candidates =
        w_.casters.gather(culler, *ctx_.prep, face_id_, grid_, tile_ ? ctx_.cull : nullptr, tile_ ? &fp_ : nullptr,
                          ctx_.solid_of);
    stats_.candidate_pairs += candidates.size();
    return candidates;
  }

  /// The receiver's exact frame, built on first use: most receivers are decided by the
  /// predicates alone (nothing strictly in front of them).
  const ReceiverFrame& exact_frame() {
    if (!frame_) {
      const ExactFace& receiver = w_.face(ctx_, face_id_);
      frame_ = make_frame(receiver, fp_, light_, plane_at_light(receiver, light_));
    }
    return *frame_;
  }

  LeafProjector& leaf_projector() {
    if (!projector_) projector_.emplace(face_.vertices, fp_, light_in_);
    return *projector_;
  }

  /// The areas-only route's chart, scaled so that projections are integers (q_mode_ only).
  ScaledChart& scaled_chart() {
    if (!scaled_chart_) scaled_chart_.emplace(face_.vertices, fp_, light_in_, ctx_.chart_least_bit);
    return *scaled_chart_;
  }

  /// Sign of s (the receiver's plane) at an input vertex, by Epick's orientation predicate on
  /// the doubles: exact, and cheap even when the answer is zero, which is common (faces that
  /// share an edge with the receiver). Lazy Epeck arithmetic would evaluate every zero exactly.
  /// Exactly planar receivers only.
  CGAL::Sign input_side(const glm::dvec3& v) const {
    CGAL::Sign sv = CGAL::orientation(corner0_, corner1_, corner2_, epick(v));
    if (fp_.flipped) sv = CGAL::opposite(sv);
    return sv;
  }

  /// Parallel projection is affine: a directional light's casts are clipped to the chart box in
  /// 2D (a point light's are clipped to the pyramid over it before the projection).
  void clip_to_chart_box(std::vector<Point2>& poly) {
    for (int c = 0; c < 2; ++c) {
      clip_convex_2d(poly, c, fp_.chart_min[c], true, w_.scratch2);
      clip_convex_2d(poly, c, fp_.chart_max[c], false, w_.scratch2);
    }
  }

  /// clip_to_chart_box for a cast in the scaled chart (the box's bounds scaled with it).
  void clip_to_chart_box_q(std::vector<QPoint2>& poly) {
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

  // ---- a convex solid casts the hull of its projection (see core::ConvexSolid) --------------------
  void cast_convex_solid(int solid) {
    w_.casters.mark_solid_done(solid);
    const core::ConvexSolid& cs = (*ctx_.solids)[solid];
    w_.vertex_sign.resize(cs.vertices.size());
    bool any_front = false;
    for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
      w_.vertex_sign[v] = input_side(cs.vertices[v]);
      any_front |= w_.vertex_sign[v] == CGAL::POSITIVE;
    }
    if (!any_front) return;
    if (q_mode_) {
      ScaledChart& projector = scaled_chart();
      std::vector<QPoint2>& pts = w_.qpoly;
      pts.clear();
      for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
        if (w_.vertex_sign[v] == CGAL::POSITIVE) projector.project(cs.vertices[v], pts.emplace_back());
        if (w_.vertex_sign[v] == CGAL::ZERO) projector.chart(cs.vertices[v], pts.emplace_back());
      }
      for (const auto& [a, b] : cs.edges) {
        const CGAL::Sign sa = w_.vertex_sign[a], sb = w_.vertex_sign[b];
        if ((sa == CGAL::POSITIVE && sb == CGAL::NEGATIVE) || (sa == CGAL::NEGATIVE && sb == CGAL::POSITIVE))
          projector.crossing(cs.vertices[a], cs.vertices[b], pts.emplace_back());
      }
      convex_hull(pts, w_.qscratch, w_.qorder, w_.qchain, w_.qs);
      pts.swap(w_.qscratch);
      clip_to_chart_box_q(pts);
      if (pts.size() < 3) return;
      if (area_sign(pts, w_.qs, w_.qarea) != CGAL::POSITIVE) return;  // flat: edge-on solid
      w_.qshadows.insert(w_.qshadows.end(), pts.begin(), pts.end());
      w_.qfirst.push_back(w_.qshadows.size());
      ++stats_.casting_pairs;
      note_cover_q(pts);
      return;
    }
    LeafProjector& projector = leaf_projector();
    w_.poly2.clear();
    for (std::size_t v = 0; v < cs.vertices.size(); ++v) {
      if (w_.vertex_sign[v] == CGAL::POSITIVE) w_.poly2.push_back(projector.project(cs.vertices[v]));
      if (w_.vertex_sign[v] == CGAL::ZERO) w_.poly2.push_back(projector.chart(cs.vertices[v]));
    }
    for (const auto& [a, b] : cs.edges) {
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

  // ---- a caster face, convex piece by convex piece ------------------------------------------
  void cast_face(std::size_t q) {
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
        std::vector<QPoint2>& pts = w_.qpoly;
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
          if (add_shadow_q(pts)) ++stats_.casting_pairs;
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
          chart.scale_point(w_.qpoly.emplace_back(QPoint2{e.x(), e.y()}));
        }
        cast |= add_shadow_q(w_.qpoly);
        continue;
      }
      cast |= add_shadow(w_.poly2);
    }
    if (cast) ++stats_.casting_pairs;
  }

  /// A point light's counterpart of the whole-outline cast above: a non-convex caster (exactly
  /// planar, every vertex strictly in front of the receiver) whose every vertex also lies
  /// strictly nearer the receiver's plane than the light, and projects inside the chart box,
  /// casts its outline as one polygon. Then the face lies in the pyramid over the box (a convex
  /// set holding its vertices), where no piece is clipped, and the central projection is a
  /// projective map of the caster's plane defined on all of it: the image of its simple
  /// outline is a simple polygon, the union of its pieces' images, vertex for vertex the same
  /// exact points (LeafProjector::project_central is project_piece's formula). Cast piece by
  /// piece, the pieces' shared edges made the union the cost (a 40,002-vertex comb under a
  /// lamp: docs/benchmarks.md). False, having cast nothing, when the conditions do not hold.
  bool cast_whole_outline_from_point(const core::FacePrep& qp, const Face& qface) {
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

  /// cast_whole_outline_from_point's caster when its shadow leaves the chart box: the outline is
  /// cut to the pyramid over the box in the caster's own chart (its input doubles, and the
  /// pyramid's sides as lines there), and each part of it cast whole. A simple polygon cut by
  /// a convex region is a set of simple polygons without holes (the complements of both are
  /// connected), whose images are simple, inside the box, and together the union of the
  /// clipped pieces' images: the same exact region. True when the caster is handled; false,
  /// casting nothing, when its corner's normal has no component along its chart's axis.
  bool cast_outline_cut_to_pyramid(const core::FacePrep& qp, const Face& qface) {
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

  /// The lazy route (a lifted receiver or caster): the piece's front part, clipped to the
  /// pyramid for a point light, projected into w_.poly2.
  void project_piece_lazy(const ExactFace& Q, const std::vector<int>& piece, const ReceiverFrame& frame) {
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

  /// A projected piece as a counter-clockwise shadow polygon; false when it has no area (the
  /// caster is edge-on to the light, or clipped away).
  bool add_shadow(const std::vector<Point2>& poly) {
    if (poly.size() < 3) return false;
    Polygon2 projected(poly.begin(), poly.end());
    const CGAL::Sign orientation = CGAL::sign(polygon_area(projected));
    if (orientation == CGAL::ZERO) return false;  // the caster is edge-on to the light
    if (orientation == CGAL::NEGATIVE) projected.reverse_orientation();
    note_cover(projected);
    shadows_.push_back(std::move(projected));
    return true;
  }

  /// Areas only, a box receiver (not a tile): a convex shadow inside the chart box (every cast
  /// is clipped to it) whose area is the box's is the box, and the union is the box whatever
  /// else casts (under a low sun many walls are wholly in shadow). Doubles first, so that only
  /// a near match costs an exact comparison.
  void note_cover(const Polygon2& shadow) {
    if (polygons_ || !fp_.chart_is_box || tile_ || covered_) return;
    const double twice = core::twice_area_about_box_corner(fp_, shadow.size(), [&](std::size_t a) {
      const auto& p = shadow.vertex(a);
      return std::array<double, 2>{CGAL::to_double(p.x()), CGAL::to_double(p.y())};
    });
    if (!near_box_area(twice) || !shadow.is_convex()) return;
    covered_ = polygon_area(shadow) == w_.face(ctx_, face_id_).chart_area;
  }

  /// add_shadow for rational points (the areas-only route).
  bool add_shadow_q(std::vector<QPoint2>& poly) {
    if (poly.size() < 3) return false;
    const CGAL::Sign orientation = area_sign(poly, w_.qs, w_.qarea);
    if (orientation == CGAL::ZERO) return false;  // the caster is edge-on to the light
    if (orientation == CGAL::NEGATIVE) std::reverse(poly.begin(), poly.end());
    w_.qshadows.insert(w_.qshadows.end(), poly.begin(), poly.end());
    w_.qfirst.push_back(w_.qshadows.size());
    note_cover_q(poly);
    return true;
  }

  /// note_cover for a rational cast (counter-clockwise, in the scaled chart). Every cast is a
  /// simple polygon inside the chart box (a convex piece or hull clipped to it, or a face's
  /// affine image lying in it), and a simple polygon inside the box with the box's area is the box.
  void note_cover_q(const std::vector<QPoint2>& poly) {
    if (tile_ || covered_ || poly.size() < 3) return;
    const ScaledChart& chart = scaled_chart();
    const double x0 = chart.lo(0).get_d(), y0 = chart.lo(1).get_d();  // the scaled box's corner
    const double twice = core::twice_area_about({x0, y0}, poly.size(), [&](std::size_t a) {
      return std::array<double, 2>{poly[a].x.get_d(), poly[a].y.get_d()};
    });
    if (!near_box_area(twice, (chart.hi(0).get_d() - x0) * (chart.hi(1).get_d() - y0))) return;
    EQ exact_twice;
    twice_polygon_area(poly.data(), poly.data() + poly.size(), exact_twice, w_.qs);
    const EQ exact_box = (chart.hi(0) - chart.lo(0)) * (chart.hi(1) - chart.lo(1));
    covered_ = exact_twice == 2 * exact_box;
  }

  /// Whether twice a cast's area in doubles (about the box's corner) is within a relative 1e-9
  /// of twice the chart box's: only such a cast can be the whole box (note_cover, note_cover_q).
  bool near_box_area(double twice) const { return near_box_area(twice, core::chart_box_area(fp_)); }
  static bool near_box_area(double twice, double box) { return std::abs(0.5 * twice - box) <= 1e-9 * box; }

  std::size_t shadow_count() const { return q_mode_ ? w_.qfirst.size() - 1 : shadows_.size(); }

  // ---- unite, areas -------------------------------------------------------------------------
  void unite_and_measure() {
    if (covered_) {  // the box itself (note_cover): the same exact values as its union would give
      twice_area_ = *w_.exact_areas(ctx_, face_id_).first;  // (the chart's area, not twice)
      measure(twice_area_);
      return;
    }
    if (q_mode_) {
      // Areas of the scaled chart (scaled_chart()), divided by K^2 before measuring.
      const ScaledChart& chart = scaled_chart();
      if (w_.qfirst.size() == 2) {  // one cast (simple) inside the box: it is the shadow
        twice_polygon_area(w_.qshadows.data(), w_.qshadows.data() + w_.qshadows.size(), twice_area_, w_.qs);
        twice_area_ /= 2;
        chart.unscale_area(twice_area_);
        measure(twice_area_);
        return;
      }
      if (w_.union_area.twice_area(w_.qshadows, w_.qfirst, twice_area_)) {
        twice_area_ /= 2;
        chart.unscale_area(twice_area_);
        measure(twice_area_);
        return;
      }
      // A non-convex cast: the Boolean union of all of them, as Epeck polygons (of the chart).
      for (std::size_t k = 0; k + 1 < w_.qfirst.size(); ++k) {
        Polygon2 polygon;
        for (std::size_t v = w_.qfirst[k]; v < w_.qfirst[k + 1]; ++v)
          polygon.push_back(Point2(FT(w_.qshadows[v].x / chart.scale()), FT(w_.qshadows[v].y / chart.scale())));
        shadows_.push_back(std::move(polygon));
      }
    } else if (!polygons_ && fp_.chart_is_box && shadows_.size() > 1) {
      // Areas only, casts already inside the chart box: the union's area from the casts'
      // boundaries (exact/convex_union_area.hpp), the same exact rational as the join's regions
      // give, without an arrangement. Not for a non-convex cast (the whole-face route of
      // cast_face): the join then.
      if (w_.union_area.twice_area(shadows_, twice_area_)) {
        twice_area_ /= 2;
        measure(twice_area_);
        return;
      }
    }
    shadow_set_storage_.emplace();  // only here: an empty Polygon_set_2 still allocates
    PolygonSet2& shadow_set_ = *shadow_set_storage_;
    if (shadows_.size() == 1 && fp_.chart_is_box) {
      // One convex caster already clipped to a rectangular receiver: it is the shadow.
      shadow_regions_.emplace_back(shadows_.front());
      if (polygons_) shadow_set_.insert(shadows_.front());
    } else {
      shadow_set_.join(shadows_.begin(), shadows_.end());  // one aggregated union
      if (!fp_.chart_is_box) shadow_set_.intersection(w_.face(ctx_, face_id_).chart);
      shadow_set_.polygons_with_holes(std::back_inserter(shadow_regions_));
    }
    std::vector<FT> region_areas;
    for (const PolygonWithHoles2& r : shadow_regions_) region_areas.push_back(region_area(r));
    measure(balanced_sum(region_areas));
  }

  /// The areas from the shadow's exact area in the chart, in plain rationals (the same values
  /// as area_3d and round_to_double give through lazy numbers, without building their DAGs).
  void measure(const FT& shadow_chart_area) { measure(CGAL::exact(shadow_chart_area)); }
  void measure(const EQ& shadow) {
    if (tile_) item_.tile_shadow_chart_area = shadow;
    const auto [chart, scale] = w_.exact_areas(ctx_, face_id_);
    measure_lit_and_shadow(*chart, *scale, shadow, w_.qarea, w_.qbound, item_.lighting);
    if (polygons_) lit_chart_area_ = FT(w_.qarea);  // lit_region's
  }

  // ---- fragments ----------------------------------------------------------------------------
  /// The face's outline as one fragment (wholly lit or wholly in shadow). A sliver face whose
  /// outline in doubles is not a simple polygon of certainly non-zero area goes through emit()
  /// like any other region: triangles, and dropped_area for those that collapse.
  void emit_whole_face(bool lit) {
    if (tile_) {  // the tile's part of the face, cut into cells like any region
      const ExactFace& P = w_.face(ctx_, face_id_);
      std::vector<PolygonWithHoles2> regions;
      if (fp_.chart_is_box)
        regions.emplace_back(tile_polygon());
      else
        tile_region(P).polygons_with_holes(std::back_inserter(regions));
      emit(P, regions, lit);
      if (!dropped_.empty()) item_.lighting.dropped_area = area_3d(balanced_sum(dropped_), P.area_scale_squared);
      return;
    }
    const ExactFace* ef = fp_.exactly_planar ? nullptr : &w_.face(ctx_, face_id_);
    Fragment fragment = whole_face_fragment(face_, face_id_, light_id_, lit, item_.lighting.area, fp_, ef);
    if (core::clean_double_polygon(fragment.polygon, fp_.axis)) {
      item_.fragments.push_back(std::move(fragment));
      return;
    }
    const ExactFace& P = w_.face(ctx_, face_id_);
    emit(P, {PolygonWithHoles2(P.chart)}, lit);
    if (!dropped_.empty()) item_.lighting.dropped_area = area_3d(balanced_sum(dropped_), P.area_scale_squared);
  }

  /// A tile's chart box as a counter-clockwise polygon (its corners are exact doubles).
  Polygon2 tile_polygon() const {
    const FT x0(fp_.chart_min[0]), y0(fp_.chart_min[1]), x1(fp_.chart_max[0]), y1(fp_.chart_max[1]);
    const Point2 corners[4] = {Point2(x0, y0), Point2(x1, y0), Point2(x1, y1), Point2(x0, y1)};
    return Polygon2(corners, corners + 4);
  }

  /// A tile's part of the face: its box, intersected with the face's outline unless the box
  /// lies in the face (chart_is_box: a box face's tiles, and the inner cells of other faces).
  PolygonSet2 tile_region(const ExactFace& P) const {
    PolygonSet2 region(tile_polygon());
    if (!fp_.chart_is_box) region.intersection(P.chart);
    return region;
  }

  void emit_fragments(const ExactFace& P) {
    std::vector<PolygonWithHoles2> lit_regions;
    // A tile's lit part is its part of the face minus the shadow.
    PolygonSet2 lit_set = tile_ ? tile_region(P) : PolygonSet2(P.chart);
    lit_set.difference(*shadow_set_storage_);
    lit_set.polygons_with_holes(std::back_inserter(lit_regions));
    emit(P, lit_regions, true);
    emit(P, shadow_regions_, false);
    if (!dropped_.empty()) item_.lighting.dropped_area = area_3d(balanced_sum(dropped_), P.area_scale_squared);
  }

  /// One cell as a fragment, if its vertices rounded to doubles still make one simple polygon
  /// of non-zero area (the output contract); false, writing nothing, otherwise.
  bool write(const ExactFace& P, const Polygon2& cell, const FT& cell_area, bool lit) {
    Fragment fragment;
    fragment.face_id = face_id_;
    fragment.light_id = light_id_;
    fragment.fragment_id = fragment_id_;
    fragment.lit = lit;
    fragment.area = area_3d(CGAL::abs(cell_area), P.area_scale_squared);
    for (auto v = cell.vertices_begin(); v != cell.vertices_end(); ++v) {
      fragment.polygon.push_back(nearest_doubles(lift(*v, P, fp_.axis)));
    }
    // The chart sees the face clockwise when flipped: restore the face's orientation.
    if (fp_.flipped == CGAL::is_positive(cell_area)) std::reverse(fragment.polygon.begin(), fragment.polygon.end());
    if (!core::clean_double_polygon(fragment.polygon, fp_.axis)) return false;
    item_.fragments.push_back(std::move(fragment));
    return true;
  }

  void emit(const ExactFace& P, const std::vector<PolygonWithHoles2>& regions, bool lit) {
    for (const PolygonWithHoles2& region : regions) {
      cells_.clear();
      append_simple_cells(region, cells_);
      const std::size_t written = item_.fragments.size();
      for (Polygon2& cell : cells_) {
        const FT cell_area = polygon_area(cell);
        if (write(P, cell, cell_area, lit)) continue;
        // Rounding broke the cell (a sliver a few ulps wide, or a spike that now crosses an
        // edge): write its triangles instead, and leave out those that collapse, accounting
        // for their exact area in dropped_area.
        if (CGAL::is_negative(cell_area)) cell.reverse_orientation();
        triangles_.clear();
        triangulate_region(PolygonWithHoles2(cell), triangles_);
        for (const Polygon2& t : triangles_) {
          const FT t_area = polygon_area(t);
          if (!write(P, t, t_area, lit)) {
            dropped_.push_back(CGAL::abs(t_area));
            ++stats_.dropped_cells;
          }
        }
      }
      if (item_.fragments.size() > written) ++fragment_id_;  // ids stay consecutive
    }
  }

  const ExactContext& ctx_;
  ExactWorker& w_;
  std::size_t face_id_, light_id_;
  const ExactLight& light_;
  const Light& light_in_;
  const core::LightSpaceGrid* grid_;
  bool polygons_;     ///< keep the shadow's union as a set (fragments or the lit region need it)
  bool emit_;         ///< write fragments (compute_exact_receiver with polygons)
  ShadowStats& stats_;
  const Face& face_;
  const core::FacePrep& fp_;
  const bool point_light_;
  const bool tile_;                 ///< computing one tile of the face (fp_ is the tile's)
  const std::size_t split_above_;   ///< ask for tiles above this many candidates (0: never)
  EK::Point_3 corner0_, corner1_, corner2_;  ///< the receiver's corner, for input_side
  std::optional<ReceiverFrame> frame_;
  std::optional<LeafProjector> projector_;
  std::optional<ScaledChart> scaled_chart_;  ///< q_mode_ only
  ReceiverResult item_;
  std::vector<Polygon2> shadows_;
  bool covered_ = false;  ///< a shadow fills the whole chart box (areas only; note_cover)
  std::vector<PolygonWithHoles2> shadow_regions_;
  std::optional<PolygonSet2> shadow_set_storage_;  ///< the shadow's union (unite_and_measure)
  ConvexUnionArea::EQ twice_area_;                 ///< scratch for the union's area (areas only)
  bool q_mode_ = false;                            ///< casts as rational points (see run())
  FT lit_chart_area_{0};                            ///< its complement's exact area (unite_and_measure)
  std::size_t fragment_id_ = 0;
  std::vector<Polygon2> cells_, triangles_;
  std::vector<FT> dropped_;  ///< exact chart areas of cells too thin to write
};

}  // namespace

ReceiverResult compute_exact_receiver(const ExactContext& ctx, ExactWorker& w, std::size_t face_id,
                                      std::size_t light_id, const ExactLight& light, int facing,
                                      const Light& light_in, const core::LightSpaceGrid* grid, bool polygons,
                                      ShadowStats& stats, const core::TileRequest& tiles) {
  return ExactReceiverJob(ctx, w, face_id, light_id, light, light_in, grid, polygons, stats, tiles).run(facing);
}

LitRegion exact_lit_region(const ExactContext& ctx, ExactWorker& w, std::size_t face_id, std::size_t light_id,
                           const ExactLight& light, int facing, const Light& light_in,
                           const core::LightSpaceGrid* grid, ShadowStats& stats) {
  return ExactReceiverJob(ctx, w, face_id, light_id, light, light_in, grid, true, stats).lit_region(facing);
}

}  // namespace shadow::exact
