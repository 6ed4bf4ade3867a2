// SPDX-License-Identifier: GPL-3.0-or-later
// The exact shadow engine (Atherton-Weiler-Greenberg, made exact).
//
// For a receiving face P that faces the light, a point X of P is in shadow exactly when the
// open segment from X to the light meets another face. That segment lies in the open slab
// between P's plane and the light, so
//
//   shadow(P) = P  intersected with  union over Q of  project_P(Q  clipped to that slab),
//
// where project_P is the projection from the light onto P's plane (Blinn's matrix for P's
// plane). No depth order is needed; cyclic overlap and interpenetration need no special case.
// Clipping Q also to the pyramid (point light) or prism (directional light) over P's chart
// bounding box keeps the projection finite and the union small. Everything is done with exact
// rationals (Epeck) in P's 2D chart; doubles appear only in culling (conservatively) and at
// the output.
//
// This file is the engine: ShadowEngine prepares the faces once (core/, exact/), dispatches each
// receiver to the fast path (fast/, Arithmetic::Fast) or the exact computation
// (exact/exact_receiver.cpp, also the fast path's fallback), and assembles the result;
// compute_shadows and find_lighting.
#include "engine/engine_impl.hpp"
#include "core/spatial_order.hpp"

#include "arealight/area_receiver.hpp"
#include "core/culling.hpp"
#include "core/dyadic.hpp"
#include "core/input_checks.hpp"
#include "core/lights.hpp"
#include "arealight/light_visibility.hpp"
#include "runtime/first_touch.hpp"
#include "runtime/parallel.hpp"
#include "core/tiles.hpp"
#include "engine/engine_access.hpp"
#include "exact/convex_solids.hpp"
#include "exact/exact_faces.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "fast/fast_receiver.hpp"
#include "geometry/unit_vector.hpp"
#include "planes/plane_shadows.hpp"

#include <shadow/shadows.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace shadow {

const FaceLighting* find_lighting(const std::vector<FaceLighting>& lighting, std::size_t face_id,
                                  std::size_t light_id) {
  auto it = std::lower_bound(lighting.begin(), lighting.end(), std::make_pair(face_id, light_id),
                             [](const FaceLighting& l, const std::pair<std::size_t, std::size_t>& key) {
                               return std::make_pair(l.face_id, l.light_id) < key;
                             });
  if (it == lighting.end() || it->face_id != face_id || it->light_id != light_id) return nullptr;
  return &*it;
}

const FaceLighting* ShadowResult::find(std::size_t face_id, std::size_t light_id) const {
  return find_lighting(lighting, face_id, light_id);
}


// =============================================================================================

// ShadowEngine::Impl: engine/engine_impl.hpp (engine/series.cpp reads it too).


