// SPDX-License-Identifier: GPL-3.0-or-later
/// @file shadows.hpp
/// @brief Exact lit and shadowed polygons on every face for every light.
///
/// For each receiving face P and light L, the face is split into lit and shadowed "detail
/// polygons" (Atherton, Weiler and Greenberg, 1978), computed with exact rational arithmetic:
/// every other face Q is clipped to the part of space strictly between P's plane and the light,
/// projected from the light onto P's plane, and the projections are united in one aggregated
/// exact Boolean operation. Areas are exact rationals until they are rounded once to double.
/// See docs/algorithm.md and docs/numeric-contract.md.
#pragma once

#include <shadow/scene.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace shadow {

/// Progress of a long computation: `done` of `total` work items (face-light pairs).
struct Progress {
  std::size_t done = 0;
  std::size_t total = 0;
};

/// How the shadows on faces are computed.
enum class Arithmetic {
  /// Exact rationals throughout (CGAL Epeck): areas correct to the last digit. The default.
  Exact,
  /// The fast path: the same culling, clipping and projection in doubles, the union with
  /// Clipper on an integer grid fitted to each receiver's chart box. Every FaceLighting then
  /// carries `lit_area_error_bound`, a bound on |lit_area - exact lit_area|; receivers where the
  /// double route is ill-conditioned (grazing light, glancing crossings, casters nearly in the
  /// receiver's plane and partly in front of it) are computed exactly instead. 7-90 times
  /// faster than Exact on the benchmark cities (docs/benchmarks.md). See docs/numeric-contract.md, "The fast path".
  Fast,
};

/// How the engine runs, the same for one light (ShadowOptions) and for a series of lights
/// (SeriesOptions).
struct EngineOptions {
  /// Worker threads; 0 means every hardware thread. Results do not depend on it. At most 1024:
  /// more is an InputError (not clamped: a huge number is a mistake worth hearing about).
  unsigned threads = 0;
  /// Exact (default) or the fast path with error bounds. Plane shadows are always exact.
  Arithmetic arithmetic = Arithmetic::Exact;
  /// Called now and then from one thread at a time (never concurrently). May be empty. An
  /// exception it throws stops the computation (running work items included, within about a
  /// second) and comes out of the call. What `done` and `total` count is said by each call:
  /// face-light pairs (ShadowOptions), instants (SeriesOptions).
  std::function<void(const Progress&)> progress;
  /// Tiles (docs/tiles.md): a receiver that faces the light, is an axis-aligned rectangle in its
  /// chart (a city's ground, most walls and roofs) and has more candidate casters than this is
  /// split into square tiles of its chart, each a separate work item that sees only the casters
  /// whose shadows reach it, so that one large receiver does not hold the other threads up.
  /// Areas are unchanged to the last bit (the tiles' exact areas are summed before rounding
  /// once); fragments are cut at tile borders. 0: never split. Arithmetic::Exact only.
  std::size_t tile_casters = 4000;
  /// The same for Arithmetic::Fast, whose receivers are cheaper. Tiles have their own grids: the
  /// fast areas of a split receiver change within their bounds. 0: never split.
  std::size_t fast_tile_casters = 20000;
};

/// Options for computing shadows on faces. `progress` (EngineOptions) counts face-light pairs;
/// the plane shadows count nothing but call it too, about every 100 ms: compute_shadows with the
/// faces' last count, ShadowEngine::compute_planes and compute_plane_shadows with 0 of 0.
struct ShadowOptions : EngineOptions {
  /// Produce the 3D lit/shadow polygons. When false only areas are computed (cheaper).
  bool polygons = true;
  /// Indices of the scene lights to compute; empty means every light. An index that is not a
  /// scene light, or an unusable light (zero or non-finite direction, ...), is an InputError,
  /// for the faces and the planes alike.
  std::vector<std::size_t> lights;
  /// compute_shadows() also computes the shadows on the scene's planes (Blinn projection).
  bool planes = true;
  /// Half the side of the square window, centred under the scene, in which plane shadows are
  /// computed (a point light at the height of some geometry casts shadows without end).
  /// 0 means ten times the diagonal of the scene's bounding box. A plane's own `window` wins.
  double plane_window = 0.0;
};

