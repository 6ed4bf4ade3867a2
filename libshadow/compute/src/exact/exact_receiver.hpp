// SPDX-License-Identifier: GPL-3.0-or-later
// The exact engine's computation for one receiving face under one light (the engine dispatches
// each receiver here or to the fast path). Steps, in exact_receiver.cpp: gather casters (the
// double culling), cast a convex solid, cast a face by the leaf route (exactly planar faces: GMP
// straight from the input doubles) or by the lazy route (lifted faces: Epeck), clip to the
// chart box, unite, areas, emit fragments. Include only from CGAL translation units.
#pragma once

#include "core/culling.hpp"
#include "core/face_prep.hpp"
#include "core/prepared_scene.hpp"
#include "core/tiles.hpp"
#include "exact/convex_union_area.hpp"
#include "exact/exact_faces.hpp"
#include "exact/lazy_geometry.hpp"

#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>

#include <CGAL/enum.h>

#include <cstddef>
#include <memory>
#include <optional>
#include <utility>
#include <unordered_map>
#include <vector>

namespace shadow::exact {

/// What the computation reads from the prepared engine (all shared, read-only).

/// How many exact faces a worker keeps (ExactWorker::trim between work items): a receiver's
/// face and its lazy-route casters are made again when needed after a trim, which a light's
/// receivers rarely need (each is a receiver once per light).
constexpr std::size_t kExactFaceCache = 4096;

/// The most polygon pairs a worker's union scratch keeps room for between work items (some
/// 3 MB; ConvexUnionArea::shed). Its lists are sized by the largest union the thread met:
/// Delft's water triangle under 4,112 casts left some 27 MB a thread to the end of the run. A
/// receiver under that many overlapping casts is rare, and costly enough that growing the
/// scratch again is nothing beside it.
constexpr std::size_t kUnionPairsKept = std::size_t{1} << 16;

/// Per-thread exact state. Epeck objects are never shared between threads.
struct ExactWorker {
  std::vector<std::unique_ptr<ExactFace>> faces;  ///< built on first use
  core::CasterCandidates casters;
  std::vector<int> cast_first;  ///< the solids a job cast before its candidate search (run())
  std::vector<Point3> poly, scratch;
  std::vector<Point2> poly2, scratch2;
  // Areas only, a chart that is not a box: the casts clipped to the chart or to one of its
  // convex pieces, as rational points (window_points[window_first[k], window_first[k + 1])),
  // and the casts' bounding boxes.
  QPointList window_points, qwindow;
  QPointList qcorners;  ///< the current job's chart corners, scaled (note_cover_of_chart_q)
  QPointList qbox;      ///< the current job's chart box corners, scaled (box_corners)
  std::vector<std::size_t> window_first;
  std::vector<CGAL::Bbox_2> cast_boxes;
  EQ piece_twice_area, piece_twice_area_lo;
  std::vector<CGAL::Sign> vertex_sign, piece_sign;
  ConvexUnionArea union_area;  ///< areas only: the union's exact area without a Boolean operation
  ConvexUnionArea::Enclosure enclosure;  ///< areas only: the union's area enclosed (measure_enclosed's callers)
  EnclosedMeasure enclosed_measure;      ///< and the doubles it pins
  BoundaryChain chain;         ///< exact_lit_boundary: the lit region's boundary as a chain
  std::vector<BoundaryChain::Segment> chain_segments;  ///< and its canonical form
  // The areas-only route's casts as rational points of the scaled chart (exact/scaled_chart.hpp,
  // exact/rational_points.hpp) and scratch.
  QPointList qshadows, qpoly, qscratch;  // slots kept between casts (their limbs reused)
  std::vector<std::size_t> qfirst, qorder, qchain;
  std::vector<int> qside;
  QScratch qs;
  EQ qbound, qarea;
  /// Per face, made on first use and kept across trims: the exact chart area and area scale of
  /// ExactFace (evaluating their lazy DAGs again after every trim cost a tenth of a year's run).
  /// A map, not a vector per face: a worker needs them for the receivers it measures, and
  /// vectors of every face's rationals in every worker were about 1.2 GB of a million-face
  /// city's 2.6 GB peak on 16 threads (and their construction was a serial cost per thread).
  std::unordered_map<std::size_t, std::pair<EQ, EQ>> areas_q;

  /// Face f's exact chart area and area scale (ExactFace::chart_area, ::area_scale_squared):
  /// for an exactly planar face from plain integers (planar_face_exact_areas), without making
  /// its lazy ExactFace.
  std::pair<const EQ*, const EQ*> exact_areas(const core::PreparedScene& ctx, std::size_t f) {
    auto [it, inserted] = areas_q.try_emplace(f);
    if (inserted) {
      const core::FacePrep& prep = (*ctx.prep)[f];
      if (!prep.exactly_planar ||
          !planar_face_exact_areas((*ctx.scene).faces[f].vertices, prep, it->second.first, it->second.second)) {
        const ExactFace& P = face(ctx, f);
        it->second.first = CGAL::exact(P.chart_area);
        it->second.second = CGAL::exact(P.area_scale_squared);
      }
    }
    return {&it->second.first, &it->second.second};
  }

  std::vector<std::size_t> built;  ///< the faces that have an entry in `faces`