ShadowEngine::ShadowEngine(const Scene& scene, unsigned threads, const std::function<void(const Progress&)>& progress)
    : impl_(std::make_unique<Impl>()) {
  // Scenes built in code may not have been validated: NaN or huge coordinates would reach GMP
  // (SIGFPE) or the double culling. One pass over the vertices.
  shadow::detail::check_scene_numbers(scene);
  // Three stages (faces, culling, convex solids), each of parallel_for calls that tick `progress`
  // while they wait: an exception it throws (Ctrl-C in Python) stops the preparation.
  constexpr std::size_t kStages = 3;
  std::size_t stage = 0;
  runtime::TickScope ticks(progress ? std::function<void()>([&] { progress(Progress{stage, kStages}); })
                                 : std::function<void()>());
  threads = runtime::resolve_threads(runtime::checked_threads(threads));
  impl_->scene = &scene;
  const std::size_t n = scene.faces.size();
  impl_->prep.resize(n);
  impl_->face_area.assign(n, 0.0);
  // The bits every coordinate spans (integer charts, exact/scaled_chart.hpp), per thread.
  std::vector<core::BitSpan> spans(threads);
  // Faces in blocks: handed out one by one, a million faces' two shared counters per face
  // (taken and done) bounced between the cores. At least 64 blocks a thread: a few faces of
  // thousands of vertices each (seconds in all) stay spread over the threads, and a stop request
  // is seen between them.
  auto prepare = [&](unsigned thread, std::size_t f) {
    const Face& face = scene.faces[f];
    for (const glm::dvec3& v : face.vertices)
      for (int k = 0; k < 3; ++k) spans[thread].add(v[k]);
    core::FacePrep& prep = impl_->prep[f];
    if (face.degenerate || face.vertices.size() < 3) {
      prep.degenerate = true;
      return;
    }
    prep = exact::prepare_face(face.vertices);
    if (prep.degenerate) return;
    if (prep.exactly_planar) {  // plain integers: no lazy exact face (its DAG, a futex call per node)
      if (const std::optional<double> area = exact::planar_face_area(face.vertices, prep)) {
        impl_->face_area[f] = *area;
        return;
      }
    }
    const exact::ExactFace ef = exact::make_exact_face(face.vertices, prep);
    impl_->face_area[f] = exact::area_3d(ef.chart_area, ef.area_scale_squared);
  };
  runtime::parallel_for_blocks(n, runtime::block_of(n, threads), threads,
                               [&](unsigned thread, std::size_t, std::size_t begin, std::size_t end) {
                                 for (std::size_t f = begin; f < end; ++f) prepare(thread, f);
                               });
  core::BitSpan span;
  for (const core::BitSpan& s : spans) span.add(s);
  impl_->chart_least_bit = core::chart_least_bit(span);
  stage = 1;
  impl_->cull = core::make_cull_scene(scene, impl_->prep, threads);
  stage = 2;
  impl_->solids = exact::find_convex_solids(scene, impl_->prep, impl_->solid_of, threads, &impl_->cull.closed_outward);
  std::vector<signed char>& outward = impl_->cull.closed_outward;
  if (std::all_of(outward.begin(), outward.end(), [](signed char o) { return o == 0; })) outward = {};  // no look-up per caster
  stage = kStages;
  if (progress) progress(Progress{stage, kStages});
}

ShadowEngine::~ShadowEngine() = default;
ShadowEngine::ShadowEngine(ShadowEngine&&) noexcept = default;
ShadowEngine& ShadowEngine::operator=(ShadowEngine&&) noexcept = default;

double ShadowEngine::face_area(std::size_t face_id) const { return impl_->face_area.at(face_id); }

std::vector<PlaneShadow> ShadowEngine::compute_planes(const ShadowOptions& options) const {
  // Plane shadows count nothing: 0 of 0, about every 100 ms, so that the callback can stop them.
  const runtime::TickScope ticks(options.progress ? std::function<void()>([&] { options.progress(Progress{0, 0}); })
                                               : std::function<void()>());
  return planes::plane_shadows(*impl_->scene, impl_->prep, impl_->solids, impl_->solid_of, options);
}


namespace {

/// The tile counts that a split receiver's tiles add to the totals: the candidate and casting
/// pairs of every tile, and the fast path's counters; the receiver itself counts once.
void add_tile_counts(ShadowStats& total, const ShadowStats& tile) {
  total.candidate_pairs += tile.candidate_pairs;
  total.casting_pairs += tile.casting_pairs;
  total.fast_exact_fallbacks += tile.fast_exact_fallbacks;
  total.fast_collapsed += tile.fast_collapsed;
  total.dropped_cells += tile.dropped_cells;
}

}  // namespace

