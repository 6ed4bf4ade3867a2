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

#include <shadow/series.hpp>

#include <shadow/error.hpp>
#include <shadow/sun_hours.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

namespace shadow {
namespace {

using namespace exact;
using sunmap::Curve;

/// What one instant leaves on one face.
struct InstantPart {
  LitRegion::Kind kind = LitRegion::Kind::Dark;
  std::vector<Curve> curves;  ///< Partial: the lit region's boundary, tagged with the instant
  mpq_class lit_area{0};      ///< the lit region's exact chart area (no lazy DAG kept)
};

/// The instants' weights, their lights and weights checked.
std::vector<double> checked_hours(const std::vector<SunHoursInstant>& instants) {
  std::vector<double> hours(instants.size());
  for (std::size_t i = 0; i < instants.size(); ++i) {
    const std::string path = "instants[" + std::to_string(i) + "]";
    shadow::detail::check_light(instants[i].light, "", path + ".light");
    const double w = instants[i].hours;
    if (!std::isfinite(w) || w < 0)
      throw InputError({"", path + ".hours"}, "hours must be finite and >= 0, got " + std::to_string(w));
    hours[i] = w;
  }
  return hours;
}

/// The face ids checked, ascending, repeats dropped.
std::vector<std::size_t> checked_faces(const Scene& scene, const std::vector<std::size_t>& faces_in) {
  std::vector<std::size_t> faces;
  for (std::size_t k = 0; k < faces_in.size(); ++k) {
    if (faces_in[k] >= scene.faces.size())
      throw InputError({"", "sun-hours map faces[" + std::to_string(k) + "]"},
                       "face id " + std::to_string(faces_in[k]) + " is out of range (the scene has " +
                           std::to_string(scene.faces.size()) + " faces)");
    faces.push_back(faces_in[k]);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

/// Checks and sorts the levels: ascending, repeats dropped.
std::vector<double> checked_levels(const std::vector<double>& levels) {
  for (std::size_t k = 0; k < levels.size(); ++k)
    if (!std::isfinite(levels[k]) || levels[k] < 0)
      throw InputError({"", "levels[" + std::to_string(k) + "]"},
                       "a level must be finite and >= 0 hours, got " + std::to_string(levels[k]));
  std::vector<double> out = levels;
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// One face's part of the map, its strips' parts concatenated (region ids local to the face).
struct FaceMap {
  std::vector<SunHoursCell> cells, level_cells;
  std::size_t regions = 0, level_regions = 0;
  SunHoursFace face;
};

FaceMap assemble(std::vector<sunmap::StripMap>& strips, SunHoursFace face, const mpq_class& scale, std::size_t levels) {
  FaceMap out;
  std::map<mpq_class, std::vector<const std::vector<mpq_class>*>> hour_area;
  std::vector<std::vector<const std::vector<mpq_class>*>> level_area(levels + 1);
  mpq_class dropped(0);
  for (sunmap::StripMap& s : strips) {
    for (SunHoursCell& c : s.cells) {
      c.region_id += out.regions;
      out.cells.push_back(std::move(c));
    }
    out.regions += s.regions;
    s.cells = {};
    for (SunHoursCell& c : s.level_cells) {
      c.region_id += out.level_regions;
      out.level_cells.push_back(std::move(c));
    }
    out.level_regions += s.level_regions;
    s.level_cells = {};
    for (const auto& [hours, areas] : s.hour_area) hour_area[hours].push_back(&areas);
    for (std::size_t k = 0; k < s.level_area.size() && k <= levels; ++k) level_area[k].push_back(&s.level_area[k]);
    dropped += s.dropped;
  }
  face.dropped_area = sunmap::area_3d_mpq(dropped, scale);
  for (const auto& [hours, parts] : hour_area)
    face.areas.push_back({exact::round_mpq_to_double(hours.get_mpq_t()), sunmap::area_3d_of_sum(parts, scale)});
  // At least level k: the cells of the levels k and above, summed exactly.
  std::vector<const std::vector<mpq_class>*> at_least;
  face.level_areas.assign(levels, 0.0);
  for (std::size_t k = levels; k >= 1; --k) {
    at_least.insert(at_least.end(), level_area[k].begin(), level_area[k].end());
    face.level_areas[k - 1] = sunmap::area_3d_of_sum(at_least, scale);
  }
  out.face = std::move(face);
  strips.clear();
  return out;
}

}  // namespace

std::vector<double> sun_hours_level_areas(const SunHoursMap& map) {
  std::vector<double> out(map.levels.size(), 0.0);
  for (const SunHoursFace& f : map.faces)
    for (std::size_t k = 0; k < f.level_areas.size() && k < out.size(); ++k) out[k] += f.level_areas[k];
  return out;
}

double sun_hours_map_area(const SunHoursMap& map) {
  double area = 0.0;
  for (const SunHoursFace& f : map.faces) area += f.area;
  return area;
}

namespace {

/// The map of `faces` under `instants`: the lit regions of a batch of instants at a time (every
/// face-instant pair of the batch in parallel), then handed on before the next batch is computed.
/// The full map gathers each face's boundaries (its strips' one sweep needs them all); so does
/// the threshold map alone, whose strips then run their rounds (sunmap::LevelRounds) one job per
/// strip, settling cells by the face's tiles (sunmap::FaceTiles); with stream_levels it feeds
/// each batch to its strips' rounds instead and drops it.
class MapBuilder {
 public:
  MapBuilder(const ShadowEngine& engine, const std::vector<std::size_t>& faces_in,
             const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options)
      : ctx_(shadow::engine::prepared_scene(engine)),
        instants_(instants),
        options_(options),
        threads_(runtime::resolve_threads(runtime::checked_threads(options.threads))),
        hours_(checked_hours(instants)),
        faces_(checked_faces(*ctx_.scene, faces_in)),
        n_(instants.size()) {
    map_.levels = checked_levels(options.levels);
    full_ = options.full || map_.levels.empty();
    map_.full = full_;
    for (double w : hours_) map_.total_hours += w;  // informative; cells are summed exactly
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
    for (std::size_t i = n_; i-- > 0;) unfed[i] = unfed[i + 1] + mpq_class(hours_[i]);
    for (std::size_t first = 0; first < n_; first += batch) {
      const std::size_t count = std::min(batch, n_ - first);
      lit_batch(first, count);
      take_batch(first, count, unfed[first + count]);
    }
    if (table_)
      for (const Worker& w : workers_) table_->stats += w.stats;  // the rows' pairs in the lit pass
    std::vector<std::vector<sunmap::StripMap>> strip_maps = full_ ? overlay_full() : finish_levels();
    // The faces in order, region ids shifted by the earlier faces'.
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      face_info_[k].hour_area = sunmap::area_3d_mpq(hour_area_[k], scales_[k]);
      FaceMap fm = assemble(strip_maps[k], face_info_[k], scales_[k], map_.levels.size());
      if (!full_) fm.face.areas.clear();
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
    }
    return std::move(map_);
  }

 private:
  struct Worker {
    ExactWorker exact;
    ShadowStats stats;        ///< the table's rows' pairs (SunHoursOptions::series_table)
    ShadowStats other_stats;  ///< the other faces' pairs (not receiving faces)
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
    if (full_) bounds_.resize(count);
    else {
      tiles_.resize(count);
      strip_maps_.resize(count);
      finished_.assign(count, 0);
      rounds_.resize(count);
      whole_pending_.assign(count, mpq_class(0));
      sample_.resize(count);
      sampled_.assign(count, 0);
    }
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t f = faces_[k];
      SunHoursFace& info = face_info_[k];
      info.face_id = f;
      info.area = (*ctx_.face_area)[f];
      info.level_areas.assign(map_.levels.size(), 0.0);
      const core::FacePrep& fp = (*ctx_.prep)[f];
      if (fp.degenerate) continue;
      const ExactFace& P = workers_[0].exact.face(ctx_, f);
      exact_to_mpq(P.area_scale_squared, scales_[k].get_mpq_t());
      sunmap::add_boundary(P.chart, static_cast<long>(n_), outline_[k]);
      requests_[k] = sunmap::OverlayRequest{&P,      &fp,     f, &hours_, options_.merge_equal, full_, level_q_,
                                            options_.level_round_edges};
    }
  }

  /// 1. The lit regions of instants [first, first + count) on every face, face-instant pairs in
  /// parallel (one large ground uses every thread), into parts_ (face-major).
  void lit_batch(std::size_t first, std::size_t count) {
    // The culling grid of each directional light of the batch, shared read-only by the threads.
    // Built one per thread at a time, as compute_series builds a batch's.
    std::vector<std::optional<core::LightSpaceGrid>> grids(count);
    runtime::parallel_for(count, threads_, [&](unsigned, std::size_t j) {
      if (instants_[first + j].light.type == LightType::Directional)
        grids[j].emplace(*ctx_.cull, *ctx_.prep, instants_[first + j].light.to_light, ctx_.solid_of);
    });
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
          const ExactFace& P = w.exact.face(ctx_, f);
          const ExactLight light = to_exact_light(instants_[i].light);
          const int side = CGAL::sign(plane_at_light(P, light));
          // The lit region's canonical boundary: the same segments whichever route made it.
          const LitBoundary region = exact_lit_boundary(ctx_, w.exact, f, i, light, side, instants_[i].light,
                                                        grids[j] ? &*grids[j] : nullptr, stats);
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
          ++done_;
        },
        report_);
  }

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
        if (hours_[i] != 0 && sgn(part.lit_area) != 0) hour_area_[k] += mpq_class(hours_[i]) * part.lit_area;
        if (part.kind == LitRegion::Kind::Whole) whole[k] += mpq_class(hours_[i]);
        std::vector<Curve>& into = full_ ? bounds_[k].curves : curves[k];
        for (Curve& c : part.curves) into.push_back(std::move(c));
        part = InstantPart{};
      }
      if (full_) bounds_[k].base += whole[k];
    }
    parts_ = {};
    if (full_) return;
    // A face's strips are chosen from its first 16 instants that cut it (or every instant, if
    // fewer; their boundaries are held until then), sized by those instants' segments: rounds
    // bound each strip's arrangement, but its kept edges (about a day's boundaries, undecided or
    // on a level's border) want strips too. A smaller sample misjudged them (the first few suns
    // of a day, low, cut a ground little), and sizing by every instant to come would give each
    // of ever more strips a round's worth of instants not yet swept: memory linear in them.
    std::vector<std::tuple<std::size_t, std::size_t, std::vector<std::size_t>>> jobs;  // face, strip, curves
    const bool last = first + count == n_;
    if (last && !options_.stream_levels) {
      // The tiles of every face cut share one budget (they are all made before the strips run).
      std::size_t cut = 0;
      for (std::size_t k = 0; k < faces_.size(); ++k)
        if (rounds_[k].empty() && !(sample_[k].empty() && curves[k].empty())) ++cut;
      const double share = sunmap::kMaxTileBitsAll / static_cast<double>(std::max<std::size_t>(cut, 1));
      tile_bits_ = std::min(sunmap::kMaxTileBits, share);
    }
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if ((*ctx_.prep)[faces_[k]].degenerate) continue;
      if (rounds_[k].empty()) {
        whole_pending_[k] += whole[k];
        whole[k] = 0;
        if (sample_[k].empty() && curves[k].empty()) continue;  // not cut yet
        sampled_[k] += count;
        for (Curve& c : curves[k]) sample_[k].push_back(std::move(c));
        if ((!options_.stream_levels || sampled_[k] < 16) && !last) continue;  // gathering
        curves[k] = std::move(sample_[k]);
        sample_[k] = {};
        if (!options_.stream_levels) make_tiles(k, curves[k], whole_pending_[k]);
        start_rounds(k, curves[k], curves[k].size());
        whole[k] = whole_pending_[k];
        whole_pending_[k] = 0;
      }
      std::vector<std::vector<std::size_t>> which = sunmap::bucket_curves(curves[k], strips_[k]);
      for (std::size_t s = 0; s < which.size(); ++s) jobs.emplace_back(k, s, std::move(which[s]));
    }
    // After the last batch each strip is finished in the same job (its level regions written and
    // its arrangement freed), one strip after another per thread.
    // A face's tiles go with its last strip (two bits per tile and instant cutting the face).
    std::unique_ptr<std::atomic<std::size_t>[]> strips_left(new std::atomic<std::size_t>[faces_.size()]);
    for (std::size_t k = 0; k < faces_.size(); ++k) strips_left[k].store(0);
    for (const auto& job : jobs) {
      if (last) finished_[std::get<0>(job)] = 1;
      ++strips_left[std::get<0>(job)];
    }
    runtime::parallel_for(jobs.size(), threads_, [&](unsigned, std::size_t j) {
      runtime::check_stop();
      const auto& [k, s, which] = jobs[j];
      rounds_[k][s].feed(curves[k], which, whole[k], unfed, first + count);
      if (!last) return;
      strip_maps_[k][s] = rounds_[k][s].finish();
      if (strips_left[k].fetch_sub(1) == 1) tiles_[k] = sunmap::FaceTiles{};
      ++done_;
    });
  }

  /// Face k's tiles (sunmap::FaceTiles) from every instant's boundaries on it (`curves`, in time
  /// order, each instant's together) and the hours of those lighting it whole: its rounds then
  /// settle a cell by the instants not yet swept that may light the tiles under it.
  void make_tiles(std::size_t k, const std::vector<Curve>& curves, const mpq_class& whole) {
    std::vector<std::pair<std::size_t, std::size_t>> runs;  // per instant cutting the face: [begin, end)
    for (std::size_t c = 0; c < curves.size(); ++c)
      if (c == 0 || std::labs(curves[c].data()) != std::labs(curves[c - 1].data()))
        runs.emplace_back(c, c + 1);
      else
        runs.back().second = c + 1;
    std::size_t most = 0;
    for (const auto& [b, e] : runs) most = std::max(most, e - b);
    sunmap::FaceTiles& t = tiles_[k];
    t.grid = sunmap::tile_grid(requests_[k].face->chart, most, runs.size(), tile_bits_);
    if (t.grid.n == 0) return;
    t.whole = whole;
    t.instants.resize(runs.size());
    for (std::size_t r = 0; r < runs.size(); ++r)
      t.instants[r] = static_cast<std::size_t>(std::labs(curves[runs[r].first].data()) - 1);
    t.masks.assign(t.grid.words() * runs.size(), 0);
    t.whole_masks.assign(t.grid.words() * runs.size(), 0);
    runtime::parallel_for(runs.size(), threads_, [&](unsigned, std::size_t r) {
      const auto [b, e] = runs[r];
      sunmap::mark_lit_tiles(t.grid, curves.data() + b, curves.data() + e, t.masks.data() + r * t.grid.words(),
                             t.whole_masks.data() + r * t.grid.words());
    });
    requests_[k].tiles = &t;
  }

  /// The strips of face k (from `sample`, the boundaries of its first instants that cut it, and
  /// its outline, sized by `expected` boundary segments) and their rounds, each starting from the
  /// outline.
  void start_rounds(std::size_t k, const std::vector<Curve>& sample, std::size_t expected) {
    std::vector<Curve> with_outline = sample;
    with_outline.insert(with_outline.end(), outline_[k].begin(), outline_[k].end());
    if (strips_.size() < faces_.size()) strips_.resize(faces_.size());
    strips_[k] = sunmap::choose_strips(with_outline, expected + outline_[k].size(), requests_[k].face->chart,
                                       options_.strip_edges);
    const std::vector<std::vector<std::size_t>> which = sunmap::bucket_curves(outline_[k], strips_[k]);
    for (std::size_t s = 0; s < strips_[k].size(); ++s)
      rounds_[k].emplace_back(requests_[k], strips_[k][s], outline_[k], which[s]);
    strip_maps_[k].resize(rounds_[k].size());
  }

  /// 3. The full map: per face its outline and strips, then face-strip pairs in parallel.
  std::vector<std::vector<sunmap::StripMap>> overlay_full() {
    std::vector<std::vector<sunmap::Strip>> strips(faces_.size());
    std::vector<std::vector<std::vector<std::size_t>>> buckets(faces_.size());
    std::vector<std::pair<std::size_t, std::size_t>> jobs;  // (face index, strip)
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if ((*ctx_.prep)[faces_[k]].degenerate) continue;
      sunmap::FaceBoundaries& b = bounds_[k];
      for (Curve& c : outline_[k]) b.curves.push_back(std::move(c));
      outline_[k] = {};
      strips[k] = sunmap::choose_strips(b.curves, b.curves.size(), requests_[k].face->chart, options_.strip_edges);
      buckets[k] = sunmap::bucket_curves(b.curves, strips[k]);
      for (std::size_t s = 0; s < strips[k].size(); ++s) jobs.emplace_back(k, s);
    }
    total_ = faces_.size() * n_ + jobs.size();
    std::vector<std::vector<sunmap::StripMap>> strip_maps(faces_.size());
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
          strip_maps[k][s] = sunmap::overlay_strip(requests_[k], bounds_[k], buckets[k][s], strips[k][s]);
          buckets[k][s] = {};
          if (strips_left[k].fetch_sub(1) == 1) bounds_[k] = {};
          ++done_;
        },
        report_);
    return strip_maps;
  }

  /// 3. The threshold map alone: the rounds left and the level regions, face-strip pairs in
  /// parallel. A face no instant cut gets its strips (one, unless its outline is long) now.
  std::vector<std::vector<sunmap::StripMap>> finish_levels() {
    std::vector<std::pair<std::size_t, std::size_t>> jobs;
    std::size_t strips = 0;
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      if ((*ctx_.prep)[faces_[k]].degenerate) continue;
      if (rounds_[k].empty()) {
        start_rounds(k, {}, 0);
        for (std::size_t s = 0; s < rounds_[k].size(); ++s)
          rounds_[k][s].feed({}, {}, whole_pending_[k], mpq_class(0), n_);
      }
      strips += rounds_[k].size();
      if (finished_[k]) continue;
      for (std::size_t s = 0; s < rounds_[k].size(); ++s) jobs.emplace_back(k, s);
    }
    total_ = faces_.size() * n_ + strips;
    runtime::parallel_for(
        jobs.size(), threads_,
        [&](unsigned, std::size_t j) {
          runtime::check_stop();
          const auto [k, s] = jobs[j];
          strip_maps_[k][s] = rounds_[k][s].finish();
          ++done_;
        },
        report_);
    return std::move(strip_maps_);
  }

  core::PreparedScene ctx_;
  const std::vector<SunHoursInstant>& instants_;
  const SunHoursOptions& options_;
  unsigned threads_;
  std::vector<double> hours_;
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
  std::vector<std::vector<Curve>> outline_;  ///< per face: its chart's outline (tag n)
  std::vector<sunmap::FaceBoundaries> bounds_;  ///< the full map: per face, every boundary
  std::vector<std::vector<sunmap::Strip>> strips_;           ///< the threshold map alone: per face
  std::vector<std::vector<sunmap::LevelRounds>> rounds_;     ///< per face and strip
  std::vector<mpq_class> whole_pending_;  ///< per face: whole-face hours before its strips exist
  std::vector<std::vector<Curve>> sample_;  ///< per face: boundaries held until its strips are chosen
  std::vector<std::size_t> sampled_;        ///< per face: instants in sample_ (from the first that cut it)
  std::vector<sunmap::FaceTiles> tiles_;    ///< per face (gathered): where each instant may light it
  double tile_bits_ = sunmap::kMaxTileBits;  ///< the most bits of masks one face's tiles may take
  std::vector<std::vector<sunmap::StripMap>> strip_maps_;  ///< per face and strip, once finished
  std::vector<char> finished_;              ///< per face: its strips finished with the last batch
  SeriesResult* table_ = nullptr;           ///< SunHoursOptions::series_table, when asked for
  std::vector<std::size_t> table_row_;      ///< per face: its row in table_ (SIZE_MAX: not a receiver)
};

}  // namespace

