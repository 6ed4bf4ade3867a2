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
#include "exact/exact_receiver_job.hpp"

#include "exact/regions.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <iterator>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>

namespace shadow::exact {
namespace receiver_job {
namespace {

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

/// Canonical segments as Epeck segments, each distinct point made once and shared by the
/// segments that end at it (the sun-hours map holds every instant's boundaries: a point per
/// segment end cost it a tenth more memory), its coordinates divided by `scale` when given.
void to_boundary_segments(const std::vector<BoundaryChain::Segment>& in, const EQ* scale,
                          std::vector<BoundarySegment>& out) {
  const std::size_t n = 2 * in.size();
  const auto end = [&](std::size_t k) -> const BoundaryChain::Point& {
    return k % 2 == 0 ? in[k / 2].from : in[k / 2].to;
  };
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto cmp = BoundaryChain::compare;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const int x = cmp(end(a).x, end(b).x);
    if (x != 0) return x < 0;
    const int y = cmp(end(a).y, end(b).y);
    return y != 0 ? y < 0 : a < b;
  });
  std::vector<Point2> points(n);
  for (std::size_t k = 0; k < n; ++k) {
    const BoundaryChain::Point& p = end(order[k]);
    if (k > 0 && cmp(p.x, end(order[k - 1]).x) == 0 && cmp(p.y, end(order[k - 1]).y) == 0) {
      points[order[k]] = points[order[k - 1]];
    } else if (scale) {  // (a leaf holding its exact point, not a node over two numbers)
      points[order[k]] = Point2(Kernel::Exact_kernel::Point_2(EQ(p.x / *scale), EQ(p.y / *scale)));
    } else {
      points[order[k]] = Point2(Kernel::Exact_kernel::Point_2(p.x, p.y));
    }
  }
  out.clear();
  out.reserve(in.size());
  for (std::size_t s = 0; s < in.size(); ++s) out.push_back({points[2 * s], points[2 * s + 1], in[s].left});
}

/// The canonical boundary (BoundaryChain) of the region `set` into `out`.
void canonical_boundary(const PolygonSet2& set, BoundaryChain& chain, std::vector<BoundarySegment>& out) {
  std::vector<PolygonWithHoles2> regions;  // outer boundaries counter-clockwise, holes clockwise
  set.polygons_with_holes(std::back_inserter(regions));
  chain.clear();
  const auto add_ring = [&](const Polygon2& ring) {
    // (By vertex, not by edge: an edge iterator's segment is a temporary, and exact() of its
    // ends would refer into it.)
    const std::size_t n = ring.size();
    for (std::size_t v = 0; v < n; ++v) {
      const auto& a = CGAL::exact(ring[v]);
      const auto& b = CGAL::exact(ring[v + 1 == n ? 0 : v + 1]);
      chain.add(a.x(), a.y(), b.x(), b.y());
    }
  };
  for (const PolygonWithHoles2& r : regions) {
    add_ring(r.outer_boundary());
    for (auto h = r.holes_begin(); h != r.holes_end(); ++h) add_ring(*h);
  }
  std::vector<BoundaryChain::Segment> segments;
  if (!chain.canonical(segments))  // a Boolean operation's result is a region: never
    throw std::logic_error("exact_lit_boundary: a lit region's boundary is not a region's");
  to_boundary_segments(segments, nullptr, out);
}

}  // namespace