void ShadowEngine::Impl::compute_light(const Light& light_in, std::size_t light_id,
                                       const ShadowOptions& options, std::vector<ThreadState>& workers,
                                       const std::vector<std::size_t>& receivers,
                                       ItemTable& items, std::size_t progress_base,
                                       std::size_t progress_total) const {
  using namespace exact;
  if (light_in.is_extended()) {
    compute_extended_light(light_in, light_id, options, workers, receivers, items, progress_base, progress_total);
    return;
  }
  const unsigned threads = static_cast<unsigned>(workers.size());
  std::optional<core::LightSpaceGrid> grid;
  if (light_in.type == LightType::Directional) {
    grid.emplace(cull, prep, light_in.to_light, &solid_of, threads);
    if (engine_detail::outlines_pay(options.arithmetic, !options.polygons, receivers.size(), solids.size())) grid->find_outlines(solids, threads);
  }

  // Areas only under a directional light: the receivers certainly turned away from it get their
  // attached shadow here, with no work item (as in compute_series).
  std::vector<std::size_t> live;  // the other receivers (indices into `receivers`)
  const bool prefilter = grid && !options.polygons;
  if (prefilter)
    engine_detail::split_turned_away(
        cull, receivers.size(), {geometry::unit(light_in.to_light)}, [&](std::size_t r) { return receivers[r]; },
        [&](std::size_t r, std::size_t) {
          FaceLighting& out = items[r].lighting;
          out = FaceLighting{};
          out.face_id = receivers[r];
          out.light_id = light_id;
          out.area = face_area[receivers[r]];
          out.shadow_area = out.area;
        },
        live, workers);
  const std::size_t turned_away = prefilter ? receivers.size() - live.size() : 0;
  // The rest along a curve through the scene (core/spatial_order.hpp): neighbours share casters.
  const std::vector<std::size_t> order = core::spatial_order(
      cull, solid_of, solids, receivers.size() - turned_away,
      [&](std::size_t i) { return receivers[prefilter ? live[i] : i]; }, threads);
  auto receiver_of = [&](std::size_t i) { return prefilter ? live[order[i]] : order[i]; };

  // Progress in receivers done: a receiver split into tiles counts when its tiles are done
  // (in proportion during the tile round).
  engine_detail::ForwardProgress report_receivers(options.progress, progress_base, progress_total);
  RoundProgress progress;
  if (report_receivers) {
    progress.first = [&](std::size_t done) { report_receivers(turned_away + done); };
    progress.tiles = [&](std::size_t done, std::size_t total, std::size_t split) {
      report_receivers(receivers.size() - split + (total == 0 ? split : done * split / total));
    };
  }
  std::vector<std::optional<ExactLight>> lights(threads);
  ItemMode mode;
  mode.fast = options.arithmetic == Arithmetic::Fast;
  mode.polygons = options.polygons;
  mode.split_above = mode.fast ? options.fast_tile_casters : options.tile_casters;
  const core::LightSpaceGrid* grid_ptr = grid ? &*grid : nullptr;
  compute_rounds(
      receivers.size() - turned_away,
      [&](std::size_t i) { return WorkItem{receivers[receiver_of(i)], light_id, &light_in, grid_ptr, 0}; }, mode,
      workers, [&](unsigned wi, std::size_t) -> std::optional<ExactLight>& { return lights[wi]; },
      [&](std::size_t i, Item& item) { items[receiver_of(i)] = std::move(item); }, progress);
}

ShadowEngine::Impl::Item ShadowEngine::Impl::compute_item(ThreadState& w, std::optional<exact::ExactLight>& exact_light,
                                                          std::size_t f, std::size_t light_id, const Light& light_in,
                                                          const core::LightSpaceGrid* grid, const ItemMode& mode,
                                                          const core::FacePrep* tile, ShadowStats& stats) const {
  const core::PreparedScene context = prepared();
  w.exact.trim(exact::kExactFaceCache);
  core::TileRequest tiles;
  tiles.tile = tile;
  if (!tile) tiles.split_above = mode.split_above;
  Item item;
  if (mode.fast) {
    std::size_t split = 0;
    const fast::Outcome outcome = fast::compute_receiver(context, w.fast, f, light_id, light_in, grid, mode.polygons,
                                                         item.lighting, item.fragments, stats, tiles, split);
    if (outcome == fast::Outcome::Done) return item;
    if (outcome == fast::Outcome::Split) {
      item = Item{};
      item.split_candidates = split;
      return item;
    }
    ++stats.fast_exact_fallbacks;  // ill-conditioned in doubles: decided exactly below
    item = Item{};
  }
  if (!exact_light) exact_light = engine_detail::to_exact_light(light_in);
  const int side = engine_detail::receiver_side(context, w.exact, f, light_in, *exact_light);
  // A fast split request that falls back: the exact engine may split it too (its threshold).
  core::TileRequest exact_tiles = tiles;
  if (!tiles.tile) exact_tiles.split_above = mode.fast ? 0 : mode.split_above;
  return exact::compute_exact_receiver(context, w.exact, f, light_id, *exact_light, side, light_in, grid,
                                       mode.polygons, stats, exact_tiles);
}

