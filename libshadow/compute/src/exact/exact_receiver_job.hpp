// SPDX-License-Identifier: GPL-3.0-or-later
// The exact engine's receiver job (exact_receiver.cpp), shared by the files of its steps: the
// run, the union, the areas and the fragments (exact_receiver.cpp), the casts
// (exact_receiver_casts.cpp). Internal to exact/.
#pragma once

#include "exact/exact_receiver.hpp"

#include "exact/leaf_projector.hpp"
#include "exact/scaled_chart.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <optional>
#include <vector>

namespace shadow::exact::receiver_job {

using EK = CGAL::Exact_predicates_inexact_constructions_kernel;

inline EK::Point_3 epick(const glm::dvec3& v) { return EK::Point_3(v.x, v.y, v.z); }

/// A non-convex caster of at least this many convex pieces, wholly in front of the receiver
/// under a directional light and casting inside its chart box, casts its whole outline as one
/// polygon (see cast_face).
constexpr std::size_t kWholeFaceFromPieces = 16;

class ExactReceiverJob {
 public:
  ExactReceiverJob(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id, std::size_t light_id,
                   const ExactLight& light, const Light& light_in, const core::LightSpaceGrid* grid, bool polygons,
                   ShadowStats& stats, const core::TileRequest& tiles = {})
      : ctx_(ctx), w_(w), face_id_(face_id), light_id_(light_id), light_(light), light_in_(light_in),
        grid_(grid), polygons_(polygons), emit_(polygons), stats_(stats), face_(ctx.scene->faces[face_id]),
        fp_(tiles.tile ? *tiles.tile : (*ctx.prep)[face_id]), point_light_(light.is_point()),
        tile_(tiles.tile != nullptr), split_above_(tiles.tile ? 0 : tiles.split_above) {}

  ReceiverResult run(int facing);

  /// run()'s steps up to the union, for the sun-hours map: the lit region itself. Constructed
  /// with polygons = true, so that the shadow's union is kept as a set.
  LitRegion lit_region(int facing);

  /// run()'s steps for exact_lit_boundary (constructed with polygons = false): the lit region's
  /// canonical boundary, from the boundary-measure union where q_mode_ applies, else from the
  /// join.
  LitBoundary lit_boundary(int facing);