/// Where a cell of a face lies with respect to an extended light (Light::is_extended): it sees
/// all of the light, part of it, or none of it. `Hard` marks the cells of a point light.
enum class LightRegion : int { Hard = -1, FullyLit = 0, Penumbra = 1, Umbra = 2 };

/// One simple polygon of a face that is wholly lit or wholly shadowed by one light.
/// A lit or shadowed region with holes is split into several simple cells that share
/// `fragment_id`. The polygon has the orientation of its face.
struct Fragment {
  std::size_t face_id = 0;
  std::size_t light_id = 0;
  std::size_t fragment_id = 0;  ///< numbers connected regions; pieces of one region share it
  bool lit = false;
  std::vector<glm::dvec3> polygon;
  double area = 0.0;            ///< exact area of this cell, rounded once
  /// Extended lights: the region this cell lies in (docs/area-lights.md); Hard otherwise.
  LightRegion region = LightRegion::Hard;
  /// Extended lights: the visible fraction (0..1) of the light at each vertex of `polygon`, in
  /// order; empty for point lights.
  std::vector<double> visibility;
  /// Extended lights: the irradiance (W/m^2) delivered through the visible part of the light at
  /// each vertex of `polygon` (light_irradiance, taken as the same limit from inside the
  /// fragment as `visibility`), computed in the same pass; empty for point lights.
  std::vector<double> irradiance;
};

/// Lit and shadowed areas of one receiving face under one light.
struct FaceLighting {
  std::size_t face_id = 0;
  std::size_t light_id = 0;
  double area = 0.0;          ///< area of the face
  double lit_area = 0.0;      ///< exact lit area, rounded once
  double shadow_area = 0.0;   ///< exact shadowed area (area - lit_area exactly), rounded once
  double lit_fraction = 0.0;  ///< exact lit_area / area, rounded once (0 for zero-area faces)
  bool faces_light = false;   ///< the face's front looks toward the light
  /// Bound on |lit_area - the exact lit area| (also on shadow_area's error): 0 for the exact
  /// path and for receivers the fast path decided exactly (Arithmetic::Fast otherwise).
  double lit_area_error_bound = 0.0;
  /// Area of cells left out of `fragments` because rounding their vertices to doubles would
  /// have made them degenerate (fewer than 3 distinct vertices, zero area, or not simple):
  /// slivers no wider than a few ulps of their coordinates (docs/numeric-contract.md, "Output").
  /// The fragments of (face, light) plus this add up to `area`. 0 without polygons.
  double dropped_area = 0.0;
  /// Extended lights (Light::is_extended): the exact area of the points that see all of the
  /// light, of those that see part of it, and of those that see none of it (docs/area-lights.md
  /// states which are exact and which are certified bounds). For a point light they are the lit
  /// area, 0 and the shadowed area.
  double fully_lit_area = 0.0;
  double penumbra_area = 0.0;
  double umbra_area = 0.0;
};

/// The shadow that the scene casts on one of its planes from one light: the union of the
/// Blinn projections of every face's part strictly between the plane and the light.
struct PlaneShadow {
  std::size_t plane_id = 0;
  std::size_t light_id = 0;
  /// Simple polygons on the plane, counter-clockwise seen from the side the plane's normal points
  /// to; a region with holes is split into several cells that share a `region_id`.
  std::vector<std::vector<glm::dvec3>> polygons;
  std::vector<std::size_t> region_id;  ///< one per polygon
  std::vector<double> polygon_area;    ///< one per polygon, exact, rounded once
  double area = 0.0;                   ///< exact shadow area inside the window, rounded once
  double window_half_size = 0.0;       ///< the window the shadow was computed in
  /// Some shadow reaches the window's edge: the true shadow extends beyond it (and `area` is
  /// that of its part inside the window).
  bool reaches_window = false;
};