namespace {

/// A tiled face's exact measure from its n tiles (compute_splits): their exact shadowed chart
/// areas summed, then rounded once as for the whole face (exact_receiver.cpp,
/// unite_and_measure): the same bits. Where some tile's shadow is enclosed instead
/// (ExactReceiverJob::measure_tile_enclosed), the enclosures added pin the doubles
/// (EnclosedMeasure::measure_between); false where they do not, `out` unchanged.
template <class TileItem>
bool measure_exact_tiles(const TileItem* tiles, std::size_t n, const exact::EQ& chart, const exact::EQ& scale,
                         exact::EnclosedMeasure& enclosed_measure, FaceLighting& out) {
  exact::EQ shadow_chart(0), width(0);
  bool enclosed = false;
  for (std::size_t t = 0; t < n; ++t) {
    if (tiles[t].tile_shadow_chart_area) shadow_chart += *tiles[t].tile_shadow_chart_area;
    if (tiles[t].tile_shadow_width) {
      width += *tiles[t].tile_shadow_width;
      enclosed = true;
    }
  }
  if (enclosed) return enclosed_measure.measure_between(chart, scale, shadow_chart, width, out);
  exact::EQ lit, scratch;
  exact::measure_lit_and_shadow(chart, scale, shadow_chart, lit, scratch, out);
  return true;
}

}  // namespace