 private:
  // ---- culling in doubles -------------------------------------------------------------------
  const std::vector<std::size_t>& gather_casters() {
    core::ReceiverCuller culler(*ctx_.cull, fp_, face_id_, light_in_);
    culler.use_caster_planes(*ctx_.scene, *ctx_.prep);
    const std::vector<std::size_t>& candidates =
        w_.casters.gather(culler, *ctx_.prep, face_id_, grid_, tile_ ? ctx_.cull : nullptr, tile_ ? &fp_ : nullptr,
                          ctx_.solid_of, /*one_face_per_solid=*/!point_light_ && fp_.exactly_planar);  // as run() casts
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
  void clip_to_chart_box(std::vector<Point2>& poly);

  /// clip_to_chart_box for a cast in the scaled chart (the box's bounds scaled with it).
  void clip_to_chart_box_q(QPointList& poly);
  /// Whether a convex rational cast and the chart box share interior points (the clip to the
  /// box would leave an area): exactly.
  bool reaches_chart_box(const QPointList& poly);
  /// The chart box's corners in the scaled chart, counter-clockwise, made once per job.
  const QPointList& box_corners();
  /// Whether the rational casts are clipped to the chart box (clip_to_chart_box_q): for a tile
  /// only; a face's chart measures them inside its box (a box chart, measure_in_box_window) or
  /// its convex pieces (measure_in_scaled_pieces) as windows.
  [[nodiscard]] bool boxed_casts() const { return tile_; }

  // ---- a convex solid casts the hull of its projection (see core::ConvexSolid) --------------------
  void cast_convex_solid(int solid);
  /// The rational hull of a solid wholly in front of the receiver (every vertex_sign positive)
  /// from its outline seen from the light (the grid's core::SolidOutlines), into `hull` as
  /// convex_hull gives it, without sorting or testing all its points; false where there is no
  /// such outline, and convex_hull must decide.
  bool hull_from_outline(int solid, QPointList& hull);

  // ---- a caster face, convex piece by convex piece ------------------------------------------
  void cast_face(std::size_t q);

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
  bool cast_whole_outline_from_point(const core::FacePrep& qp, const Face& qface);

  /// cast_whole_outline_from_point's caster when its shadow leaves the chart box: the outline is
  /// cut to the pyramid over the box in the caster's own chart (its input doubles, and the
  /// pyramid's sides as lines there), and each part of it cast whole. A simple polygon cut by
  /// a convex region is a set of simple polygons without holes (the complements of both are
  /// connected), whose images are simple, inside the box, and together the union of the
  /// clipped pieces' images: the same exact region. True when the caster is handled; false,
  /// casting nothing, when its corner's normal has no component along its chart's axis.
  bool cast_outline_cut_to_pyramid(const core::FacePrep& qp, const Face& qface);

  /// The lazy route (a lifted receiver or caster): the piece's front part, clipped to the
  /// pyramid for a point light, projected into w_.poly2.
  void project_piece_lazy(const ExactFace& Q, const std::vector<int>& piece, const ReceiverFrame& frame);

  /// A projected piece as a counter-clockwise shadow polygon; false when it has no area (the
  /// caster is edge-on to the light, or clipped away).
  bool add_shadow(const std::vector<Point2>& poly);

  /// Areas only, a box receiver (not a tile): a convex shadow inside the chart box (every cast
  /// is clipped to it) whose area is the box's is the box, and the union is the box whatever
  /// else casts (under a low sun many walls are wholly in shadow). Doubles first, so that only
  /// a near match costs an exact comparison.
  void note_cover(const Polygon2& shadow);

  /// add_shadow for rational points (the areas-only route).
  bool add_shadow_q(QPointList& poly);

  /// note_cover for a rational cast (counter-clockwise, in the scaled chart), not for a tile:
  /// note_cover_of_chart_q.
  void note_cover_q(const QPointList& poly);
  /// Sets covered_ when the cast (simple, counter-clockwise, not clipped) holds the chart: every
  /// vertex of the chart on the left of or on every edge of the cast (then the chart is in the
  /// cast's kernel, the cast itself when convex); the shadow is then the whole face.
  void note_cover_of_chart_q(const QPointList& poly);

  /// Whether twice a cast's area in doubles (about the box's corner) is within a relative 1e-9
  /// of twice the chart box's: only such a cast can be the whole box (note_cover).
  bool near_box_area(double twice) const { return near_box_area(twice, core::chart_box_area(fp_)); }
  static bool near_box_area(double twice, double box) { return std::abs(0.5 * twice - box) <= 1e-9 * box; }

  std::size_t shadow_count() const { return q_mode_ ? w_.qfirst.size() - 1 : shadows_.size(); }

  // ---- unite, areas -------------------------------------------------------------------------
  void unite_and_measure();

  /// Whether the shadow's region is wanted, as a set (fragments, the lit region) or as a chain
  /// (the lit boundary): not the areas-only shortcuts that give an area alone.
  bool wants_region() const { return polygons_ || boundary_; }

  /// q_mode_'s casts as Epeck polygons of the chart, into shadows_ (for the join).
  void q_casts_to_shadows();

  /// The union of shadows_ by CGAL's join (intersected with the chart unless it is its box),
  /// its regions and their area measured.
  void unite_by_join();

  /// lit_boundary's union in q_mode_: the chart box (or each convex piece) minus the union of
  /// the casts, as a chain in w_.chain (of the scaled chart), and the areas measured; false,
  /// nothing measured, where the union refuses a cast.
  bool unite_into_chain();

  /// The chart minus shadow_set_storage_ (lit_region's region, boundary_from_set's).
  PolygonSet2 chart_minus_shadow();

  /// The canonical boundary of the chart minus shadow_set_storage_ into `out` (its kind too).
  void boundary_from_set(LitBoundary& out);

  /// Whether canonical segments of the scaled chart enclose exactly the lit area measured
  /// (lit_chart_area_): lit_boundary's check of the chain before it is used.
  bool encloses_lit_area(const std::vector<BoundaryChain::Segment>& segments, const ScaledChart& chart);

  /// The areas from the shadow's exact area in the chart, in plain rationals (the same values
  /// as area_3d and round_to_double give through lazy numbers, without building their DAGs).
  void measure(const FT& shadow_chart_area) { measure(CGAL::exact(shadow_chart_area)); }
  void measure(const EQ& shadow);
  /// Twice an area of the scaled chart, in place, made the chart's area (halved, unscaled).
  void unscale_twice_area(EQ& twice) {
    twice /= 2;
    scaled_chart().unscale_area(twice);
  }
  bool measure_in_convex_pieces();  ///< unite_and_measure's areas-only route for a chart not a box
  /// Twice the area of the union of the casts (shadows_, their boxes in w_.cast_boxes) clipped
  /// to a convex counter-clockwise window with bounding box `box`; false where the union refuses.
  bool twice_area_in_window(const Polygon2& window, const CGAL::Bbox_2& box, EQ& out);
  /// measure_in_convex_pieces for q_mode_'s rational casts (the scaled chart's pieces, each a
  /// window the casts are measured in, not clipped to); false, the casts left in w_.qshadows,
  /// where the union refuses a cast or a piece that is not convex.
  bool measure_in_scaled_pieces();
  /// The areas-only union of the rational casts inside the chart box (a box chart, not a tile)
  /// as a window, measured (and, with `chain`, its boundary reversed into it); false when some
  /// cast is not convex.
  bool measure_in_box_window(BoundaryChain* chain);
  bool measure_tile_enclosed();  ///< unite_and_measure's areas-only route for a tile's casts (several)
  /// The doubles from twice the union's area (scaled chart) in [twice_lo, + slack 2^-k]: measure()
  /// of the exact area where there is no slack, else pinned (EnclosedMeasure); false, nothing
  /// set, where they are not.
  bool measure_enclosed(const EQ& twice_lo, std::size_t slack);

  // ---- fragments ----------------------------------------------------------------------------
  /// The face's outline as one fragment (wholly lit or wholly in shadow). A sliver face whose
  /// outline in doubles is not a simple polygon of certainly non-zero area goes through emit()
  /// like any other region: triangles, and dropped_area for those that collapse.
  void emit_whole_face(bool lit);

  /// A tile's chart box as a counter-clockwise polygon (its corners are exact doubles).
  Polygon2 tile_polygon() const;

  /// A tile's part of the face: its box, intersected with the face's outline unless the box
  /// lies in the face (chart_is_box: a box face's tiles, and the inner cells of other faces).
  PolygonSet2 tile_region(const ExactFace& P) const;

  void emit_fragments(const ExactFace& P);

  /// One cell as a fragment, if its vertices rounded to doubles still make one simple polygon
  /// of non-zero area (the output contract); false, writing nothing, otherwise.
  bool write(const ExactFace& P, const Polygon2& cell, const FT& cell_area, bool lit);

  void emit(const ExactFace& P, const std::vector<PolygonWithHoles2>& regions, bool lit);

  const core::PreparedScene& ctx_;
  ExactWorker& w_;
  std::size_t face_id_, light_id_;
  const ExactLight& light_;
  const Light& light_in_;
  const core::LightSpaceGrid* grid_;
  bool polygons_;     ///< keep the shadow's union as a set (fragments or the lit region need it)
  bool boundary_ = false;     ///< lit_boundary: the union wanted as a chain (see wants_region())
  bool chain_ready_ = false;  ///< w_.chain holds the lit region's boundary (unite_into_chain)
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
  bool chart_corners_ready_ = false;  ///< w_.qcorners holds this job's chart corners
  bool box_corners_ready_ = false;    ///< w_.qbox holds this job's chart box corners
  bool q_outline_cast_ = false;  ///< q_mode_: a non-convex caster cast its whole outline (cast_face)
  FT lit_chart_area_{0};                            ///< its complement's exact area (unite_and_measure)
  std::size_t fragment_id_ = 0;
  std::vector<Polygon2> cells_, triangles_;
  std::vector<FT> dropped_;  ///< exact chart areas of cells too thin to write
};

}  // namespace shadow::exact::receiver_job