SunHoursMap compute_sun_hours_map(const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                                  const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options) {
  return MapBuilder(engine, faces, instants, options).build();
}

void add_sun_hours_levels(SunHoursMap& map, const ShadowEngine& engine, const std::vector<std::size_t>& faces,
                          const std::vector<SunHoursInstant>& instants, const std::vector<double>& levels,
                          unsigned threads) {
  SunHoursOptions options;
  options.threads = threads;
  options.levels = levels;
  options.full = false;
  SunHoursMap with = compute_sun_hours_map(engine, faces, instants, options);
  if (with.faces.size() != map.faces.size())
    throw std::invalid_argument("add_sun_hours_levels: the map has other faces than those given");
  for (std::size_t k = 0; k < map.faces.size(); ++k) {
    if (with.faces[k].face_id != map.faces[k].face_id)
      throw std::invalid_argument("add_sun_hours_levels: the map has other faces than those given");
    map.faces[k].level_areas = std::move(with.faces[k].level_areas);
  }
  map.levels = std::move(with.levels);
  map.level_cells = std::move(with.level_cells);
  map.level_regions = with.level_regions;
}

std::string sun_hours_levels_summary(const SunHoursMap& map, const std::string& indent) {
  if (map.levels.empty()) return {};
  const double area = sun_hours_map_area(map);
  const std::vector<double> at_least = sun_hours_level_areas(map);
  std::string out;
  char line[256];
  for (std::size_t k = 0; k < map.levels.size(); ++k) {
    std::snprintf(line, sizeof line, "%sat least %g h of sun: area %.6g of %.6g (%.1f%%)\n", indent.c_str(), map.levels[k],
                  at_least[k], area, area > 0 ? 100.0 * at_least[k] / area : 0.0);
    out += line;
  }
  std::snprintf(line, sizeof line, "%sthreshold map: %zu cells (sun_hours_levels.vtp)\n", indent.c_str(), map.level_cells.size());
  out += line;
  return out;
}