void ShadowEngine::Impl::compute_splits(
    std::vector<SplitReceiver>& splits, const ItemMode& mode, std::vector<ThreadState>& workers,
    const ExactLightSlot& exact_light,
    const std::function<void(std::size_t, std::size_t)>& progress) const {
  using namespace exact;
  const unsigned threads = static_cast<unsigned>(workers.size());
  const bool fast = mode.fast;
  struct Tile {
    std::size_t s;  // index into `splits`
    core::FacePrep prep;
  };
  std::vector<Tile> tiles;
  std::vector<std::size_t> first_tile;  // per split receiver, then the end
  // Tiles of about kTileCandidates candidates each (fewer when the threshold is lower); the fast
  // path's half as many: its items are cheaper, and under a low sun the tiles downstream of long
  // shadows cost several times the others.
  const std::size_t target = fast ? core::kTileCandidates / 2 : core::kTileCandidates;
  const std::size_t per_tile = std::max<std::size_t>(1, std::min(mode.split_above / 2, target));
  // Each split receiver's cells on its own thread (placing them against a long outline is a
  // predicate per cell and outline edge), then in split order: the tiles do not depend on the
  // thread count.
  std::vector<std::vector<core::FacePrep>> cells(splits.size());
  runtime::parallel_for(splits.size(), threads, [&](unsigned, std::size_t s) {
    const std::size_t f = splits[s].face;
    // A face that is not its own chart box: cells are placed against its outline, exactly, and
    // cut for its candidates spread over the face, not over its box (the cells outside it are
    // dropped: a triangle's would otherwise get half as many tiles, each twice the work).
    const core::PlaceCell place = [&](const std::array<double, 2>& lo, const std::array<double, 2>& hi) {
      return exact::place_cell(scene->faces[f].vertices, prep[f], lo, hi);
    };
    std::size_t candidates = splits[s].out->split_candidates;
    if (!prep[f].chart_is_box) {
      const double fill = core::box_fill(scene->faces[f].vertices, prep[f]);
      candidates = static_cast<std::size_t>(static_cast<double>(candidates) / std::max(fill, 1.0 / 16));
    }
    cells[s] = core::make_tiles(prep[f], candidates, per_tile, core::kMaxTiles, place);
  });
  for (std::size_t s = 0; s < splits.size(); ++s) {
    first_tile.push_back(tiles.size());
    for (core::FacePrep& t : cells[s]) tiles.push_back({s, std::move(t)});
  }
  first_tile.push_back(tiles.size());
  std::vector<Item> tile_items(tiles.size());
  std::vector<ShadowStats> tile_stats(tiles.size());
  std::function<void(std::size_t)> report_tiles;
  if (progress) report_tiles = [&](std::size_t done) { progress(done, tiles.size()); };
  runtime::parallel_for(
      tiles.size(), threads,
      [&](unsigned wi, std::size_t t) {
        ThreadState& w = workers[wi];
        const SplitReceiver& sr = splits[tiles[t].s];
        const double t0 = engine_detail::thread_cpu_seconds();
        tile_items[t] = compute_item(w, exact_light(wi, sr.light_slot), sr.face, sr.light_id, *sr.light, sr.grid, mode,
                                     &tiles[t].prep, tile_stats[t]);
        engine_detail::count_item(w.stats, engine_detail::thread_cpu_seconds() - t0);
      },
      report_tiles);

  // Merge each split receiver's tiles into its item (on this thread only).
  const core::PreparedScene exact_context = prepared();
  ThreadState& w0 = workers[0];
  for (std::size_t s = 0; s < splits.size(); ++s) {
    const SplitReceiver& sr = splits[s];
    const std::size_t f = sr.face;
    const std::size_t t0 = first_tile[s], t1 = first_tile[s + 1];
    Item& item = *sr.out;
    item = Item{};
    FaceLighting& out = item.lighting;
    out.face_id = f;
    out.light_id = sr.light_id;
    out.area = face_area[f];
    ShadowStats& stats = w0.stats;
    if (t1 == t0) {  // the face could not be cut (a sliver, or one cell meets it): computed whole
      // Without a threshold: compute_item applies mode.split_above to a whole exact face, which
      // would only ask for tiles again and leave the face's item unfilled (lit area 0).
      ItemMode whole_mode = mode;
      whole_mode.split_above = 0;
      item = compute_item(w0, exact_light(0, sr.light_slot), f, sr.light_id, *sr.light, sr.grid, whole_mode, nullptr,
                          stats);
      continue;
    }
    ++stats.receivers;
    ++stats.tiled_receivers;
    stats.tiles += t1 - t0;
    bool unshadowed = true, exact_tiles = true;
    for (std::size_t t = t0; t < t1; ++t) {
      add_tile_counts(stats, tile_stats[t]);
      unshadowed &= tile_stats[t].unshadowed == 1;
      exact_tiles &= tile_items[t].tile_exact;
    }
    out.faces_light = true;
    if (unshadowed) ++stats.unshadowed;
    // Fragments: the tiles' in order, fragment ids renumbered (cells cut at tile borders stay
    // separate fragments: docs/tiles.md).
    std::size_t next_id = 0;
    double dropped = 0;
    for (std::size_t t = t0; t < t1; ++t) {
      engine_detail::append_renumbered(tile_items[t].fragments, item.fragments, next_id);
      dropped += tile_items[t].lighting.dropped_area;
    }
    out.dropped_area = dropped;
    if (!fast || exact_tiles) {
      if (unshadowed) {
        out.lit_area = out.area;
        out.lit_fraction = 1.0;
        continue;
      }
      const auto [chart, scale] = w0.exact.exact_areas(exact_context, f);
      if (measure_exact_tiles(tile_items.data() + t0, t1 - t0, *chart, *scale, w0.exact.enclosed_measure, out))
        continue;
      // Not pinned (next to a rounding boundary): the face computed whole, exactly (by the exact
      // engine also on the fast path, whose tiles all fell back to it here), its counts left out
      // (the tiles' are in).
      ItemMode whole_mode = mode;
      whole_mode.split_above = 0;
      whole_mode.fast = false;
      ShadowStats again;
      item = compute_item(w0, exact_light(0, sr.light_slot), f, sr.light_id, *sr.light, sr.grid, whole_mode, nullptr,
                          again);
      continue;
    }
    // Fast: each tile's shadow is within its bound of the exact one (a tile that fell back to
    // the exact engine: within half an ulp); sums and the subtraction in doubles, their
    // rounding added to the bound.
    constexpr double kEps = std::numeric_limits<double>::epsilon();
    double shadow = 0, bound = 0;
    for (std::size_t t = t0; t < t1; ++t) {
      const FaceLighting& tl = tile_items[t].lighting;
      shadow += tl.shadow_area;
      bound += tl.lit_area_error_bound > 0 ? tl.lit_area_error_bound : kEps * tl.shadow_area;
    }
    const double n = static_cast<double>(t1 - t0);
    bound = (bound + (n + 2) * kEps * (shadow + out.area)) * (1 + 1e-9);
    out.shadow_area = std::clamp(shadow, 0.0, out.area);
    out.lit_area = out.area - out.shadow_area;
    out.lit_fraction = out.area > 0 ? out.lit_area / out.area : 0.0;
    out.lit_area_error_bound = bound;
  }
}

