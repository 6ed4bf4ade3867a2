// SPDX-License-Identifier: GPL-3.0-or-later
// The exact sun-hours map (shadow/sun_hours.hpp, docs/sun-hours-map.md).
//
// Per receiving face: the lit region of every instant, exactly as the exact engine computes it
// (exact/exact_receiver: casters, projection, one union, the chart minus it), is cut into
// directed boundary segments, the region on each segment's left (face-instant pairs in parallel).
// Instants under which the face is wholly lit add their weight to the whole chart (no curves);
// wholly dark ones add nothing. A face whose boundaries are many is then cut into vertical strips
// of its chart, each overlaid in its own arrangement (sunmap/face_overlay.hpp: face-strip pairs
// in parallel), so that no arrangement holds every boundary of a large ground and one face's map
// uses every thread. The strips' cells are concatenated in strip order.
#include "core/culling.hpp"
#include "core/face_prep.hpp"
#include "core/lights.hpp"
#include "runtime/parallel.hpp"
#include "core/prepared_scene.hpp"
#include "engine/engine_access.hpp"
#include "exact/exact_faces.hpp"
#include "exact/exact_receiver.hpp"
#include "exact/lazy_geometry.hpp"
#include "exact/regions.hpp"
#include "sunmap/face_overlay.hpp"
#include "sunmap/lit_tiles.hpp"
#include "sunmap/packed_boundaries.hpp"
#include "sunmap/rough_segments.hpp"
#include "sunmap/sun_hours_inputs.hpp"

#include <shadow/series.hpp>

#include <shadow/error.hpp>
#include <shadow/sun_hours.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <exception>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace shadow {
namespace {

using namespace exact;
using sunmap::Curve;

using sunmap::RoughSegment;


/// What one instant leaves on one face.
struct InstantPart {
  LitRegion::Kind kind = LitRegion::Kind::Dark;
  /// Partial: the lit region's boundary, tagged with the instant, as the face keeps it: packed
  /// (the full map; a face the threshold map keeps exact), in doubles (one it does not) or curves.
  std::vector<Curve> curves;
  sunmap::PackedBoundaries::Chunk packed;
  std::vector<RoughSegment> rough;
  mpq_class lit_area{0};      ///< the lit region's exact chart area (no lazy DAG kept)
};

/// The map of `faces` under `instants`: the lit regions of a batch of instants at a time (every
/// face-instant pair of the batch in parallel), then handed on before the next batch is computed.
/// The full map gathers each face's boundaries (its strips' one sweep needs them all), packed
/// (sunmap::PackedBoundaries); each face is assembled by the job that overlays its last strip. The
/// threshold map alone gathers the exact ones up to a budget, and past it the faces holding the
/// most keep theirs in doubles (sunmap::RoughSegment): from what it kept each face gets its tiles
/// (sunmap::FaceTiles), the order its instants are swept in and its strips, each planned; the
/// exact boundaries are then fed to the strips' rounds (sunmap::LevelRounds) in that order,
/// those kept at once, the others computed again a wave of strips and a band of instants at a
/// time. With stream_levels each batch is fed to the strips' rounds in time order instead, and
/// dropped.
class MapBuilder {
 public:
  MapBuilder(const ShadowEngine& engine, const std::vector<std::size_t>& faces_in,
             const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options)
      : ctx_(shadow::engine::prepared_scene(engine)),
        instants_(instants),
        options_(options),
        threads_(runtime::resolve_threads(runtime::checked_threads(options.threads))),
        hours_(sunmap::checked_hours(instants)),
        hours_q_(sunmap::exact_hours(hours_)),
        faces_(sunmap::checked_faces(*ctx_.scene, faces_in)),
        n_(instants.size()) {
    map_.levels = sunmap::checked_levels(options.levels);
    full_ = options.full || map_.levels.empty();
    map_.full = full_;
    mpq_class total(0);
    for (const mpq_class& w : hours_q_) total += w;
    map_.total_hours = total.get_d();  // rounded once, as the cells' hours
    for (double h : map_.levels) level_q_.emplace_back(h);
    workers_ = std::vector<Worker>(threads_);
    for (Worker& w : workers_) w.exact.reset(ctx_.scene->faces.size(), ctx_.solids->size());
    total_ = faces_.size() * (n_ + 1);
    if (options.progress) report_ = [this](std::size_t) { options_.progress(Progress{done_.load(), total_.load()}); };
    prepare_faces();
    if (options.series_table) start_table(*options.series_table);
  }