std::vector<double> parse_sun_hours_levels(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::string where = what + " item " + std::to_string(out.size() + 1);
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used == 0 || item.find_first_not_of(" \t", used) != std::string::npos)
      throw InputError({"", where}, "expected a number of hours, got \"" + item + "\"");
    if (!std::isfinite(value) || value < 0)
      throw InputError({"", where}, "a level must be finite and >= 0 hours, got \"" + item + "\"");
    out.push_back(value);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<std::size_t> sun_hours_map_faces(const Scene& scene) {
  std::vector<std::size_t> faces;
  for (std::size_t k = 0; k < scene.sun_hours_map.size(); ++k) {
    const std::size_t m = scene.sun_hours_map[k];
    if (m >= scene.meshes.size())  // a scene built in code: load_scene only stores valid indices
      throw InputError({scene.source.string(), "sun_hours_map[" + std::to_string(k) + "]"},
                       "mesh index " + std::to_string(m) + " is out of range (the scene has " +
                           std::to_string(scene.meshes.size()) + " meshes)");
    const Mesh& mesh = scene.meshes[m];
    for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count; ++f) faces.push_back(f);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

std::vector<std::size_t> sun_hours_map_faces(const Scene& scene, const std::vector<std::string>& mesh_names,
                                             const std::string& what) {
  Scene chosen;
  chosen.meshes = scene.meshes;
  // A mesh's name, or type:<T> for every mesh of a CityJSON object type (select_meshes).
  for (std::size_t k = 0; k < mesh_names.size(); ++k)
    for (std::size_t m : select_meshes(scene, mesh_names[k], {"", what})) chosen.sun_hours_map.push_back(m);
  return sun_hours_map_faces(chosen);
}

std::vector<SunHoursInstant> sun_hours_instants(const Scene& scene) {
  std::vector<SunHoursInstant> out;
  if (!scene.sun) return out;
  const double step_hours = hours_per_instant(*scene.sun);  // the series' rule (shadow/series.hpp)
  for (const SunInstant& instant : scene.sun_instants) {
    if (instant.light_id == SunInstant::none || instant.light_id >= scene.lights.size()) continue;
    out.push_back({scene.lights[instant.light_id], step_hours});
  }
  return out;
}

std::vector<SunHoursInstant> sun_hours_instants(const SunSeries& suns) {
  std::vector<SunHoursInstant> out;
  out.reserve(suns.lights.size());
  for (const Light& light : suns.lights) out.push_back({light, suns.hours_per_instant});
  return out;
}

}  // namespace shadow