void ShadowEngine::Impl::compute_extended_light(const Light& light_in, std::size_t light_id,
                                                const ShadowOptions& options, std::vector<ThreadState>& workers,
                                                const std::vector<std::size_t>& receivers, ItemTable& items,
                                                std::size_t progress_base, std::size_t progress_total) const {
  // lit_area, shadow_area, lit_fraction, faces_light and the fast path's bound are the light's
  // centre's (docs/area-lights.md): computed by the point-light route, areas only.
  const Light centre = shadow::detail::centre_light(light_in);
  ShadowOptions centre_options = options;
  centre_options.polygons = false;
  centre_options.progress = nullptr;
  ItemTable centre_items(receivers.size(), static_cast<unsigned>(workers.size()));
  compute_light(centre, light_id, centre_options, workers, receivers, centre_items, 0, 0);

  const core::PreparedScene ctx = prepared();
  const arealight::AreaLightPrep area = arealight::prepare_area_light(ctx, light_in, light_id);
  std::vector<arealight::AreaWorker> area_workers(workers.size());
  std::function<void(std::size_t)> report;
  if (options.progress)
    report = [&](std::size_t done) { options.progress(Progress{progress_base + done, progress_total}); };
  runtime::parallel_for(
      receivers.size(), static_cast<unsigned>(workers.size()),
      [&](unsigned wi, std::size_t r) {
        ThreadState& w = workers[wi];
        Item item = arealight::compute_area_receiver(ctx, w.exact, area_workers[wi], area, receivers[r], light_id,
                                                     options.polygons, w.stats);
        const FaceLighting& c = centre_items[r].lighting;
        item.lighting.lit_area = c.lit_area;
        item.lighting.shadow_area = c.shadow_area;
        item.lighting.lit_fraction = c.lit_fraction;
        item.lighting.faces_light = c.faces_light;
        item.lighting.lit_area_error_bound = c.lit_area_error_bound;
        // The centre shines forward only, as the light does.
        arealight::restrict_centre_to_emitting_side(ctx, w.exact, area_workers[wi], area, receivers[r], light_id,
                                                    centre, w.stats, item.lighting);
        items[r] = std::move(item);
      },
      report);
}

ShadowResult ShadowEngine::Impl::assemble(std::vector<ItemTable>& per_light,
                                          const std::vector<ThreadState>& workers) {
  ShadowResult result;
  const std::size_t lights = per_light.size();
  const std::size_t receivers = lights ? per_light[0].size() : 0;
  // The lighting rows (receiver-major, then light) copied by blocks on every worker's thread,
  // their pages first touched there too (a million rows: 96 MB). Each block notes whether any
  // of its items has fragments, so that the renumbering below visits only those blocks (areas
  // only: none, where visiting every item was a serial pass over the whole table).
  const unsigned threads = static_cast<unsigned>(std::max<std::size_t>(1, workers.size()));
  constexpr std::size_t kBlock = 4096;
  runtime::resize_touched(result.lighting, lights * receivers, threads);
  std::vector<char> block_has_fragments((receivers + kBlock - 1) / kBlock, 0);
  runtime::parallel_for_blocks(receivers, kBlock, threads, [&](unsigned, std::size_t b, std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      for (std::size_t li = 0; li < lights; ++li) {
        const Item& item = per_light[li][r];
        result.lighting[r * lights + li] = item.lighting;
        if (!item.fragments.empty()) block_has_fragments[b] = 1;
      }
  });
  // Fragments in the same order, their ids made global.
  std::size_t next_fragment_id = 0;
  for (std::size_t b = 0; b < block_has_fragments.size(); ++b) {
    if (!block_has_fragments[b]) continue;
    for (std::size_t r = b * kBlock; r < std::min(receivers, (b + 1) * kBlock); ++r)
      for (std::size_t li = 0; li < lights; ++li) {
        Item& item = per_light[li][r];
        if (item.fragments.empty()) continue;
        engine_detail::append_renumbered(item.fragments, result.fragments, next_fragment_id);
        item.fragments.clear();
        item.fragments.shrink_to_fit();
      }
  }
  for (const ThreadState& w : workers) {
    result.stats += w.stats;
  }
  return result;
}