  SunHoursMap build() {
    const std::size_t batch = options_.instant_batch == 0 ? std::max<std::size_t>(n_, 1) : options_.instant_batch;
    // unfed[b]: the hours of the instants from b on (exact), a bound on what is still to come.
    std::vector<mpq_class> unfed(n_ + 1, mpq_class(0));
    for (std::size_t i = n_; i-- > 0;) unfed[i] = unfed[i + 1] + hours_q_[i];
    for (std::size_t first = 0; first < n_; first += batch) {
      const std::size_t count = std::min(batch, n_ - first);
      lit_batch(first, count);
      take_batch(first, count, unfed[first + count]);
    }
    if (table_)
      for (const Worker& w : workers_) table_->stats += w.stats;  // the rows' pairs in the lit pass
    std::vector<sunmap::FaceMap> face_maps(faces_.size());
    if (full_) {
      face_maps = overlay_full();
    } else {
      finish_levels();
      face_maps = std::move(face_maps_);
    }
    // The faces in order, region ids shifted by the earlier faces'.
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      sunmap::FaceMap& fm = face_maps[k];
      for (SunHoursCell& c : fm.cells) {
        c.region_id += map_.regions;
        map_.cells.push_back(std::move(c));
      }
      map_.regions += fm.regions;
      for (SunHoursCell& c : fm.level_cells) {
        c.region_id += map_.level_regions;
        map_.level_cells.push_back(std::move(c));
      }
      map_.level_regions += fm.level_regions;
      map_.faces.push_back(std::move(fm.face));
      fm = {};
    }
    return std::move(map_);
  }

 private:
  struct Worker {
    ExactWorker exact;
    ShadowStats stats;        ///< the table's rows' pairs (SunHoursOptions::series_table)
    ShadowStats other_stats;  ///< the other faces' pairs (not receiving faces)
    ShadowStats again_stats;  ///< pairs computed again (the threshold map alone): counted once
  };

