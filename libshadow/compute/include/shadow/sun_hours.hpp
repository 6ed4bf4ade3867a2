// SPDX-License-Identifier: GPL-3.0-or-later
/// @file sun_hours.hpp
/// @brief The exact sun-hours map: the overlay of every instant's lit region on chosen faces.
///
/// For each receiving face, the lit region of every instant (an exact polygon set in the face's
/// chart, as the exact engine computes it) is overlaid in one exact arrangement; each cell of
/// the overlay carries the sum of the weights (hours) of the instants under which it is lit.
/// Cells of equal hours that share an edge are merged, and regions with holes are split into
/// simple polygons as fragments are. Sampling tools draw this map on point grids; here the
/// boundaries are exact. See docs/sun-hours-map.md.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/series.hpp>
#include <shadow/shadows.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace shadow {

/// One instant of a sun path: a directional light and the hours it stands for.
struct SunHoursInstant {
  Light light;         ///< a directional light (point lights are accepted too)
  double hours = 1.0;  ///< the weight: hours of sun this instant stands for (finite, >= 0)
};

/// One simple polygon of a face, lit under the same instants everywhere inside.
struct SunHoursCell {
  std::size_t face_id = 0;
  /// Sum of the `hours` of the instants under which the cell is lit, summed exactly and
  /// rounded once (so equal sets of instants give bit-equal hours).
  double sun_hours = 0.0;
  /// Numbers the connected regions of equal hours of the whole map; the simple pieces of one
  /// region (a region with holes is split) share it.
  std::size_t region_id = 0;
  std::vector<glm::dvec3> polygon;  ///< with the face's orientation, points rounded once
  double area = 0.0;                ///< exact area of this cell, rounded once
};

/// The area of a face's part that gets exactly `sun_hours` hours (SunHoursFace::areas).
struct SunHoursArea {
  double sun_hours = 0.0;  ///< rounded once from the exact sum, as SunHoursCell::sun_hours
  double area = 0.0;       ///< the exact area of every cell with these hours, rounded once
};

/// Sun hours on one receiving face.
struct SunHoursFace {
  std::size_t face_id = 0;
  double area = 0.0;  ///< the face's area
  /// Exact integral of sun hours over the face (sum over cells of sun_hours x area, equal to
  /// the sum over instants of hours x lit area), rounded once; unit: hours x area.
  double hour_area = 0.0;
  /// Area of cells left out because rounding them to doubles made them degenerate (slivers a
  /// few ulps wide; see Fragment and FaceLighting::dropped_area).
  double dropped_area = 0.0;
  std::size_t instants_lit = 0;  ///< instants under which some part of the face is lit
  /// The full map's area per distinct hours, ascending by hours (empty when
  /// SunHoursOptions::full is false). Exact: the sum of the cells' exact areas, rounded once, so
  /// two ways of cutting the face into cells give bit-equal areas.
  std::vector<SunHoursArea> areas;
  /// Per SunHoursMap::levels: the exact area of the part of the face that gets at least that
  /// many hours, rounded once (empty without levels).
  std::vector<double> level_areas;
};

/// The map over every chosen face.
struct SunHoursMap {
  std::vector<SunHoursCell> cells;  ///< ordered by face_id, then region_id
  std::vector<SunHoursFace> faces;  ///< one per chosen face, by face_id
  double total_hours = 0.0;         ///< the sum of the instants' hours
  /// Whether `cells` and SunHoursFace::areas hold the full map (false: the threshold map was
  /// computed alone, SunHoursOptions::full false with levels).
  bool full = true;
  /// Region ids used: every cell's region_id is below it (a region whose cells were all too
  /// thin to write still takes its id). A map of more faces computed in parts is their
  /// concatenation in face order, each part's region ids shifted by the earlier parts' `regions`.
  std::size_t regions = 0;

  /// The threshold map's levels (SunHoursOptions::levels, ascending, repeats dropped).
  std::vector<double> levels;
  /// The threshold map: cells of the regions that reach the same level, `sun_hours` being the
  /// highest level reached (0 below the lowest), merged where they touch; ordered by face_id,
  /// then region_id (numbered apart from `cells`' regions). Its size follows the level
  /// boundaries, not the number of instants. Empty without levels.
  std::vector<SunHoursCell> level_cells;
  std::size_t level_regions = 0;  ///< region ids used by level_cells
};