/// Counters that show how much work culling saved.
struct ShadowStats {
  std::uint64_t receivers = 0;          ///< face-light pairs considered
  std::uint64_t back_facing = 0;        ///< pairs in attached shadow (no clipping needed)
  /// Occluder-receiver pairs after culling in doubles (boxes, the receiver's slab and prism). A
  /// convex solid that the engine casts as one hull (a directional light on an exactly planar
  /// receiver) counts once, as in casting_pairs; otherwise each of its faces that passes counts.
  /// Areas only, a box receiver, a directional light: a receiver that one solid shades whole is
  /// decided without the search. The fast path counts that one pair (docs/numeric-contract.md);
  /// the exact engine counts the solids it cast first, the covering one last
  /// (docs/algorithm.md), and those casts are in casting_pairs.
  std::uint64_t candidate_pairs = 0;
  std::uint64_t casting_pairs = 0;      ///< pairs whose exact projection was non-empty
  std::uint64_t unshadowed = 0;         ///< front-facing receivers with nothing in front (no clipping)
  /// Arithmetic::Fast only: receivers the fast path handed to the exact engine because the double
  /// route was ill-conditioned there (grazing light, glancing crossings, nearly coplanar casters).
  std::uint64_t fast_exact_fallbacks = 0;
  /// Arithmetic::Fast only: cast polygons that collapsed to zero area on the integer grid (their
  /// true area is within the bound; they are dropped).
  std::uint64_t fast_collapsed = 0;
  /// Extended lights (docs/area-lights.md): face-light pairs whose regions were computed.
  std::uint64_t area_receivers = 0;
  /// Extended lights: pairs where two or more occluder pieces cast on the face, so that
  /// `umbra_area` is a certified inner bound (the union of each piece's umbra) rather than exact.
  std::uint64_t area_umbra_bounded = 0;
  /// Extended lights: pairs whose face sees part of the light from behind its own plane (the
  /// light crosses it): nowhere fully lit, the umbra taken for the part of the light in front.
  std::uint64_t area_light_straddles = 0;
  /// Area lights and disks: pairs where part of the face lies behind the light's plane, whose
  /// lit_area (the centre's) was cut to the light's emitting side (docs/area-lights.md).
  std::uint64_t area_centre_behind = 0;
  /// Extended lights: occluder pieces cast by projection from the light's vertices (the piece is
  /// nearer to the receiver's plane than the whole light) and by separating planes (the rest).
  std::uint64_t area_projection_pieces = 0;
  std::uint64_t area_plane_pieces = 0;
  /// Fragment cells (triangles of a cell that rounding broke) left out because they collapse in
  /// doubles; their exact area is in FaceLighting::dropped_area (docs/numeric-contract.md).
  std::uint64_t dropped_cells = 0;
  /// Receivers split into tiles (ShadowOptions::tile_casters, fast_tile_casters), and the tiles
  /// they were split into. A split receiver counts once in `receivers` (and in `unshadowed` when
  /// no tile has a shadow); candidate and casting pairs are counted per tile.
  std::uint64_t tiled_receivers = 0;
  std::uint64_t tiles = 0;
  /// CPU time (per-thread clock) of the work items: whole receivers, tiles, and the culling of
  /// a receiver that was then split. Summed; `longest_item_seconds` is the largest single one
  /// (operator+= takes the maximum). Receivers are taken in runs of 16, and a thread's CPU time is
  /// read when it takes its first run and when it takes no more (the per-thread clock is a
  /// system call, a quarter of a small item's cost): a receiver's own time is its share of the
  /// thread's time-stamp counter ticks over the call times that CPU time (its wall time scaled by
  /// the thread's CPU / wall ratio); tiles are timed one by one. They vary from
  /// run to run, unlike the counts.
  double item_seconds = 0;
  double longest_item_seconds = 0;

  /// Adds every counter of `other` (per-thread or per-receiver counts summed into a total).
  ShadowStats& operator+=(const ShadowStats& other) {
    receivers += other.receivers;
    back_facing += other.back_facing;
    candidate_pairs += other.candidate_pairs;
    casting_pairs += other.casting_pairs;
    unshadowed += other.unshadowed;
    fast_exact_fallbacks += other.fast_exact_fallbacks;
    fast_collapsed += other.fast_collapsed;
    area_receivers += other.area_receivers;
    area_umbra_bounded += other.area_umbra_bounded;
    area_light_straddles += other.area_light_straddles;
    area_centre_behind += other.area_centre_behind;
    area_projection_pieces += other.area_projection_pieces;
    area_plane_pieces += other.area_plane_pieces;
    dropped_cells += other.dropped_cells;
    tiled_receivers += other.tiled_receivers;
    tiles += other.tiles;
    item_seconds += other.item_seconds;
    longest_item_seconds = longest_item_seconds > other.longest_item_seconds ? longest_item_seconds
                                                                             : other.longest_item_seconds;
    return *this;
  }
};