std::vector<ShadowEngine::Impl::ThreadState> ShadowEngine::Impl::make_workers(unsigned threads, bool fast) const {
  std::vector<ThreadState> workers(threads);
  runtime::parallel_for(workers.size(), threads, [&](unsigned, std::size_t i) {
    workers[i].exact.reset(scene->faces.size(), solids.size());
    if (fast) workers[i].fast.casters.reset(solids.size());
  });
  return workers;
}

void ShadowEngine::Impl::release_workers(std::vector<ThreadState>& workers) {
  runtime::parallel_for(workers.size(), static_cast<unsigned>(workers.size()), [&](unsigned, std::size_t i) {
    workers[i].exact = exact::ExactWorker{};
    workers[i].fast = fast::FastWorker{};
  });
}

ShadowResult ShadowEngine::Impl::run(const std::vector<const Light*>& lights,
                                     const std::vector<std::size_t>& light_ids,
                                     const ShadowOptions& options) const {
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));
  const std::vector<std::size_t> receivers = engine_detail::receiving_faces(*scene, threads);
  std::vector<ThreadState> workers = make_workers(threads, options.arithmetic == Arithmetic::Fast);
  std::vector<ItemTable> per_light;
  for (std::size_t li = 0; li < lights.size(); ++li)
    per_light.emplace_back(receivers.size(), static_cast<unsigned>(workers.size()));
  const std::size_t total = lights.size() * receivers.size();
  for (std::size_t li = 0; li < lights.size(); ++li)
    compute_light(*lights[li], light_ids[li], options, workers, receivers, per_light[li],
                  li * receivers.size(), total);
  ShadowResult result = assemble(per_light, workers);
  release_workers(workers);
  for (ItemTable& table : per_light) table.release(threads);
  result.arithmetic = options.arithmetic;
  // Extended lights: the exact visible fraction of the light at every fragment vertex.
  for (std::size_t li = 0; li < lights.size(); ++li)
    if (lights[li]->is_extended())
      shadow::detail::fill_light_fragment_visibility(*scene, *lights[li], light_ids[li], result.fragments,
                                                     options.threads);
  return result;
}

ShadowResult ShadowEngine::compute(const ShadowOptions& options) const {
  const Scene& scene = *impl_->scene;
  const std::vector<std::size_t> light_ids = shadow::detail::resolve_lights(scene, options.lights);
  std::vector<const Light*> lights;
  for (std::size_t l : light_ids) lights.push_back(&scene.lights[l]);
  return impl_->run(lights, light_ids, options);
}

ShadowResult ShadowEngine::compute(const Light& light, std::size_t light_id,
                                   const ShadowOptions& options) const {
  // A light that need not be one of the scene's: checked here (resolve_lights checks the scene's).
  shadow::detail::check_light(light, "", "lights[" + std::to_string(light_id) + "]");
  return impl_->run({&light}, {light_id}, options);
}

core::PreparedScene engine::prepared_scene(const ShadowEngine& engine) { return engine.impl().prepared(); }

ShadowResult compute_shadows(const Scene& scene, const ShadowOptions& options) {
  return compute_shadows(ShadowEngine(scene, options.threads), options);
}

ShadowResult compute_shadows(const ShadowEngine& engine, const ShadowOptions& options) {
  if (!options.progress) {
    ShadowResult result = engine.compute(options);
    if (options.planes) result.plane_shadows = engine.compute_planes(options);
    return result;
  }
  // The plane shadows count nothing: while they run, the faces' last count is reported again
  // (about every 100 ms), so that the callback can still stop the call.
  Progress last;
  ShadowOptions counted = options;
  counted.progress = [&](const Progress& p) {
    last = p;
    options.progress(p);
  };
  ShadowResult result = engine.compute(counted);
  if (options.planes) {
    counted.progress = [&](const Progress&) { options.progress(last); };
    result.plane_shadows = engine.compute_planes(counted);
  }
  return result;
}

}  // namespace shadow