/// The area of the map's faces that gets at least levels[k] hours: the sum over faces of
/// SunHoursFace::level_areas[k] (one value per level).
std::vector<double> sun_hours_level_areas(const SunHoursMap& map);

/// The area of the map's faces (the sum of SunHoursFace::area).
double sun_hours_map_area(const SunHoursMap& map);

/// Lines for a summary, each starting with `indent`: per level, the area that gets at least
/// that many hours and its share of the map's area ("at least 2 h: 812.5 m2 of 1200 m2
/// (67.7%)"), the threshold map's cell count; empty without levels.
std::string sun_hours_levels_summary(const SunHoursMap& map, const std::string& indent = "");

/// Options of compute_sun_hours_map.
/// The largest SunHoursOptions::level_held_segments that `shadow series` and Python accept (a
/// trillion: beyond any machine's memory, so larger is a typo).
inline constexpr std::size_t kMaxLevelHeldSegments = 1000000000000;

struct SunHoursOptions {
  /// Worker threads (faces are computed in parallel); 0: every hardware thread; at most 1024.
  unsigned threads = 0;
  /// Called now and then from one thread at a time; `total` is the number of faces times the
  /// number of instants (lit regions), then the faces' overlays count once more each.
  std::function<void(const Progress&)> progress;
  /// Merge touching cells of equal hours into one region (fewer cells). When false every face
  /// of the arrangement is its own region.
  bool merge_equal = true;
  /// The threshold map's levels in hours (finite, >= 0, any order): for each, the exact region
  /// that gets at least that many hours (SunHoursMap::level_cells, SunHoursFace::level_areas).
  std::vector<double> levels;
  /// Compute the full map's cells (SunHoursMap::cells, SunHoursFace::areas); false with levels:
  /// only the threshold map.
  bool full = true;
  /// A face whose instants' boundaries hold more than this many segments is cut into vertical
  /// strips of its chart of about this many, overlaid apart and in parallel (a region crossing a
  /// strip's side is written as one region per strip; hours and areas do not change); 0: never.
  std::size_t strip_edges = 6000;
  /// The threshold map alone (`full` false): the instants' boundaries are overlaid in rounds,
  /// each keeping only the level boundaries and those of cells still undecided; the first round
  /// takes this many segments, later ones as many as keep each round's arrangement at about
  /// twice the boundaries kept (at least twice this). Smaller rounds hold less at
  /// once, larger ones sweep less often; the results are the same.
  std::size_t level_round_edges = 1000;
  /// The instants' lit regions are computed this many instants at a time (on every face, in
  /// parallel) and handed on before the next are computed; 0: all at once. The full map gathers
  /// every instant's boundaries on the faces (its strips are one sweep of them); so does the
  /// threshold map alone, exactly up to `level_held_segments` and in doubles past it, unless
  /// `stream_levels`; only the culling grids are per batch. Exact areas and cells do not depend
  /// on it.
  std::size_t instant_batch = 16;
  /// The threshold map alone (`full` false): feed each batch of instants to the strips' rounds
  /// as it comes and drop it, instead of gathering every instant's boundaries first (a face's
  /// strips are then chosen from the first 16 instants that cut it). It never holds every
  /// instant's boundaries, but it holds every strip's undecided cells at once, and those are
  /// about as large over the periods measured (docs/sun-hours-map.md, "Streamed instants"):
  /// more memory and time than gathering there. Exact areas do not depend on it; the cells may
  /// (which cells are decided in a round depends on the hours still to be fed).
  bool stream_levels = false;
  /// When set, also filled with the series table of the map's receiving faces (Scene::
  /// is_receiver; ascending: the rows) under the instants' lights (the columns): for directional
  /// and point lights every lit area, lit fraction and facing bit for bit what
  /// ShadowEngine::compute_series with Arithmetic::Exact reports for those faces and lights,
  /// taken from the same exact pass that makes the lit regions (each face-instant pair is
  /// computed once for the map and the table: `shadow series` leaves those faces out of its own
  /// pass). Its stats are that pass's counters for the rows; lit_area_error_bound is 0. Its
  /// memory is rows x instants x 25 bytes for the whole call.
  SeriesResult* series_table = nullptr;
  // Members are added here, at the end: the layout of those above stays as it was.
  /// The threshold map alone (`full` false, not streamed): about the most exact boundary
  /// segments it keeps between computing the lit regions and the rounds, packed (their points'
  /// exact rationals as GMP limbs, some 120-200 bytes a segment; besides a batch's, as CGAL
  /// curves of several hundred bytes, `instant_batch`, while they are taken). Every instant's boundaries are
  /// kept exactly while all faces' together stay within this; past it, the faces holding the
  /// most keep theirs in doubles (about 60 bytes a segment) and have them computed again when their
  /// strips' rounds take them, a wave of strips at a time (about half this many segments of
  /// theirs) and, within a wave, a band of instants at a time (about half, at least 4
  /// instants): memory bounded for the time of computing the lit regions once more per wave
  /// (docs/sun-hours-map.md, step 7). Exact areas do not depend on it, nor on which faces keep
  /// theirs; the cells may (a strip sweeps its sunniest instants first within a band).
  std::size_t level_held_segments = std::size_t{1} << 20;
};