/// The entry for (face_id, light_id) in `lighting` sorted by (face_id, light_id), as every
/// result of libshadow is; nullptr when there is none. Binary search.
[[nodiscard]] const FaceLighting* find_lighting(const std::vector<FaceLighting>& lighting, std::size_t face_id,
                                                std::size_t light_id);

/// Everything computed for a scene's faces.
struct ShadowResult {
  /// One entry per receiving face and computed light, ordered by face_id then light_id.
  std::vector<FaceLighting> lighting;
  /// Lit and shadowed polygons, ordered by face_id, then light_id, then fragment_id.
  std::vector<Fragment> fragments;
  /// Shadows on the scene's planes (compute_shadows with options.planes), by plane then light.
  std::vector<PlaneShadow> plane_shadows;
  ShadowStats stats;
  /// The arithmetic the faces were computed with (options.arithmetic).
  Arithmetic arithmetic = Arithmetic::Exact;

  /// The entry for (face, light), or nullptr when that pair was not computed.
  [[nodiscard]] const FaceLighting* find(std::size_t face_id, std::size_t light_id) const;
};

/// Options for a series of lights computed together (ShadowEngine::compute_series): the many
/// suns of a day or a year. Areas only: no polygons, no plane shadows. `progress`
/// (EngineOptions) counts instants (lights) finished, never decreasing, ending at `total`; within
/// a batch of instants it moves through both rounds (the receivers, then the tiles of split
/// receivers), in proportion to the time the previous batch spent in each (docs/tiles.md).
/// Tiles work exactly as for ShadowOptions.
struct SeriesOptions : EngineOptions {
  /// Receiving faces whose rows another pass fills (SunHoursOptions::series_table): they stay
  /// rows of the table, in place, but are not computed and their entries are left 0 for the
  /// caller to write. Any order; ids that are not receiving faces are ignored.
  std::vector<std::size_t> given_faces;
};

/// Lit areas of every receiving face under every light of a series: a faces x instants table.
/// Entry (row, instant) is what `compute(lights[instant], id, {polygons = false})` reports for
/// face `faces[row]`, bit for bit, with the same tile thresholds (SeriesOptions::tile_casters,
/// fast_tile_casters; exact tiles change no bit); 0 in the rows of SeriesOptions::given_faces.
struct SeriesResult {
  std::vector<std::size_t> faces;  ///< the receiving faces, ascending: the rows
  std::size_t instants = 0;        ///< the columns: one per light, in the order given
  std::vector<double> area;        ///< per row: the face's exact area, rounded once
  /// Row-major (row * instants + instant): exact lit area rounded once, the lit fraction, whether
  /// the face's front looks toward the light (1/0), and the fast path's bound (0 when exact).
  std::vector<double> lit_area;
  std::vector<double> lit_fraction;
  std::vector<unsigned char> faces_light;
  std::vector<double> lit_area_error_bound;
  ShadowStats stats;                          ///< summed over every face and instant
  Arithmetic arithmetic = Arithmetic::Exact;  ///< SeriesOptions::arithmetic

  /// Index of (row, instant) in the row-major arrays.
  [[nodiscard]] std::size_t at(std::size_t row, std::size_t instant) const { return row * instants + instant; }

  /// Sizes the four row-major arrays to faces.size() x instants entries, every one 0.
  void zero_entries() {
    const std::size_t cells = faces.size() * instants;
    lit_area.assign(cells, 0.0);
    lit_fraction.assign(cells, 0.0);
    faces_light.assign(cells, 0);
    lit_area_error_bound.assign(cells, 0.0);
  }
};