ReceiverResult ExactReceiverJob::run(int facing) {
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
  // Areas only, a directional light, an exactly planar receiver: the casts are kept as plain
  // rational points in the receiver's scaled chart (integers where they can be:
  // exact/scaled_chart.hpp) and united by their boundaries (no Epeck number, no arrangement),
  // inside the chart box or each convex piece of a chart that is not its box as a window
  // (measure_in_box_window, measure_in_scaled_pieces), unless the chart has more than
  // kMaxChartPiecesToClip pieces (the join then).
  q_mode_ = !polygons_ && !point_light_ && fp_.exactly_planar &&
            (fp_.chart_is_box || fp_.convex_pieces.size() <= kMaxChartPiecesToClip);
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
  corner0_ = epick(face_.vertices[fp_.corner[1]]);
  corner1_ = epick(face_.vertices[fp_.corner[2]]);
  corner2_ = epick(face_.vertices[fp_.corner[0]]);
  const int own_solid = (*ctx_.solid_of)[face_id_];
  // A receiver in one solid's shadow whole (a fifth of a city's walls and roofs with some
  // shadow over a year): the solids whose light-space box contains the receiver's are cast
  // first, and one whose cast holds the chart box (note_cover_q, exactly) ends the job before
  // the candidate search. The others' casts stay: each is the exact shadow the search would
  // have it cast (a solid the culler rules out casts nothing on the box), and the union's area,
  // exact, does not depend on the order.
  w_.cast_first.clear();
  if (q_mode_ && fp_.chart_is_box && !tile_ && grid_ && ctx_.solids && ctx_.solid_of &&
      grid_->solid_items() == ctx_.solid_of) {  // (items that are solids: each met once)
    grid_->query_containing(face_id_, core::CasterCandidates::depth_floor(*grid_, *ctx_.cull, ctx_.cull->faces[face_id_]),
                            [&](std::size_t q) {
                              const int solid = (*ctx_.solid_of)[q];
                              if (solid < 0 || solid == own_solid) return false;
                              w_.cast_first.push_back(solid);
                              cast_convex_solid(solid);
                              return covered_;
                            });
  }
  static const std::vector<std::size_t> kNone;
  const std::vector<std::size_t>& candidates = covered_ ? kNone : gather_casters();
  if (covered_) stats_.candidate_pairs += w_.cast_first.size();
  if (split_above_ > 0 && !grid_ && candidates.size() > split_above_ && core::tileable(fp_)) {
    // Too many casters for one work item: the engine splits the face into tiles (and counts
    // it then), nothing else is done here.
    --stats_.receivers;
    stats_.candidate_pairs -= candidates.size();
    item_.split_candidates = candidates.size();
    return std::move(item_);
  }
  // (The search began a new round of the solids' marks: those cast already are not cast again.)
  for (const int solid : w_.cast_first) w_.casters.mark_solid_done(solid);
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

LitRegion ExactReceiverJob::lit_region(int facing) {
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
  region.lit = chart_minus_shadow();
  region.kind = region.lit.is_empty() ? LitRegion::Kind::Dark : LitRegion::Kind::Partial;
  return region;
}

PolygonSet2 ExactReceiverJob::chart_minus_shadow() {
  PolygonSet2 lit(w_.face(ctx_, face_id_).chart);
  lit.difference(*shadow_set_storage_);
  return lit;
}

bool ExactReceiverJob::unite_into_chain() {
  if (!fp_.chart_is_box) {
    chain_ready_ = measure_in_scaled_pieces();
    return chain_ready_;
  }
  BoundaryChain& chain = w_.chain;
  chain.clear();
  const ScaledChart& chart = scaled_chart();
  const EQ &x0 = chart.lo(0), &y0 = chart.lo(1), &x1 = chart.hi(0), &y1 = chart.hi(1);
  chain.add(x0, y0, x1, y0);  // the chart (its box), counter-clockwise
  chain.add(x1, y0, x1, y1);
  chain.add(x1, y1, x0, y1);
  chain.add(x0, y1, x0, y0);
  chain_ready_ = measure_in_box_window(&chain);
  return chain_ready_;
}

bool ExactReceiverJob::measure_in_box_window(BoundaryChain* chain) {
  // The chart box, counter-clockwise, as the window the casts (not clipped to it) are measured
  // in: the same exact rational as their clips to the box united, without the clips' crossings.
  const QPointList& box = box_corners();
  if (!chain && !tile_ && !wants_region()) {
    // Only the rounded doubles are wanted (no tile's sum, no region): the union's area enclosed
    // (no gcd per partly covered edge), measured exactly only where the enclosure leaves a
    // double undecided (exact_faces.hpp, EnclosedMeasure).
    ConvexUnionArea::Enclosure& e = w_.enclosure;
    if (!w_.union_area.twice_area_in_window_enclosed(w_.qshadows.data(), w_.qfirst, box.data(), box.size(), e))
      return false;
    if (measure_enclosed(e.lo, e.slack)) return true;
  }
  if (!w_.union_area.twice_area_in_window(w_.qshadows.data(), w_.qfirst, box.data(), box.size(), twice_area_, chain))
    return false;
  unscale_twice_area(twice_area_);
  measure(twice_area_);
  return true;
}

void ExactReceiverJob::boundary_from_set(LitBoundary& out) {
  const PolygonSet2 lit = chart_minus_shadow();
  if (lit.is_empty()) {
    out.kind = LitRegion::Kind::Dark;
    return;
  }
  out.kind = LitRegion::Kind::Partial;
  out.via_join = true;
  canonical_boundary(lit, w_.chain, out.segments);
}

LitBoundary ExactReceiverJob::lit_boundary(int facing) {
  LitBoundary out;
  emit_ = false;
  boundary_ = true;
  const ReceiverResult r = run(facing);
  out.lighting = r.lighting;
  if (!r.lighting.faces_light || fp_.degenerate) return out;  // attached shadow: dark
  if (shadow_count() == 0) {  // nothing in front
    out.kind = LitRegion::Kind::Whole;
    out.lit_chart_area = FT(*w_.exact_areas(ctx_, face_id_).first);
    return out;
  }
  if (covered_) return out;  // one cast is the chart box: dark, no lit area
  out.lit_chart_area = lit_chart_area_;
  if (chain_ready_) {
    std::vector<BoundaryChain::Segment>& segments = w_.chain_segments;
    const ScaledChart& chart = scaled_chart();
    if (w_.chain.canonical(segments) && encloses_lit_area(segments, chart)) {
      if (segments.empty()) return out;  // dark
      out.kind = LitRegion::Kind::Partial;
      to_boundary_segments(segments, chart.integer() ? &chart.scale() : nullptr, out.segments);
      return out;
    }
    // Not a region's boundary, or not around the measured lit area: never seen; the join
    // decides. (item_ was moved out by run(), but FaceLighting is trivially copyable, and
    // unite_by_join's measure() writes every area of it again.)
    shadows_.clear();
    q_casts_to_shadows();
    unite_by_join();
    out.lighting = item_.lighting;
    out.lit_chart_area = lit_chart_area_;
  }
  if (!shadow_set_storage_)  // every route that reaches here made the set
    throw std::logic_error("exact_lit_boundary: no shadow set and no boundary");
  boundary_from_set(out);
  return out;
}

bool ExactReceiverJob::encloses_lit_area(const std::vector<BoundaryChain::Segment>& segments,
                                         const ScaledChart& chart) {
  // Twice the area the canonical segments enclose (each on its region's side), in the scaled
  // chart, against twice the lit area measured by the union (unscaled) times K^2.
  EQ& twice = w_.qs.a;
  EQ& term = w_.qs.b;
  twice = 0;
  for (const BoundaryChain::Segment& sg : segments) {
    term = sg.from.x * sg.to.y;
    w_.qs.c = sg.from.y * sg.to.x;
    term -= w_.qs.c;
    if (sg.left) twice += term;
    else twice -= term;
  }
  term = CGAL::exact(lit_chart_area_);
  term *= 2;
  if (chart.integer()) {
    term *= chart.scale();
    term *= chart.scale();
  }
  return twice == term;
}

void ExactReceiverJob::unite_and_measure() {
  if (covered_) {  // the box itself (note_cover): the same exact values as its union would give
    twice_area_ = *w_.exact_areas(ctx_, face_id_).first;  // (the chart's area, not twice)
    measure(twice_area_);
    return;
  }
  if (q_mode_) {
    // Areas of the scaled chart (scaled_chart()), divided by K^2 before measuring.
    if (boundary_) {
      if (!q_outline_cast_ && unite_into_chain()) return;
    } else if (!fp_.chart_is_box) {
      if (!q_outline_cast_ && measure_in_scaled_pieces()) return;
    } else if (!boxed_casts()) {  // a box chart (not a tile): the casts measured inside the box
      if (!q_outline_cast_ && measure_in_box_window(nullptr)) return;
    } else if (w_.qfirst.size() == 2) {  // one cast (simple) inside a tile's box: it is the shadow
      twice_polygon_area(w_.qshadows.data(), w_.qshadows.data() + w_.qshadows.size(), twice_area_, w_.qs);
      unscale_twice_area(twice_area_);
      measure(twice_area_);
      return;
    } else if (!wants_region() && measure_tile_enclosed()) {
      return;
    } else if (w_.union_area.twice_area(w_.qshadows, w_.qfirst, twice_area_)) {
      unscale_twice_area(twice_area_);
      measure(twice_area_);
      return;
    }
    // A non-convex cast (the whole-outline route): the Boolean union of all of them, as Epeck
    // polygons (of the chart); measure_in_convex_pieces refuses them too, so the join.
    q_casts_to_shadows();
  } else if (!wants_region() && fp_.chart_is_box && shadows_.size() > 1) {
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
  if (!wants_region() && !fp_.chart_is_box && !shadows_.empty() && measure_in_convex_pieces()) return;
  unite_by_join();
}

bool ExactReceiverJob::measure_enclosed(const EQ& twice_lo, std::size_t slack) {
  const ScaledChart& chart = scaled_chart();
  if (slack == 0) {  // every term exact: the area itself
    twice_area_ = twice_lo;
    unscale_twice_area(twice_area_);
    measure(twice_area_);
    return true;
  }
  const auto [chart_area, scale] = w_.exact_areas(ctx_, face_id_);
  return w_.enclosed_measure.measure(*chart_area, *scale, twice_lo, slack, ConvexUnionArea::kEnclosureBits,
                                     chart.integer() ? &chart.scale() : nullptr, item_.lighting);
}

bool ExactReceiverJob::measure_tile_enclosed() {
  // A tile's casts (clipped to its box), areas only: the union's area enclosed, and the
  // enclosure unscaled into the item for the engine's sum (ReceiverResult::tile_shadow_width).
  // The tile's own doubles are pinned too: the fast path's merge reads a tile that fell back to
  // this engine by its shadow_area. False (the exact sum then) where they are not.
  ConvexUnionArea::Enclosure& e = w_.enclosure;
  if (!w_.union_area.twice_area_enclosed(w_.qshadows, w_.qfirst, e)) return false;
  if (e.slack > 0) {
    // A tile its casts may cover whole is measured exactly: the engine's sum of the tiles of a
    // face covered whole is then exact, and its lit part, zero, decided (an enclosure of it is not).
    const QPointList& box = box_corners();
    twice_polygon_area(box.data(), box.data() + box.size(), w_.qbound, w_.qs);
    w_.qarea = w_.qbound - e.lo;  // (box - lo) 2^k against the slack: can the union be the box?
    mpq_mul_2exp(w_.qarea.get_mpq_t(), w_.qarea.get_mpq_t(), ConvexUnionArea::kEnclosureBits);
    if (w_.qarea <= static_cast<unsigned long>(e.slack)) return false;
  }
  if (!measure_enclosed(e.lo, e.slack)) return false;
  if (e.slack == 0) return true;  // measured as the exact area (measure(): the tile's sum too)
  twice_area_ = e.lo;
  unscale_twice_area(twice_area_);
  item_.tile_shadow_chart_area = twice_area_;
  EQ width(static_cast<unsigned long>(e.slack));
  mpq_div_2exp(width.get_mpq_t(), width.get_mpq_t(), ConvexUnionArea::kEnclosureBits);
  unscale_twice_area(width);
  item_.tile_shadow_width = std::move(width);
  return true;
}

void ExactReceiverJob::q_casts_to_shadows() {
  const ScaledChart& chart = scaled_chart();
  for (std::size_t k = 0; k + 1 < w_.qfirst.size(); ++k) {
    Polygon2 polygon;
    for (std::size_t v = w_.qfirst[k]; v < w_.qfirst[k + 1]; ++v)
      polygon.push_back(Point2(FT(w_.qshadows[v].x / chart.scale()), FT(w_.qshadows[v].y / chart.scale())));
    shadows_.push_back(std::move(polygon));
  }
}

void ExactReceiverJob::unite_by_join() {
  shadow_set_storage_.emplace();  // only here: an empty Polygon_set_2 still allocates
  PolygonSet2& shadow_set_ = *shadow_set_storage_;
  // The areas route's rational casts are clipped to a tile's box only (boxed_casts()).
  const bool inside_chart = fp_.chart_is_box && (!q_mode_ || boxed_casts());
  if (shadows_.size() == 1 && inside_chart) {
    // One convex caster already clipped to a rectangular receiver: it is the shadow.
    shadow_regions_.emplace_back(shadows_.front());
    if (wants_region()) shadow_set_.insert(shadows_.front());
  } else {
    shadow_set_.join(shadows_.begin(), shadows_.end());  // one aggregated union
    if (!inside_chart) shadow_set_.intersection(w_.face(ctx_, face_id_).chart);
    shadow_set_.polygons_with_holes(std::back_inserter(shadow_regions_));
  }
  std::vector<FT> region_areas;
  for (const PolygonWithHoles2& r : shadow_regions_) region_areas.push_back(region_area(r));
  measure(balanced_sum(region_areas));
}

bool ExactReceiverJob::measure_in_convex_pieces() {
  // Areas only, a face whose chart is not its bounding box (a turned roof or ground, a gable, an
  // L-shaped footprint, a wall not exactly vertical: most of a real model's): area((union of the
  // casts) n chart), which the join and the intersection below make with arrangements (CGAL's
  // Boolean operations were most of such a face's time), as the union of the casts clipped
  // exactly to the chart, measured from its boundary (ConvexUnionArea): the same exact rational.
  // A chart that is not convex is the sum over its convex pieces (they tile it: their interiors
  // are disjoint, their union is the chart), each with the casts clipped to it. A cast that is
  // not convex leaves it to the join (as would a flat cast, which the union refuses; clipping a
  // convex cast of positive area never makes one).
  if (fp_.convex_pieces.size() > kMaxChartPiecesToClip) return false;  // (a comb: the join)
  const ExactFace& P = w_.face(ctx_, face_id_);
  w_.cast_boxes.clear();
  for (const Polygon2& cast : shadows_) {
    if (!cast.is_convex()) return false;
    w_.cast_boxes.push_back(cast.bbox());
  }
  if (P.chart_pieces.empty()) {
    if (!twice_area_in_window(P.chart, P.chart.bbox(), twice_area_)) return false;
  } else {
    twice_area_ = 0;
    for (std::size_t k = 0; k < P.chart_pieces.size(); ++k) {
      if (!twice_area_in_window(P.chart_pieces[k], P.chart_piece_boxes[k], w_.piece_twice_area)) return false;
      twice_area_ += w_.piece_twice_area;
    }
  }
  twice_area_ /= 2;
  measure(twice_area_);
  return true;
}

bool ExactReceiverJob::twice_area_in_window(const Polygon2& window, const CGAL::Bbox_2& box, EQ& out) {
  w_.window_points.clear();
  w_.window_first.assign(1, 0);
  for (std::size_t c = 0; c < shadows_.size(); ++c) {
    // Boxes of interval approximations hold the exact ones: apart, the cast misses the window.
    if (!CGAL::do_overlap(w_.cast_boxes[c], box)) continue;
    const Polygon2& cast = shadows_[c];
    w_.poly2.assign(cast.vertices_begin(), cast.vertices_end());
    clip_convex_to_window(w_.poly2, window, w_.scratch2);
    if (w_.poly2.size() < 3) continue;
    for (const Point2& p : w_.poly2) {
      const auto& e = CGAL::exact(p);
      QPoint2& q = w_.window_points.emplace_back();
      q.x = e.x();
      q.y = e.y();
      q.update_intervals();
    }
    w_.window_first.push_back(w_.window_points.size());
  }
  if (w_.window_first.size() == 1) {
    out = 0;
    return true;
  }
  return w_.union_area.twice_area(w_.window_points, w_.window_first, out);
}

bool ExactReceiverJob::measure_in_scaled_pieces() {
  // measure_in_convex_pieces for the casts as rational points of the scaled chart: each convex
  // piece of the face (the chart itself when it is convex) made a window of the scaled chart
  // from the receiver's own vertices (ScaledChart::chart), the union of the casts that reach
  // it measured inside it (ConvexUnionArea::twice_area_in_window: no cast is clipped); the
  // pieces' areas added.
  ScaledChart& chart = scaled_chart();
  w_.cast_boxes.clear();  // (to pick the casts that reach each piece: several pieces only)
  for (std::size_t k = 0; fp_.convex_pieces.size() > 1 && k + 1 < w_.qfirst.size(); ++k) {
    const IPoint2& i0 = w_.qshadows[w_.qfirst[k]].i;
    CGAL::Bbox_2 box(i0.x.inf(), i0.y.inf(), i0.x.sup(), i0.y.sup());
    for (std::size_t v = w_.qfirst[k] + 1; v < w_.qfirst[k + 1]; ++v) {
      const IPoint2& i = w_.qshadows[v].i;
      box += CGAL::Bbox_2(i.x.inf(), i.y.inf(), i.x.sup(), i.y.sup());
    }
    w_.cast_boxes.push_back(box);
  }
  BoundaryChain* chain = boundary_ ? &w_.chain : nullptr;
  // Each piece as a window of the scaled chart, and the casts that reach it: calls
  // measure_piece(casts, first) for every piece some cast reaches; false when it does.
  const auto for_each_piece = [&](const auto& measure_piece) {
    for (const std::vector<int>& piece : fp_.convex_pieces) {  // (a tile's fp_: the face's, its box aside)
      w_.qwindow.clear();
      CGAL::Bbox_2 box;
      for (int v : piece) {
        QPoint2& p = w_.qwindow.emplace_back();
        chart.chart(face_.vertices[v], p);  // its intervals are the input doubles, exactly
        box += CGAL::Bbox_2(p.i.x.inf(), p.i.y.inf(), p.i.x.sup(), p.i.y.sup());
      }
      if (chain) {  // the piece's boundary (counter-clockwise); the pieces' shared sides cancel
        for (std::size_t v = 0; v < w_.qwindow.size(); ++v) {
          const QPoint2& a = w_.qwindow[v];
          const QPoint2& b = w_.qwindow[v + 1 == w_.qwindow.size() ? 0 : v + 1];
          chain->add(a.x, a.y, b.x, b.y);
        }
      }
      // The casts that reach the piece, measured inside it as a window (no clip: its crossings'
      // rationals, and their gcds, were most of a georeferenced model's time). One piece (a
      // convex chart): all the casts as they are.
      const QPoint2* casts = w_.qshadows.data();
      const std::vector<std::size_t>* first = &w_.qfirst;
      if (fp_.convex_pieces.size() > 1) {
        w_.window_points.clear();
        w_.window_first.assign(1, 0);
        for (std::size_t k = 0; k + 1 < w_.qfirst.size(); ++k) {
          if (!CGAL::do_overlap(w_.cast_boxes[k], box)) continue;  // (boxes around the exact points)
          for (std::size_t v = w_.qfirst[k]; v < w_.qfirst[k + 1]; ++v) w_.window_points.push_back(w_.qshadows[v]);
          w_.window_first.push_back(w_.window_points.size());
        }
        casts = w_.window_points.data();
        first = &w_.window_first;
      }
      if (first->size() == 1) continue;  // no cast reaches this piece
      if (!measure_piece(casts, *first)) return false;
    }
    return true;
  };
  if (!chain && !tile_ && !wants_region()) {
    // Only the rounded doubles are wanted: the pieces' union areas enclosed and added
    // (measure_in_box_window), the exact route below only where they leave a double undecided.
    ConvexUnionArea::Enclosure& e = w_.enclosure;
    EQ& lo = w_.piece_twice_area_lo;
    lo = 0;
    std::size_t slack = 0;
    if (!for_each_piece([&](const QPoint2* casts, const std::vector<std::size_t>& first) {
          if (!w_.union_area.twice_area_in_window_enclosed(casts, first, w_.qwindow.data(), w_.qwindow.size(), e))
            return false;
          lo += e.lo;
          slack += e.slack;
          return true;
        }))
      return false;
    if (measure_enclosed(lo, slack)) return true;
  }
  twice_area_ = 0;
  if (chain) chain->clear();
  if (!for_each_piece([&](const QPoint2* casts, const std::vector<std::size_t>& first) {
        if (!w_.union_area.twice_area_in_window(casts, first, w_.qwindow.data(), w_.qwindow.size(),
                                                w_.piece_twice_area, chain))
          return false;
        twice_area_ += w_.piece_twice_area;
        return true;
      }))
    return false;
  unscale_twice_area(twice_area_);
  measure(twice_area_);
  return true;
}

void ExactReceiverJob::measure(const EQ& shadow) {
  if (tile_) item_.tile_shadow_chart_area = shadow;
  const auto [chart, scale] = w_.exact_areas(ctx_, face_id_);
  measure_lit_and_shadow(*chart, *scale, shadow, w_.qarea, w_.qbound, item_.lighting);
  if (wants_region()) lit_chart_area_ = FT(w_.qarea);  // lit_region's, lit_boundary's
}

void ExactReceiverJob::emit_whole_face(bool lit) {
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

Polygon2 ExactReceiverJob::tile_polygon() const {
  const FT x0(fp_.chart_min[0]), y0(fp_.chart_min[1]), x1(fp_.chart_max[0]), y1(fp_.chart_max[1]);
  const Point2 corners[4] = {Point2(x0, y0), Point2(x1, y0), Point2(x1, y1), Point2(x0, y1)};
  return Polygon2(corners, corners + 4);
}

PolygonSet2 ExactReceiverJob::tile_region(const ExactFace& P) const {
  PolygonSet2 region(tile_polygon());
  if (!fp_.chart_is_box) region.intersection(P.chart);
  return region;
}

void ExactReceiverJob::emit_fragments(const ExactFace& P) {
  std::vector<PolygonWithHoles2> lit_regions;
  // A tile's lit part is its part of the face minus the shadow.
  PolygonSet2 lit_set = tile_ ? tile_region(P) : PolygonSet2(P.chart);
  lit_set.difference(*shadow_set_storage_);
  lit_set.polygons_with_holes(std::back_inserter(lit_regions));
  emit(P, lit_regions, true);
  emit(P, shadow_regions_, false);
  if (!dropped_.empty()) item_.lighting.dropped_area = area_3d(balanced_sum(dropped_), P.area_scale_squared);
}

bool ExactReceiverJob::write(const ExactFace& P, const Polygon2& cell, const FT& cell_area, bool lit) {
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

void ExactReceiverJob::emit(const ExactFace& P, const std::vector<PolygonWithHoles2>& regions, bool lit) {
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

}  // namespace receiver_job

using receiver_job::ExactReceiverJob;

ReceiverResult compute_exact_receiver(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id,
                                      std::size_t light_id, const ExactLight& light, int facing,
                                      const Light& light_in, const core::LightSpaceGrid* grid, bool polygons,
                                      ShadowStats& stats, const core::TileRequest& tiles) {
  return ExactReceiverJob(ctx, w, face_id, light_id, light, light_in, grid, polygons, stats, tiles).run(facing);
}

namespace {

/// exact_lit_boundary's route through the join (lit_region's steps), its boundary made canonical.
LitBoundary join_lit_boundary(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id,
                              std::size_t light_id, const ExactLight& light, int facing, const Light& light_in,
                              const core::LightSpaceGrid* grid, ShadowStats& stats) {
  LitRegion region = exact_lit_region(ctx, w, face_id, light_id, light, facing, light_in, grid, stats);
  LitBoundary out;
  out.kind = region.kind;
  out.lit_chart_area = region.lit_chart_area;
  out.lighting = region.lighting;
  out.via_join = true;
  if (region.kind != LitRegion::Kind::Partial) return out;
  receiver_job::canonical_boundary(region.lit, w.chain, out.segments);
  return out;
}

}  // namespace

LitBoundary exact_lit_boundary(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id,
                               std::size_t light_id, const ExactLight& light, int facing, const Light& light_in,
                               const core::LightSpaceGrid* grid, ShadowStats& stats, bool via_join) {
  LitBoundary out = via_join ? join_lit_boundary(ctx, w, face_id, light_id, light, facing, light_in, grid, stats)
                             : ExactReceiverJob(ctx, w, face_id, light_id, light, light_in, grid, false, stats)
                                   .lit_boundary(facing);
  // A lit region that is the whole chart (casts that reach the chart's box but have no area on
  // the chart) is Whole, whichever route measured it.
  if (out.kind == LitRegion::Kind::Partial && CGAL::exact(out.lit_chart_area) == *w.exact_areas(ctx, face_id).first) {
    out.kind = LitRegion::Kind::Whole;
    out.segments.clear();
  }
  return out;
}

LitRegion exact_lit_region(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id, std::size_t light_id,
                           const ExactLight& light, int facing, const Light& light_in,
                           const core::LightSpaceGrid* grid, ShadowStats& stats) {
  return ExactReceiverJob(ctx, w, face_id, light_id, light, light_in, grid, true, stats).lit_region(facing);
}

}  // namespace shadow::exact
