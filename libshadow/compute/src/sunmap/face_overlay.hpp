// SPDX-License-Identifier: GPL-3.0-or-later
// One receiving face's overlay of lit regions (the sun-hours map, docs/sun-hours-map.md), cut
// into vertical strips of its chart that are overlaid independently (in parallel, each in its
// own small arrangement) so that neither time nor memory is held by one arrangement of every
// boundary of every instant.
#pragma once

#include "core/face_prep.hpp"
#include "exact/exact_faces.hpp"
#include "exact/kernel.hpp"

#include <shadow/sun_hours.hpp>

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>

#include <gmpxx.h>

#include <cstddef>
#include <map>
#include <memory>
#include <vector>

namespace shadow::sunmap {

using SegmentTraits = CGAL::Arr_segment_traits_2<exact::Kernel>;
// A curve's data: +(i + 1) when instant i's lit region lies on the left of the segment run from
// its lexicographically smaller end to the larger, -(i + 1) when it lies on the right. Instant
// index `n` (the number of instants) stands for the face's chart outline, n + 1 for a strip's
// frame (which changes nothing when crossed, and is never crossed).
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, long>;

/// The tag of instant `instant`'s boundary curve, its region on the left when `left` (above).
inline long curve_tag(std::size_t instant, bool left) {
  const long t = static_cast<long>(instant) + 1;
  return left ? t : -t;
}
/// The instant (or the outline's n, the frame's n + 1) a curve's tag names.
inline std::size_t tag_instant(long tag) { return static_cast<std::size_t>((tag < 0 ? -tag : tag) - 1); }
/// Whether the tagged curve's region lies on its left (run from its smaller end to the larger).
inline bool tag_left(long tag) { return tag > 0; }
using Curve = Traits::Curve_2;
using XCurve = Traits::X_monotone_curve_2;  ///< a segment with every tag of the curves overlapping it

/// Boundaries of one face gathered over the instants: all of them, or those entering one strip
/// (the full map unpacks each strip's before overlaying it).
struct FaceBoundaries {
  std::vector<Curve> curves;  ///< the partial instants' boundaries and the chart's outline
  mpq_class base{0};          ///< the hours of the instants that light the whole face
};

/// A vertical strip x0 <= x <= x1 of a face's chart; `whole`: the whole plane (no frame).
struct Strip {
  bool whole = true;
  double x0 = 0, x1 = 0;    ///< the strip's sides (exact doubles)
  double ylo = 0, yhi = 0;  ///< below and above the whole chart: the frame's bottom and top
};

/// Splits a face whose boundaries hold more than `strip_edges` segments into strips of about
/// that many (0: never), at quantiles of the x of the segments `curves`; else one whole strip.
/// `expected`: the number of segments to size the strips by (curves.size() when every instant's
/// boundaries are there; more when they are a sample, the first instants of a stream).
std::vector<Strip> choose_strips(const std::vector<Curve>& curves, std::size_t expected, const exact::Polygon2& chart,
                                 std::size_t strip_edges);

/// The indices of `curves` that may enter each strip (by interval bounds: a superset).
std::vector<std::vector<std::size_t>> bucket_curves(const std::vector<Curve>& curves, const std::vector<Strip>& strips);

/// What one strip of one face contributes.
struct StripMap {
  std::vector<SunHoursCell> cells;        ///< the full map's cells (region ids local, from 0)
  std::size_t regions = 0;
  std::vector<SunHoursCell> level_cells;  ///< the threshold map's cells (sun_hours = the level reached)
  std::size_t level_regions = 0;
  /// The exact chart areas of the cells, per exact hours (full map only): summed once per face
  /// by area_3d_of_sum (adding them one by one was most of the run time: unrelated denominators).
  std::map<mpq_class, std::vector<mpq_class>> hour_area;
  std::vector<std::vector<mpq_class>> level_area;  ///< the same per level index (0: below every level)
  mpq_class dropped{0};                      ///< chart area of cells too thin to write
};

struct FaceTiles;     // lit_tiles.hpp
struct RoughSegment;  // rough_segments.hpp

/// How a strip is overlaid.
struct OverlayRequest {
  const exact::ExactFace* face = nullptr;
  const core::FacePrep* prep = nullptr;
  std::size_t face_id = 0;
  const std::vector<double>* hours = nullptr;  ///< the instants' weights
  /// The same weights as summed exactly (sunmap::exact_hours): every exact sum, bound and level
  /// comparison uses these; `hours` only says which are zero.
  const std::vector<mpq_class>* exact_hours = nullptr;
  bool merge = true;                           ///< merge touching cells of equal hours
  bool full = true;                            ///< emit the full map's cells
  std::vector<mpq_class> levels;               ///< ascending thresholds; empty: no threshold map
  std::size_t round_edges = 1000;              ///< the threshold map alone: the first round's new segments
  /// The threshold map alone: where each instant may light the face (lit_tiles.hpp), to bound
  /// per cell the sun still to come; null: every cell is bounded by every instant still to come.
  const FaceTiles* tiles = nullptr;
};

/// Overlays the curves `which` of `b` inside `strip` in one arrangement (the full map, and its
/// levels when asked): the cells of the chart in the strip, with hours summed exactly along a walk
/// from a face of known hours (outside the chart: 0).
StripMap overlay_strip(const OverlayRequest& request, const FaceBoundaries& b, const std::vector<std::size_t>& which,
                       const Strip& strip);

class StripOverlay;

/// The threshold map alone of one strip (OverlayRequest::full false, with levels), fed the
/// instants' boundaries as they are computed, in rounds (docs/sun-hours-map.md, step 7): it holds
/// the boundaries kept so far and the instants fed and not yet swept, never every instant's.
/// Either streamed (feed: in time order, the hours still to come bounded by all of them) or
/// planned (plan, then feed_planned: in a face's order, the hours still to come bounded per cell
/// by the request's tiles and the strip's pending boundaries). A round is swept once the instants
/// fed fill it, so the rounds do not depend on how many instants come at a time.
class LevelRounds {
 public:
  /// `outline`: the face's chart outline (tagged with the number of instants); `which`: those of
  /// its curves that may enter `strip` (bucket_curves). `request` and `outline` must outlive
  /// this: the strip's overlay is begun from them on first use, not here (a map sets up every
  /// face's strips before their jobs run; Delft's overlays held from the start were 92 MB).
  LevelRounds(const OverlayRequest& request, const Strip& strip, const std::vector<Curve>& outline,
              const std::vector<std::size_t>& which);
  ~LevelRounds();
  LevelRounds(LevelRounds&&) noexcept;
  LevelRounds& operator=(LevelRounds&&) noexcept;