/// One call: every selected light on every receiving face, and (options.planes) on every plane.
/// The scene should have been validated (load_scene does it; see validate_scene); even if it was
/// not, non-finite coordinates and coordinates beyond max_coordinate (scene_io.hpp) are found
/// here and thrown as InputError naming the face's source.
/// @throws InputError if a light, face or option is unusable (zero direction, NaN, threads > 1024, ...).
ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options = {});

class ShadowEngine;

/// compute_shadows on an engine prepared already (the faces, then with options.planes the
/// planes; while the planes run, which count nothing, options.progress hears the faces' last
/// count again, about every 100 ms, so that it can still stop the call). For callers that
/// prepare the engine themselves (to report or interrupt the preparation).
/// @throws InputError as compute_shadows.
ShadowResult compute_shadows(const ShadowEngine& engine, const ShadowOptions& options);

/// The exact shadows on the scene's planes for the selected lights (Blinn's projection: see
/// blinn.hpp), ordered by plane then light. Independent of the per-face engine: the two are
/// checked against each other in the tests. Checks coordinates and lights like compute_shadows.
/// @throws InputError
std::vector<PlaneShadow> compute_plane_shadows(const Scene& scene, const ShadowOptions& options = {});

/// Reusable engine over one scene: exact face data (planes, charts, convex pieces, bounding
/// boxes) is prepared once and reused for every light, e.g. many sun positions over a day.
class ShadowEngine {
 public:
  /// Prepares the scene on `threads` threads (0: every hardware thread, at most 1024). The
  /// scene must outlive the engine and stay unchanged. `progress`, when given, is called about
  /// every 100 ms from the calling thread with `done` of `total` = 3 preparation stages (the
  /// faces, the culling grid, the convex solids) and once at the end; an exception it throws
  /// stops the preparation and comes out of the constructor (how Python's Ctrl-C stops it).
  /// @throws InputError for a non-finite or out-of-range coordinate (scene_io.hpp's
  /// max_coordinate) of a face or plane, named by the face's source, and for threads > 1024.
  explicit ShadowEngine(const Scene& scene, unsigned threads = 0,
                        const std::function<void(const Progress&)>& progress = {});
  ~ShadowEngine();
  ShadowEngine(ShadowEngine&&) noexcept;
  ShadowEngine& operator=(ShadowEngine&&) noexcept;
  ShadowEngine(const ShadowEngine&) = delete;
  ShadowEngine& operator=(const ShadowEngine&) = delete;

  /// The scene's own lights (options.lights selects among them).
  [[nodiscard]] ShadowResult compute(const ShadowOptions& options = {}) const;

  /// Any light, not necessarily in the scene; results carry `light_id`.
  [[nodiscard]] ShadowResult compute(const Light& light, std::size_t light_id,
                                     const ShadowOptions& options = {}) const;

  /// Lit areas of every receiving face under each of `lights` (the suns of a period), without
  /// a ShadowResult per light: the prepared faces, light-space grids and per-thread caster
  /// lists are shared by the instants (the per-thread exact faces too, up to 4,096 faces a
  /// thread; above that they are rebuilt as needed), and the work is spread over instants and
  /// receivers together.
  /// Values equal compute(lights[i], i, {polygons = false}) bit for bit, with the same tile
  /// thresholds: a receiver with more candidates than the threshold at an instant is split into
  /// tiles, as compute() splits it. Lights are checked like compute(light, ...) (named `lights[i]`).
  /// @throws InputError for an unusable light or threads > 1024
  [[nodiscard]] SeriesResult compute_series(const std::vector<Light>& lights,
                                            const SeriesOptions& options = {}) const;

  /// Shadows on the scene's planes (Blinn), reusing the engine's prepared faces; the same as
  /// compute_plane_shadows(scene, options).
  [[nodiscard]] std::vector<PlaneShadow> compute_planes(const ShadowOptions& options = {}) const;

  /// Exact area of a face, rounded once (0 for degenerate faces).
  [[nodiscard]] double face_area(std::size_t face_id) const;

  /// What the engine prepared, for the library's own computations over it (the sun-hours map,
  /// vector views, irradiance); an incomplete type outside the library.
  struct Impl;
  [[nodiscard]] const Impl& impl() const noexcept { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace shadow