/// The exact sun-hours map on `faces` (face ids, any order, duplicates ignored) of the engine's
/// scene under `instants`, reusing the engine's prepared faces. Degenerate faces get no cells.
/// @throws InputError for a face id out of range, an unusable light (zero or non-finite
/// direction, ...) or hours that are negative or not finite, naming `instants[i]`, or a level
/// that is negative or not finite, naming `levels[k]`.
SunHoursMap compute_sun_hours_map(const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                                  const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options = {});

/// Adds the threshold map of `levels` to `map` (a full map of the same faces and instants, for
/// instance one put together from parts computed apart): computes it with full = false and
/// moves its levels, level cells and per-face level areas into `map`.
/// @throws InputError as compute_sun_hours_map; std::invalid_argument when `map`'s faces are
/// not `faces`' (sorted, repeats dropped).
void add_sun_hours_levels(SunHoursMap& map, const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                          const std::vector<SunHoursInstant>& instants, const std::vector<double>& levels,
                          unsigned threads = 0);

/// The faces of the scene's `sun_hours_map` meshes (Scene::sun_hours_map), ascending.
/// @throws InputError for a mesh index out of range (possible only in scenes built in code).
std::vector<std::size_t> sun_hours_map_faces(const Scene& scene);

/// The faces of the meshes named in `mesh_names` (the CLI's `--sun-hours-map MESH[,MESH]`):
/// mesh names, or `type:<T>` for every mesh of CityJSON object type T (select_meshes()).
/// @throws InputError naming `what` (e.g. "--sun-hours-map") for a name that is no mesh's, or a
/// type no mesh has (listing the types present).
std::vector<std::size_t> sun_hours_map_faces(const Scene& scene, const std::vector<std::string>& mesh_names,
                                             const std::string& what = "--sun-hours-map");

/// The scene's sun instants above the horizon (Scene::sun_instants with a light), each weighing
/// hours_per_instant() of the period (shadow/series.hpp): its step, or for explicit `times` the
/// median gap between them, the same rule as the series' sun hours.
/// Empty when the scene has no `sun` block.
std::vector<SunHoursInstant> sun_hours_instants(const Scene& scene);

/// The instants of a series (sun_series()), each weighing its hours_per_instant, in the
/// series' order: a map whose columns are the series' (SunHoursOptions::series_table).
std::vector<SunHoursInstant> sun_hours_instants(const SunSeries& suns);

/// Parses a comma-separated list of levels in hours (the CLI's `--sun-hours-levels 2,4,6`).
/// @throws InputError naming `what` for an empty item, a non-number, or a value negative or
/// not finite.
std::vector<double> parse_sun_hours_levels(const std::string& text, const std::string& what = "--sun-hours-levels");

}  // namespace shadow