  /// Feeds the next instants: the curves `which` of `curves` (their boundaries on the face, in
  /// time order, each tagged with its instant), `whole` the hours of those lighting the whole
  /// face, `unfed` the hours of every instant still to be fed (a bound on what may still come).
  /// Streamed only (no plan). Sweeps every round that these instants fill.
  void feed(const std::vector<Curve>& curves, const std::vector<std::size_t>& which, const mpq_class& whole,
            const mpq_class& unfed);

  /// Before any feed: plans the instants of `order` (the face's instants cutting it, fed a band
  /// at a time: the bands end before the positions `band_ends`) whose boundaries may enter the
  /// strip (a segment among `which` of `segments`, the face's boundaries in doubles,
  /// bucket_rough): swept band by band, the sunniest in the strip first within a band; `whole`
  /// the hours of every instant lighting the whole face.
  void plan(const std::vector<std::size_t>& order, const std::vector<std::size_t>& band_ends,
            const std::vector<RoughSegment>& segments, const std::vector<std::size_t>& which,
            const mpq_class& whole);
  /// plan from the exact curves `which` of `curves` (those that may enter the strip).
  void plan(const std::vector<std::size_t>& order, const std::vector<std::size_t>& band_ends,
            const std::vector<Curve>& curves, const std::vector<std::size_t>& which, const mpq_class& whole);
  /// After plan: feeds the planned instants at positions before `order_end` (a band's end) in the
  /// face's order, whose boundaries that may enter the strip are `which` of `curves` (all of
  /// them, in any order). Sweeps every round that these instants fill.
  void feed_planned(const std::vector<Curve>& curves, const std::vector<std::size_t>& which, std::size_t order_end);
  bool planned() const;

  /// After the last feed: the rounds left and the level regions.
  StripMap finish();

 private:
  StripOverlay& started();  ///< the overlay, begun on first use

  std::unique_ptr<StripOverlay> impl_;
  const OverlayRequest* request_;
  Strip strip_;
  const std::vector<Curve>* outline_;
  std::vector<std::size_t> outline_which_;
};

/// `c` clipped to the strip x0 <= x <= x1 (into `out`); false when nothing of it enters the
/// strip's inside (outside, touching a side at a point, or lying on a side).
bool clip_to_strip(const Curve& c, const exact::FT& x0, const exact::FT& x1, Curve& out);

/// The exact signed area of a polygon of exact points (a cell's chart area): the shoelace on its
/// vertices' exact rational coordinates. The same value as polygon_area, with half the rational
/// operations and no lazy DAG per term: the cells' exact areas were half the map's run time.
mpq_class exact_polygon_area(const exact::Polygon2& polygon);

/// One face's part of the map, its strips' parts concatenated (region ids local to the face).
struct FaceMap {
  std::vector<SunHoursCell> cells, level_cells;
  std::size_t regions = 0, level_regions = 0;
  SunHoursFace face;
};

/// Face `face`'s map from its strips' parts (taken), its areas summed exactly and rounded once
/// under (3D / chart area)^2 = `scale`, with `levels` levels.
FaceMap assemble(std::vector<StripMap>& strips, SunHoursFace face, const mpq_class& scale, std::size_t levels);

/// Adds the boundary of `polygon` (the region on its left) as curves tagged with `instant`.
void add_boundary(const exact::Polygon2& polygon, long instant, std::vector<Curve>& curves);

/// Adds segment from -> to (from lexicographically before to: a canonical boundary's,
/// exact::BoundarySegment) as a curve tagged with `instant`, the region on its left when `left`.
void add_segment(const exact::Point2& from, const exact::Point2& to, bool left, long instant,
                 std::vector<Curve>& curves);

/// area_3d (as area_3d_mpq) of the exact sum of the non-negative chart areas in `parts`, rounded
/// once. The terms are first summed in fixed point, far below the total's last bit, which brackets
/// the sum; when both ends of the bracket round alike that is the exact sum's rounding, else (a
/// sum within about 2^-60 of its last bit from a tie) the terms are summed exactly.
double area_3d_of_sum(const std::vector<const std::vector<mpq_class>*>& parts, const mpq_class& scale);

/// area_3d of an exact rational chart area under (3D / chart area)^2 = `scale`, rounded as
/// area_3d rounds.
double area_3d_mpq(const mpq_class& chart_area, const mpq_class& scale);

}  // namespace shadow::sunmap