  /// The series table of the map's receiving faces (SunHoursOptions::series_table):
  /// compute_series' shape, its entries written by lit_batch. A degenerate face keeps
  /// compute's zeros.
  void start_table(SeriesResult& table) {
    table_ = &table;
    table = SeriesResult{};
    table.instants = n_;
    table_row_.assign(faces_.size(), SIZE_MAX);
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if (!ctx_.scene->is_receiver(faces_[k])) continue;
      table_row_[k] = table.faces.size();
      table.faces.push_back(faces_[k]);
      table.area.push_back((*ctx_.face_area)[faces_[k]]);
    }
    table.zero_entries();
  }

  void prepare_faces() {
    const std::size_t count = faces_.size();
    face_info_.resize(count);
    scales_.resize(count);
    hour_area_.assign(count, mpq_class(0));
    requests_.resize(count);
    outline_.resize(count);
    packed_.resize(count);
    if (full_) base_.assign(count, mpq_class(0));
    else {
      tiles_.resize(count);
      strip_maps_.resize(count);
      face_maps_.resize(count);
      strips_left_ = std::make_unique<std::atomic<std::size_t>[]>(count);
      rounds_.resize(count);
      whole_pending_.assign(count, mpq_class(0));
      sample_.resize(count);
      sampled_.assign(count, 0);
      rough_.resize(count);
      keep_exact_.assign(count, 1);
      order_.resize(count);
    }
    // Each face's exact view is the map's own (not a worker's, whose cache is trimmed), made with
    // its outline and scale when its strips start (face_view), until the face is assembled: the
    // lit pass needs none of them (Delft's 30,708 outlines alone were some 50 MB).
    map_faces_.resize(count);
    runtime::parallel_for(count, threads_, [&](unsigned, std::size_t k) {
      const std::size_t f = faces_[k];
      SunHoursFace& info = face_info_[k];
      info.face_id = f;
      info.area = (*ctx_.face_area)[f];
      info.level_areas.assign(map_.levels.size(), 0.0);
      const core::FacePrep& fp = (*ctx_.prep)[f];
      if (fp.degenerate) return;
      requests_[k] = sunmap::OverlayRequest{nullptr, &fp, f, &hours_, &hours_q_, options_.merge_equal, full_, level_q_,
                                            options_.level_round_edges};
    });
  }

  /// Face k's exact view (requests_[k].face) and outline_[k], made again for its strips; they go
  /// when the face is assembled. A face's are made by one thread.
  const ExactFace& face_view(std::size_t k) {
    if (!map_faces_[k]) {
      const std::size_t f = faces_[k];
      map_faces_[k] = std::make_unique<ExactFace>(make_exact_face(ctx_.scene->faces[f].vertices, (*ctx_.prep)[f]));
      requests_[k].face = map_faces_[k].get();
      // Its area scale made exact here, not first by its strips' jobs at once.
      exact_to_mpq(map_faces_[k]->area_scale_squared, scales_[k].get_mpq_t());
      sunmap::add_boundary(map_faces_[k]->chart, static_cast<long>(n_), outline_[k]);
    }
    return *map_faces_[k];
  }

  /// 1. The lit regions of instants [first, first + count) on every face, face-instant pairs in
  /// parallel (one large ground uses every thread), into parts_ (face-major).
  void lit_batch(std::size_t first, std::size_t count) {
    // The culling grid of each directional light of the batch, shared read-only by the threads.
    std::vector<std::size_t> batch(count);
    for (std::size_t j = 0; j < count; ++j) batch[j] = first + j;
    const std::vector<std::optional<core::LightSpaceGrid>> grids = light_grids(batch);
    parts_.assign(faces_.size() * count, InstantPart{});
    runtime::parallel_for(
        parts_.size(), threads_,
        [&](unsigned wi, std::size_t job) {
          runtime::check_stop();
          Worker& w = workers_[wi];
          const std::size_t k = job / count, j = job % count, i = first + j, f = faces_[k];
          const std::size_t row = table_ ? table_row_[k] : SIZE_MAX;
          ShadowStats& stats = row != SIZE_MAX ? w.stats : w.other_stats;
          if ((*ctx_.prep)[f].degenerate) {  // no lit region; the table keeps compute's zeros
            ++stats.receivers;               // and counts the pair as compute does
            ++done_;
            return;
          }
          const LitBoundary region = lit_boundary(w, k, i, grids[j] ? &*grids[j] : nullptr, stats);
          if (row != SIZE_MAX) {  // the engine's FaceLighting: what compute_series writes for the pair
            const std::size_t at = table_->at(row, i);
            table_->lit_area[at] = region.lighting.lit_area;
            table_->lit_fraction[at] = region.lighting.lit_fraction;
            table_->faces_light[at] = region.lighting.faces_light ? 1 : 0;
          }
          InstantPart& part = parts_[job];
          part.kind = region.kind;
          exact_to_mpq(region.lit_chart_area, part.lit_area.get_mpq_t());
          part.curves.reserve(region.segments.size());
          for (const BoundarySegment& s : region.segments)
            sunmap::add_segment(s.from, s.to, s.left, static_cast<long>(i), part.curves);
          if (keeps_packed(k)) {
            part.packed = sunmap::PackedBoundaries::pack(part.curves);
            part.curves = {};
          } else if (levels_gathered_mode()) {
            for (const Curve& c : part.curves) part.rough.push_back(sunmap::rough_segment(c));
            part.curves = {};
          }
          ++done_;
        },
        report_);
  }

  /// Face k's lit region under instant i: its canonical boundary, the same segments whichever
  /// route made it (exact_lit_boundary), and the engine's lighting of the pair. One call is one
  /// work item: the worker's exact faces are trimmed first, as the engine's workers' are (the
  /// result holds no reference into them).
  LitBoundary lit_boundary(Worker& w, std::size_t k, std::size_t i, const core::LightSpaceGrid* grid,
                           ShadowStats& stats) {
    w.exact.trim(exact::kExactFaceCache);
    const std::size_t f = faces_[k];
    const ExactFace& P = w.exact.face(ctx_, f);
    const ExactLight light = to_exact_light(instants_[i].light);
    const int side = CGAL::sign(plane_at_light(P, light));
    return exact_lit_boundary(ctx_, w.exact, f, i, light, side, instants_[i].light, grid, stats);
  }

  /// The culling grid of each directional light among `instants` (their positions), built in
  /// parallel, one per thread at a time, as compute_series builds a batch's.
  std::vector<std::optional<core::LightSpaceGrid>> light_grids(const std::vector<std::size_t>& instants) {
    std::vector<std::optional<core::LightSpaceGrid>> grids(instants.size());
    runtime::parallel_for(instants.size(), threads_, [&](unsigned, std::size_t j) {
      if (instants_[instants[j]].light.type == LightType::Directional)
        grids[j].emplace(*ctx_.cull, *ctx_.prep, instants_[instants[j]].light.to_light, ctx_.solid_of);
    });
    return grids;
  }

  /// The threshold map alone, gathered (not streamed): exact boundaries kept within the budget.
  bool levels_gathered_mode() const { return !full_ && !options_.stream_levels; }
  /// Face k keeps its boundaries packed (the full map, and a face the gathered threshold map keeps
  /// exact); else in doubles (gathered) or as curves (streamed).
  bool keeps_packed(std::size_t k) const { return full_ || (levels_gathered_mode() && keep_exact_[k]); }

  /// 2. The batch's parts, face by face: the integral's terms and the instants lit; the
  /// boundaries gathered (full map) or fed to the face's strips (threshold map alone).
  void take_batch(std::size_t first, std::size_t count, const mpq_class& unfed) {
    std::vector<std::vector<Curve>> curves(faces_.size());
    std::vector<mpq_class> whole(faces_.size(), mpq_class(0));
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if ((*ctx_.prep)[faces_[k]].degenerate) continue;
      for (std::size_t j = 0; j < count; ++j) {
        InstantPart& part = parts_[k * count + j];
        const std::size_t i = first + j;
        if (part.kind == LitRegion::Kind::Dark) continue;
        ++face_info_[k].instants_lit;
        // The integral of hours over the face, sum over instants of w_i x lit area_i: the same
        // exact rational as the sum over the overlay's faces of hours x area (the tests check
        // the cells against it), and far cheaper than thousands of cell areas with unrelated
        // denominators.
        if (hours_[i] != 0 && sgn(part.lit_area) != 0) hour_area_[k] += hours_q_[i] * part.lit_area;
        if (part.kind == LitRegion::Kind::Whole) whole[k] += hours_q_[i];
        if (keeps_packed(k)) {
          if (!full_) kept_segments_ += part.packed.size();
          packed_[k].add(std::move(part.packed));
        } else if (levels_gathered_mode()) {
          rough_[k].insert(rough_[k].end(), part.rough.begin(), part.rough.end());
        } else {
          for (Curve& c : part.curves) curves[k].push_back(std::move(c));
        }
        part = InstantPart{};
      }
      if (full_) base_[k] += whole[k];
    }
    parts_ = {};
    if (full_) return;
    const bool last = first + count == n_;
    if (levels_gathered_mode()) {
      for (std::size_t k = 0; k < faces_.size(); ++k) whole_pending_[k] += whole[k];
      // Over the budget: the faces holding the most exact boundaries drop them, to be computed
      // again (decided in face order, batch by batch: the same whatever the threads).
      while (kept_segments_ > options_.level_held_segments) {
        std::size_t most = 0;
        for (std::size_t k = 1; k < faces_.size(); ++k)
          if (packed_[k].size() > packed_[most].size()) most = k;
        kept_segments_ -= packed_[most].size();
        rough_[most] = packed_[most].rough(threads_);
        packed_[most] = {};
        keep_exact_[most] = 0;
      }
      if (last) levels_gathered();
      return;
    }
    // A face's strips are chosen from its first 16 instants that cut it (or every instant, if
    // fewer; their boundaries are held until then), sized by those instants' segments: rounds
    // bound each strip's arrangement, but its kept edges (about a day's boundaries, undecided or
    // on a level's border) want strips too. A smaller sample misjudged them (the first few suns
    // of a day, low, cut a ground little), and sizing by every instant to come would give each
    // of ever more strips a round's worth of instants not yet swept: memory linear in them.
    std::vector<std::tuple<std::size_t, std::size_t, std::vector<std::size_t>>> jobs;  // face, strip, curves
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if ((*ctx_.prep)[faces_[k]].degenerate) continue;
      if (rounds_[k].empty()) {
        whole_pending_[k] += whole[k];
        whole[k] = 0;
        if (sample_[k].empty() && curves[k].empty()) continue;  // not cut yet
        sampled_[k] += count;
        for (Curve& c : curves[k]) sample_[k].push_back(std::move(c));
        if (sampled_[k] < 16 && !last) continue;  // gathering the sample
        curves[k] = std::move(sample_[k]);
        sample_[k] = {};
        start_rounds(k, curves[k], curves[k].size());
        whole[k] = whole_pending_[k];
        whole_pending_[k] = 0;
      }
      std::vector<std::vector<std::size_t>> which = sunmap::bucket_curves(curves[k], strips_[k]);
      for (std::size_t s = 0; s < which.size(); ++s) jobs.emplace_back(k, s, std::move(which[s]));
    }
    // After the last batch each strip is finished in the same job (its level regions written and
    // its arrangement freed), one strip after another per thread.
    runtime::parallel_for(jobs.size(), threads_, [&](unsigned, std::size_t j) {
      runtime::check_stop();
      const auto& [k, s, which] = jobs[j];
      rounds_[k][s].feed(curves[k], which, whole[k], unfed);
      if (!last) return;
      strip_done(k, s);
      ++done_;
    });
  }

  /// The threshold map alone, gathered, after the last batch: each face cut by an instant gets
  /// its tiles, the order its instants are swept in (cut into bands), and its strips; then each
  /// strip is planned, fed its exact boundaries in that order and finished: a kept face's in one
  /// job per strip, the others' computed again in waves (feed_in_waves).
  void levels_gathered() {
    // The tiles of every face cut share one budget (they are all made before the strips run).
    std::vector<std::size_t> cut;
    for (std::size_t k = 0; k < faces_.size(); ++k)
      if (!(*ctx_.prep)[faces_[k]].degenerate && !(rough_[k].empty() && packed_[k].empty())) cut.push_back(k);
    tile_bits_ = std::min(sunmap::kMaxTileBits,
                          sunmap::kMaxTileBitsAll / static_cast<double>(std::max<std::size_t>(cut.size(), 1)));
    runtime::parallel_for(cut.size(), threads_, [&](unsigned, std::size_t j) { face_view(cut[j]); });
    rough_which_.resize(faces_.size());
    band_ends_.resize(faces_.size());
    const std::size_t band_segments = options_.level_held_segments / 2;
    // Per kept face: the strips fed its packed curves that enter them.
    std::vector<std::vector<std::vector<std::size_t>>> which(faces_.size());
    for (std::size_t k : cut) {
      // A face keeps either its exact curves (packed) or its rough segments, each instant's
      // together; either way its tiles, order, bands and strips come from the rough segments
      // (a kept face's made for the purpose, the same doubles as its curves').
      const bool exact = keep_exact_[k] != 0;
      std::vector<RoughSegment> made;
      if (exact) made = packed_[k].rough(threads_);
      std::vector<RoughSegment>& rough = exact ? made : rough_[k];
      std::vector<std::pair<std::size_t, std::size_t>> runs;  // per instant cutting it: [begin, end)
      const std::size_t count = rough.size();
      for (std::size_t c = 0, i = SIZE_MAX; c < count; ++c) {
        const std::size_t at = rough[c].instant;
        if (at != i) runs.emplace_back(c, c), i = at;
        runs.back().second = c + 1;
      }
      tiles_[k] = sunmap::make_face_tiles(face_view(k).chart, rough, runs, whole_pending_[k], tile_bits_, threads_);
      if (tiles_[k].grid.n != 0) requests_[k].tiles = &tiles_[k];
      order_[k] = sunmap::sweep_order(tiles_[k]);
      // The bands of its order: about band_segments segments each, at least 4 instants (so
      // that a band's lit regions can be computed in parallel), whether its exact curves were
      // kept or not (its strips' order within a band so depends on the budget alone). A band
      // computed again keeps only the curves entering the wave's strips.
      std::vector<std::size_t> segments(n_, 0);
      for (std::size_t r = 0; r < runs.size(); ++r) segments[tiles_[k].instants[r]] = runs[r].second - runs[r].first;
      for (std::size_t p = 0, held = 0, first = 0; p < order_[k].size(); ++p) {
        held += segments[order_[k][p]];
        if ((held >= band_segments && p + 1 - first >= 4) || p + 1 == order_[k].size())
          band_ends_[k].push_back(p + 1), held = 0, first = p + 1;
      }
      // The outline (tagged n) joins the boundaries to choose the strips, and goes.
      for (const Curve& c : outline_[k]) rough.push_back(sunmap::rough_segment(c));
      start_rounds(k, sunmap::choose_strips(rough, rough.size(), face_view(k).chart, options_.strip_edges));
      rough.resize(count);
      if (exact) which[k] = sunmap::bucket_rough(rough, strips_[k]);  // as bucket_curves buckets its curves
      else rough_which_[k] = sunmap::bucket_rough(rough, strips_[k]);
    }
    // The faces whose exact boundaries were kept: each strip unpacks its curves, is planned, fed
    // and finished in one job (its curves, pending boundaries and rounds are held one strip per
    // thread at a time).
    std::vector<std::pair<std::size_t, std::size_t>> jobs;  // (face, strip)
    for (std::size_t k : cut)
      if (keep_exact_[k])
        for (std::size_t s = 0; s < strips_[k].size(); ++s) jobs.emplace_back(k, s);
    runtime::parallel_for(jobs.size(), threads_, [&](unsigned, std::size_t j) {
      runtime::check_stop();
      const auto [k, s] = jobs[j];
      std::vector<Curve> curves;
      packed_[k].unpack(which[k][s], curves);
      which[k][s] = {};
      std::vector<std::size_t> all(curves.size());
      std::iota(all.begin(), all.end(), std::size_t{0});
      plan_strip(jobs[j], curves, all);
      rounds_[k][s].feed_planned(curves, all, order_[k].size());
      strip_done(k, s);
      ++done_;
    });
    jobs.clear();
    for (std::size_t k : cut) {
      if (!keep_exact_[k]) {
        for (std::size_t s = 0; s < strips_[k].size(); ++s) jobs.emplace_back(k, s);
        continue;
      }
      packed_[k] = {};
      tiles_[k] = sunmap::FaceTiles{};  // its strips are finished
    }
    // The others a wave of strips at a time, their instants computed again band by band.
    feed_in_waves(jobs);
    for (std::size_t k : cut) rough_[k] = {}, rough_which_[k] = {};
  }

  /// The strips `all` (face, strip; each face's in order), of faces whose exact boundaries were
  /// not kept, planned, fed and finished a wave of them at a time (their rough segments about
  /// half of level_held_segments together: their pending boundaries and rounds are held at
  /// once). Each wave's instants, those whose boundaries enter its strips, are computed again
  /// band by band (band b of each face's order in the wave together, sharing the culling grids):
  /// the band's face-instant pairs in parallel, then the wave's strips. Each wave computes its
  /// instants once more: memory bounded for time (docs/sun-hours-map.md, step 7).
  void feed_in_waves(const std::vector<std::pair<std::size_t, std::size_t>>& all) {
    std::vector<std::vector<std::vector<std::size_t>>> which(faces_.size());
    std::vector<std::vector<Curve>> curves(faces_.size());
    for (std::size_t w0 = 0; w0 < all.size();) {
      std::size_t w1 = w0, held = 0;
      const auto rough_of = [&](std::size_t w) { return rough_which_[all[w].first][all[w].second].size(); };
      while (w1 < all.size() && (w1 == w0 || held + rough_of(w1) <= options_.level_held_segments / 2))
        held += rough_of(w1++);
      const std::vector<std::pair<std::size_t, std::size_t>> wave(all.begin() + static_cast<std::ptrdiff_t>(w0),
                                                                  all.begin() + static_cast<std::ptrdiff_t>(w1));
      w0 = w1;
      // Per face in the wave: its strips there [first, last) and the instants entering them.
      struct Part {
        std::size_t face, first, last;
        std::vector<char> present;
      };
      std::vector<Part> parts;
      std::size_t bands = 0;
      for (const auto& [k, s] : wave) {
        if (parts.empty() || parts.back().face != k) {
          parts.push_back(Part{k, s, s, std::vector<char>(n_, 0)});
          bands = std::max(bands, band_ends_[k].size());
        }
        parts.back().last = s + 1;
        for (std::size_t c : rough_which_[k][s]) parts.back().present[rough_[k][c].instant] = 1;
      }
      std::unordered_map<std::size_t, std::pair<std::size_t, std::size_t>> span;  // face: its strips here
      for (const Part& part : parts) span[part.face] = {part.first, part.last};
      runtime::parallel_for(wave.size(), threads_, [&](unsigned, std::size_t j) { plan_strip(wave[j], {}, {}); });
      for (std::size_t b = 0; b < bands; ++b) {
        std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (face, instant), each face's in its order
        std::vector<std::size_t> instants;
        for (const Part& part : parts) {
          const std::vector<std::size_t>& ends = band_ends_[part.face];
          if (b >= ends.size()) continue;
          for (std::size_t p = b == 0 ? 0 : ends[b - 1]; p < ends[b]; ++p)
            if (part.present[order_[part.face][p]]) {
              pairs.emplace_back(part.face, order_[part.face][p]);
              instants.push_back(order_[part.face][p]);
            }
        }
        again_ += pairs.size();
        total_ += pairs.size();
        std::sort(instants.begin(), instants.end());
        instants.erase(std::unique(instants.begin(), instants.end()), instants.end());
        const std::vector<std::optional<core::LightSpaceGrid>> grids = light_grids(instants);
        std::vector<std::vector<Curve>> pair_curves(pairs.size());
        runtime::parallel_for(
            pairs.size(), threads_,
            [&](unsigned wi, std::size_t j) {
              runtime::check_stop();
              const auto [k, i] = pairs[j];
              const auto g = std::lower_bound(instants.begin(), instants.end(), i) - instants.begin();
              Worker& w = workers_[wi];
              const LitBoundary region = lit_boundary(w, k, i, grids[g] ? &*grids[g] : nullptr, w.again_stats);
              // Only the segments that may enter the wave's strips of face k (bucket_curves' test).
              const auto [first, last] = span.at(k);
              const sunmap::Strip &a = strips_[k][first], &z = strips_[k][last - 1];
              for (const BoundarySegment& seg : region.segments) {
                const auto p = CGAL::to_interval(seg.from.x()), q = CGAL::to_interval(seg.to.x());
                if (a.whole || (std::min(p.first, q.first) <= z.x1 && std::max(p.second, q.second) >= a.x0))
                  sunmap::add_segment(seg.from, seg.to, seg.left, static_cast<long>(i), pair_curves[j]);
              }
              ++done_;
            },
            report_);
        for (std::size_t j = 0; j < pairs.size(); ++j) {
          for (Curve& c : pair_curves[j]) curves[pairs[j].first].push_back(std::move(c));
          pair_curves[j] = {};
        }
        std::vector<std::pair<std::size_t, std::size_t>> jobs;
        for (const Part& part : parts) {
          const std::size_t k = part.face;
          if (b >= band_ends_[k].size()) continue;
          const std::vector<sunmap::Strip> strips(strips_[k].begin() + static_cast<std::ptrdiff_t>(part.first),
                                                  strips_[k].begin() + static_cast<std::ptrdiff_t>(part.last));
          std::vector<std::vector<std::size_t>> in_wave = sunmap::bucket_curves(curves[k], strips);
          which[k].assign(strips_[k].size(), {});
          for (std::size_t s = part.first; s < part.last; ++s) {
            which[k][s] = std::move(in_wave[s - part.first]);
            jobs.emplace_back(k, s);
          }
        }
        feed_strips(jobs, curves, which, [&](std::size_t k) { return band_ends_[k][b]; });
      }
      for (const Part& part : parts)
        if (part.last == strips_[part.face].size()) {  // all its strips finished
          tiles_[part.face] = sunmap::FaceTiles{};
          rough_[part.face] = {}, rough_which_[part.face] = {};
        }
    }
  }

  /// Plans strip (face k, s) once: a kept face's from its exact curves `which` of `curves`
  /// (those bucketed into the strip), another's from its rough segments.
  void plan_strip(std::pair<std::size_t, std::size_t> job, const std::vector<Curve>& curves,
                  const std::vector<std::size_t>& which) {
    const auto [k, s] = job;
    if (rounds_[k][s].planned()) return;
    if (keep_exact_[k]) {  // from its exact curves, bucketed into the strip
      rounds_[k][s].plan(order_[k], band_ends_[k], curves, which, whole_pending_[k]);
      return;
    }
    rounds_[k][s].plan(order_[k], band_ends_[k], rough_[k], rough_which_[k][s], whole_pending_[k]);
    rough_which_[k][s] = {};
  }

  /// Feeds each job's strip (face, strip) the curves which[face][strip] of curves[face], those
  /// of the instants before position order_end(face) of the face's order; a strip fed its last
  /// instant is finished in the same job. The curves go once fed.
  template <class OrderEnd>
  void feed_strips(const std::vector<std::pair<std::size_t, std::size_t>>& jobs,
                   std::vector<std::vector<Curve>>& curves, std::vector<std::vector<std::vector<std::size_t>>>& which,
                   const OrderEnd& order_end) {
    runtime::parallel_for(jobs.size(), threads_, [&](unsigned, std::size_t j) {
      runtime::check_stop();
      const auto [k, s] = jobs[j];
      const std::size_t end = order_end(k);
      plan_strip(jobs[j], curves[k], which[k][s]);
      rounds_[k][s].feed_planned(curves[k], which[k][s], end);
      which[k][s] = {};
      if (end != order_[k].size()) return;
      strip_done(k, s);
      ++done_;
    });
    for (const auto& [k, s] : jobs) curves[k] = {};
  }

  /// The strips of face k (from `sample`, the boundaries of its first instants that cut it, and
  /// its outline, sized by `expected` boundary segments) and their rounds, each starting from the
  /// outline.
  void start_rounds(std::size_t k, const std::vector<Curve>& sample, std::size_t expected) {
    const exact::Polygon2& chart = face_view(k).chart;
    std::vector<Curve> with_outline = sample;
    with_outline.insert(with_outline.end(), outline_[k].begin(), outline_[k].end());
    start_rounds(k, sunmap::choose_strips(with_outline, expected + outline_[k].size(), chart,
                                          options_.strip_edges));
  }

  /// Face k's strips `strips` and their rounds, each starting from the outline.
  void start_rounds(std::size_t k, std::vector<sunmap::Strip> strips) {
    if (strips_.size() < faces_.size()) strips_.resize(faces_.size());
    strips_[k] = std::move(strips);
    const std::vector<std::vector<std::size_t>> which = sunmap::bucket_curves(outline_[k], strips_[k]);
    for (std::size_t s = 0; s < strips_[k].size(); ++s)
      rounds_[k].emplace_back(requests_[k], strips_[k][s], outline_[k], which[s]);
    strip_maps_[k].resize(rounds_[k].size());
    strips_left_[k].store(rounds_[k].size());
  }

  /// Face k's map from its strips' maps (taken): its areas summed exactly and rounded.
  sunmap::FaceMap assemble_face(std::size_t k, std::vector<sunmap::StripMap>& strips) {
    face_info_[k].hour_area = sunmap::area_3d_mpq(hour_area_[k], scales_[k]);
    sunmap::FaceMap fm = sunmap::assemble(strips, face_info_[k], scales_[k], map_.levels.size());
    if (!full_) fm.face.areas.clear();
    map_faces_[k].reset();  // its strips are done
    outline_[k] = {};
    return fm;
  }

  /// 3. The full map: per face its outline and strips (faces in parallel), then face-strip
  /// pairs in parallel. The strips and buckets come from the packed boundaries' rough segments:
  /// the same doubles as the curves' own x ranges, so the same strips as choose_strips and
  /// bucket_curves of the curves give. A face is assembled as soon as its last strip is
  /// overlaid, so that its cells' exact areas (a rational each) go as the map grows.
  std::vector<sunmap::FaceMap> overlay_full() {
    std::vector<std::vector<sunmap::Strip>> strips(faces_.size());
    std::vector<std::vector<std::vector<std::size_t>>> buckets(faces_.size());
    // Faces in parallel; a scene of fewer faces than threads (one large ground) makes each
    // face's rough segments on every thread instead.
    const unsigned per_face = faces_.size() < threads_ ? threads_ : 1;
    runtime::parallel_for(faces_.size(), threads_, [&](unsigned, std::size_t k) {
      runtime::check_stop();
      if ((*ctx_.prep)[faces_[k]].degenerate) return;
      const exact::Polygon2& chart = face_view(k).chart;
      packed_[k].add(outline_[k]);  // after every instant's boundaries, as they were gathered
      outline_[k] = {};
      const std::vector<RoughSegment> rough = packed_[k].rough(per_face);
      strips[k] = sunmap::choose_strips(rough, rough.size(), chart, options_.strip_edges);
      buckets[k] = sunmap::bucket_rough(rough, strips[k]);
    });
    std::vector<std::pair<std::size_t, std::size_t>> jobs;  // (face index, strip)
    for (std::size_t k = 0; k < faces_.size(); ++k)
      for (std::size_t s = 0; s < strips[k].size(); ++s) jobs.emplace_back(k, s);
    total_ = faces_.size() * n_ + jobs.size();
    std::vector<std::vector<sunmap::StripMap>> strip_maps(faces_.size());
    std::vector<sunmap::FaceMap> face_maps(faces_.size());
    // Per face: its strips not overlaid yet. The last one frees the face's boundaries, so that
    // they go as the cells come (a triangulated city's were most of the map's memory).
    std::unique_ptr<std::atomic<std::size_t>[]> strips_left(new std::atomic<std::size_t>[faces_.size()]);
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      strip_maps[k].resize(strips[k].size());
      strips_left[k].store(strips[k].size());
    }
    runtime::parallel_for(
        jobs.size(), threads_,
        [&](unsigned, std::size_t j) {
          runtime::check_stop();
          const auto [k, s] = jobs[j];
          // The strip's curves unpacked (in the order bucketed), overlaid, and let go.
          sunmap::FaceBoundaries b;
          packed_[k].unpack(buckets[k][s], b.curves);
          b.base = base_[k];
          buckets[k][s] = {};
          std::vector<std::size_t> all(b.curves.size());
          std::iota(all.begin(), all.end(), std::size_t{0});
          strip_maps[k][s] = sunmap::overlay_strip(requests_[k], b, all, strips[k][s]);
          if (strips_left[k].fetch_sub(1) == 1) {  // the face's last strip: the others are done
            packed_[k] = {};
            face_maps[k] = assemble_face(k, strip_maps[k]);
          }
          ++done_;
        },
        report_);
    // The faces without strips (degenerate) as well.
    for (std::size_t k = 0; k < faces_.size(); ++k)
      if (strips[k].empty()) face_maps[k] = assemble_face(k, strip_maps[k]);
    return face_maps;
  }

  /// The threshold map alone: strip s of face k is finished; the face's last strip assembles it,
  /// so that its exact view and its cells' rational areas go then, not at the map's end.
  void strip_done(std::size_t k, std::size_t s) {
    strip_maps_[k][s] = rounds_[k][s].finish();
    if (strips_left_[k].fetch_sub(1) == 1) face_maps_[k] = assemble_face(k, strip_maps_[k]);
  }

  /// 3. The threshold map alone: the rounds left and the level regions, face-strip pairs in
  /// parallel; a face no instant cut gets its strips (one, unless its outline is long) now.
  void finish_levels() {
    std::vector<std::pair<std::size_t, std::size_t>> jobs;
    std::size_t strips = 0;
    runtime::parallel_for(faces_.size(), threads_, [&](unsigned, std::size_t k) {  // views of those starting now
      if (rounds_[k].empty() && !(*ctx_.prep)[faces_[k]].degenerate) face_view(k);
    });
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if ((*ctx_.prep)[faces_[k]].degenerate) continue;
      if (rounds_[k].empty()) {
        start_rounds(k, {}, 0);
        for (std::size_t s = 0; s < rounds_[k].size(); ++s)
          rounds_[k][s].feed({}, {}, whole_pending_[k], mpq_class(0));
      }
      strips += rounds_[k].size();
      if (strips_left_[k].load() == 0) continue;  // its strips finished with the last batch
      for (std::size_t s = 0; s < rounds_[k].size(); ++s) jobs.emplace_back(k, s);
    }
    total_ = faces_.size() * n_ + again_ + strips;
    runtime::parallel_for(
        jobs.size(), threads_,
        [&](unsigned, std::size_t j) {
          runtime::check_stop();
          const auto [k, s] = jobs[j];
          strip_done(k, s);
          ++done_;
        },
        report_);
    for (std::size_t k = 0; k < faces_.size(); ++k)  // no strips (degenerate): none to assemble it
      if (rounds_[k].empty()) face_maps_[k] = assemble_face(k, strip_maps_[k]);
  }

  core::PreparedScene ctx_;
  const std::vector<SunHoursInstant>& instants_;
  const SunHoursOptions& options_;
  unsigned threads_;
  std::vector<double> hours_;
  std::vector<mpq_class> hours_q_;  // the weights as summed (sunmap::exact_hours)
  std::vector<std::size_t> faces_;
  std::size_t n_;
  SunHoursMap map_;
  bool full_ = true;
  std::vector<mpq_class> level_q_;
  std::vector<Worker> workers_;
  std::atomic<std::size_t> done_{0}, total_{0};
  std::function<void(std::size_t)> report_;
  std::vector<InstantPart> parts_;          ///< the batch's lit regions, face-major
  std::vector<SunHoursFace> face_info_;     ///< per face
  std::vector<mpq_class> scales_;           ///< per face: (3D / chart area)^2
  std::vector<mpq_class> hour_area_;        ///< per face: sum over instants of w_i x lit chart area
  std::vector<sunmap::OverlayRequest> requests_;
  std::vector<std::unique_ptr<ExactFace>> map_faces_;  ///< per face, until assembled: requests_' faces
  std::vector<std::vector<Curve>> outline_;  ///< per face, with its view: its chart's outline (tag n)
  std::vector<mpq_class> base_;  ///< the full map: per face, the hours of the instants lighting it whole
  std::vector<std::vector<sunmap::Strip>> strips_;           ///< the threshold map alone: per face
  std::vector<std::vector<sunmap::LevelRounds>> rounds_;     ///< per face and strip
  std::vector<mpq_class> whole_pending_;  ///< per face: whole-face hours before its strips exist
  std::vector<std::vector<Curve>> sample_;  ///< per face: boundaries held until its strips are chosen
  std::vector<std::size_t> sampled_;        ///< per face: instants in sample_ (from the first that cut it)
  std::vector<sunmap::FaceTiles> tiles_;    ///< per face (gathered): where each instant may light it
  std::vector<std::vector<RoughSegment>> rough_;  ///< per face (gathered, not kept): every boundary, in doubles
  /// Per face (the full map, or the threshold map gathered): every boundary, while kept.
  std::vector<sunmap::PackedBoundaries> packed_;
  std::vector<char> keep_exact_;            ///< per face (gathered): its exact boundaries are kept
  std::size_t kept_segments_ = 0;           ///< the threshold map gathered: in packed_, all faces together
  std::size_t again_ = 0;                   ///< face-instant pairs computed again
  std::vector<std::vector<std::size_t>> order_;  ///< per face (gathered): its instants in sweep order
  std::vector<std::vector<std::vector<std::size_t>>> rough_which_;  ///< per face and strip: its rough segments
  std::vector<std::vector<std::size_t>> band_ends_;  ///< per face (gathered): its bands' ends in order_
  double tile_bits_ = sunmap::kMaxTileBits;  ///< the most bits of masks one face's tiles may take
  std::vector<std::vector<sunmap::StripMap>> strip_maps_;  ///< per face and strip, once finished
  std::unique_ptr<std::atomic<std::size_t>[]> strips_left_;  ///< per face: its strips not finished
  std::vector<sunmap::FaceMap> face_maps_;  ///< per face, assembled by its last strip (threshold map)
  SeriesResult* table_ = nullptr;           ///< SunHoursOptions::series_table, when asked for
  std::vector<std::size_t> table_row_;      ///< per face: its row in table_ (SIZE_MAX: not a receiver)
};

}  // namespace

SunHoursMap compute_sun_hours_map(const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                                  const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options) {
  return MapBuilder(engine, faces, instants, options).build();
}

}  // namespace shadow