  /// Sized for a scene of `faces` faces and `solids` convex solids.
  void reset(std::size_t face_count, std::size_t solid_count) {
    faces.clear();
    faces.resize(face_count);
    built.clear();
    areas_q.clear();
    casters.reset(solid_count);
  }
  /// This thread's exact view of face f (made on first use).
  const ExactFace& face(const core::PreparedScene& ctx, std::size_t f) {
    if (!faces[f]) {
      faces[f] = std::make_unique<ExactFace>(make_exact_face((*ctx.scene).faces[f].vertices, (*ctx.prep)[f]));
      built.push_back(f);
    }
    return *faces[f];
  }
  /// Frees every exact face made so far when there are more than `cap` of them: the cache
  /// otherwise grows to one ExactFace (with its lazy numbers; docs/benchmarks.md) per face
  /// and thread.
  /// Only between work items: it invalidates the references face() handed out.
  void trim(std::size_t cap) {
    // The exact areas outlive trims (a series measures every receiver at every instant) up to
    // eight times as many faces: a million-face series would otherwise end with one per face.
    if (areas_q.size() > 8 * cap) areas_q.clear();
    union_area.shed(kUnionPairsKept);
    if (built.size() <= cap) return;
    for (std::size_t f : built) faces[f].reset();
    built.clear();
  }
};

/// Result for one receiving face (or one tile of it) under one light.
struct ReceiverResult {
  FaceLighting lighting;
  std::vector<Fragment> fragments;  ///< fragment_id local to the receiver (or tile), from 0
  /// Set, and nothing else computed, when the face asked to be split into tiles
  /// (core::TileRequest::split_above): its number of candidate casters.
  std::size_t split_candidates = 0;
  /// A tile (core::TileRequest::tile) only: its exact shadowed area in the face's chart, as a
  /// plain exact rational (no lazy DAG shared with the worker that made it); the engine sums
  /// the tiles' before rounding once. `tile_unshadowed`: nothing in front of the tile.
  /// (Empty for zero and for whole receivers: a million items each with a GMP rational were
  /// a serial cost of their own.)
  std::optional<FT::Exact_type> tile_shadow_chart_area;
  /// Instead, areas only: the tile's exact shadowed area lies in [tile_shadow_chart_area,
  /// + tile_shadow_width] (ConvexUnionArea's enclosure, unscaled); the engine adds the tiles'
  /// and pins the face's doubles from the sum (EnclosedMeasure::measure_between), or computes the
  /// face whole where they are not pinned. Empty: tile_shadow_chart_area is exact.
  std::optional<FT::Exact_type> tile_shadow_width;
  bool tile_unshadowed = false;
  /// A tile computed by the exact engine (tile_shadow_chart_area is then its shadow); false for
  /// a tile of the fast path, whatever its bound (a fast bound of 0 does not make it exact).
  bool tile_exact = false;
};

/// One segment of a lit region's canonical boundary (LitBoundary).
struct BoundarySegment {
  Point2 from, to;  ///< from lexicographically before to
  bool left = true;  ///< the region lies on the left of from -> to (else on its right)
};

/// The lit part of a receiver under one light, exact, in the receiver's chart (ExactFace::chart).
struct LitRegion {
  enum class Kind { Dark, Whole, Partial };
  Kind kind = Kind::Dark;  ///< Dark: nothing lit (also degenerate faces); Whole: the whole chart
  PolygonSet2 lit;         ///< Partial only: the lit region (the chart minus the shadow's union)
  FT lit_chart_area{0};    ///< exact area of the lit region in the chart (the whole chart's when Whole)
  FaceLighting lighting;   ///< the areas, as compute_exact_receiver reports them
};

/// The lit region of receiver `face_id` under `light`: the same steps (casters, projection,
/// union) as compute_exact_receiver, stopping at the exact region instead of fragments.
LitRegion exact_lit_region(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id, std::size_t light_id,
                           const ExactLight& light, int facing, const Light& light_in,
                           const core::LightSpaceGrid* grid, ShadowStats& stats);

/// A lit region's boundary in the receiver's chart, in canonical form (exact/boundary_chain.hpp):
/// the same segments, in the same order, for the same region, however it was computed.
struct LitBoundary {
  LitRegion::Kind kind = LitRegion::Kind::Dark;  ///< as LitRegion's
  FT lit_chart_area{0};                         ///< as LitRegion's
  FaceLighting lighting;                        ///< as LitRegion's
  /// Partial only: the lit region's boundary, every segment from its lexicographically smaller
  /// end, the region on its left when `left`.
  std::vector<BoundarySegment> segments;
  bool via_join = false;  ///< a partly lit region whose boundary came from CGAL's join (tests)
};

/// exact_lit_region's region as its canonical boundary. Areas-only steps where they apply (an
/// exactly planar receiver under a directional light, a chart of at most kMaxChartPiecesToClip
/// convex pieces, convex casts): the casts as rational points of the scaled chart, the lit
/// region's boundary taken from the boundary-measure union's uncovered pieces (the window's
/// boundary minus the union's, exact/boundary_chain.hpp), with no Boolean operation; otherwise,
/// or when `via_join` (tests), the chart minus CGAL's join of the casts, its boundary made
/// canonical the same way.
LitBoundary exact_lit_boundary(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id,
                               std::size_t light_id, const ExactLight& light, int facing, const Light& light_in,
                               const core::LightSpaceGrid* grid, ShadowStats& stats, bool via_join = false);

/// Computes receiver `face_id` under `light` (exact form of `light_in`), whose plane has sign
/// `facing` at the light (> 0: lit side). Adds to `stats`.
ReceiverResult compute_exact_receiver(const core::PreparedScene& ctx, ExactWorker& w, std::size_t face_id,
                                      std::size_t light_id, const ExactLight& light, int facing,
                                      const Light& light_in, const core::LightSpaceGrid* grid, bool polygons,
                                      ShadowStats& stats, const core::TileRequest& tiles = {});

}  // namespace shadow::exact
