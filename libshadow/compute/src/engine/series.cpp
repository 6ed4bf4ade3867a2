// SPDX-License-Identifier: GPL-3.0-or-later
// ShadowEngine::compute_series: the many suns of a period on every receiving face, areas only.
//
// The same per-receiver computation as ShadowEngine::compute (fast path with its exact fallback,
// or exact), so every value equals a one-light compute(light, i, {polygons = false}) bit for
// bit; what differs is what is shared. One set of workers (their exact faces and caster scratch
// built on first use) serves every instant instead of being made afresh per call, and the work
// is handed out over the (instant, receiver) pairs of a batch of instants, so that no thread
// waits at the end of each instant for the slowest receiver, and the table is filled in place
// (no ShadowResult per instant). The items run on the engine's one scheduler (engine/rounds.cpp),
// as compute()'s receivers do.
#include "engine/engine_impl.hpp"

#include "arealight/area_receiver.hpp"

#include "core/lights.hpp"
#include "core/spatial_order.hpp"
#include "geometry/unit_vector.hpp"
#include "runtime/parallel.hpp"
#include "exact/lazy_geometry.hpp"

#include <shadow/error.hpp>
#include <shadow/series.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace shadow {
namespace {

/// The indices of `lights` with the directional ones ordered along a Z-order curve over their
/// directions' azimuth and height (neighbouring suns next to each other), the others after them
/// in their own order. Only the order in which instants are computed: each is computed alone.
std::vector<std::size_t> by_direction(const std::vector<Light>& lights) {
  auto spread = [](std::uint64_t x) {  // the 16 bits of x to the even bits of 32
    x &= 0xffff;
    x = (x | (x << 8)) & 0x00ff00ff;
    x = (x | (x << 4)) & 0x0f0f0f0f;
    x = (x | (x << 2)) & 0x33333333;
    x = (x | (x << 1)) & 0x55555555;
    return x;
  };
  auto quantise = [](double t) {  // t in [0, 1]
    return static_cast<std::uint64_t>(std::clamp(t, 0.0, 1.0) * 65535.0);
  };
  constexpr double kPi = 3.14159265358979323846;
  std::vector<std::uint64_t> key(lights.size(), UINT64_MAX);
  for (std::size_t i = 0; i < lights.size(); ++i) {
    if (lights[i].type != LightType::Directional) continue;
    const glm::dvec3 d = lights[i].to_light / glm::length(lights[i].to_light);
    const double azimuth = std::atan2(d.y, d.x);
    if (!std::isfinite(azimuth) || !std::isfinite(d.z)) continue;
    key[i] = spread(quantise((azimuth + kPi) / (2 * kPi))) | (spread(quantise(0.5 * (d.z + 1))) << 1);
  }
  std::vector<std::size_t> order(lights.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  return order;
}

/// The table while it is computed. Batches of neighbouring suns (receiver by receiver) write
/// into a stage of a few batches, one compact block per batch (a receiver's values for the
/// batch side by side); a full stage goes into the row-major table as one contiguous run per
/// row, its columns in the computing order (column p holds instant order[p]); at the end each
/// row is put in the lights' order. Writing a few cells into every row of the table once per
/// batch had been a third of the fast path's time on the 2-core benchmark machine (a virtual
/// machine, where a 4 KiB page not touched for ~100 ms costs microseconds to touch again;
/// anywhere, a cache and TLB miss per cell): docs/benchmarks.md, "Ninth look". The stage holds
/// 64 instants, or one batch where a batch is larger (4 per thread beyond 16 threads), and no
/// more than the table: memory beyond the table's stays small.
class StagedTable {
 public:
  StagedTable(SeriesResult& result, std::size_t rows, std::size_t instants, std::size_t batch)
      : result_(result), rows_(rows), instants_(instants), batch_(batch),
        length_(std::min(instants, batch * std::max<std::size_t>(1, 64 / batch))) {
    result.zero_entries();  // (rows x instants: the result's rows and columns)
    each_array([&](auto& stage, auto&) { stage.resize(rows * length_); });
  }

  /// Before the batch starting at `position` (a multiple of the batch size): the stage before
  /// it goes into the table when the batch starts a new one.
  void begin_batch(std::size_t position, unsigned threads) {
    if (position >= first_ + length_) {
      flush(threads);
      first_ = position - position % length_;
    }
  }

  void write(std::size_t r, std::size_t position, const FaceLighting& lighting) {
    const std::size_t at = cell(r, position);
    lit_area_[at] = lighting.lit_area;
    lit_fraction_[at] = lighting.lit_fraction;
    faces_light_[at] = lighting.faces_light ? 1 : 0;
    bound_[at] = lighting.lit_area_error_bound;
  }

  /// The last stage into the table, then every row from the computing order to the lights'.
  void finish(const std::vector<std::size_t>& order, unsigned threads) {
    flush(threads);
    bool identity = true;
    for (std::size_t p = 0; p < order.size() && identity; ++p) identity = order[p] == p;
    if (identity) return;
    // Per thread, a row of each element type in the computing order.
    std::vector<std::tuple<std::vector<double>, std::vector<unsigned char>>> scratch(threads);
    runtime::parallel_for(rows_, threads, [&](unsigned wi, std::size_t r) {
      each_array([&](auto&, auto& table) {
        using Row = std::decay_t<decltype(table)>;
        auto* const row = table.data() + result_.at(r, 0);
        Row& computed = std::get<Row>(scratch[wi]);
        computed.assign(row, row + instants_);
        for (std::size_t p = 0; p < instants_; ++p) row[order[p]] = computed[p];
      });
    });
  }

 private:
  /// The stage's cell of row r at `position` (in the current stage).
  [[nodiscard]] std::size_t cell(std::size_t r, std::size_t position) const {
    const std::size_t batch_first = position - position % batch_;
    const std::size_t width = std::min(batch_, instants_ - batch_first);
    return (batch_first - first_) * rows_ + r * width + (position - batch_first);
  }

  /// The stage's positions [first_, first_ + length_) into every row, rows in groups of 64.
  void flush(unsigned threads) {
    const std::size_t end = std::min(first_ + length_, instants_);
    runtime::parallel_for_blocks(rows_, 64, threads, [&](unsigned, std::size_t, std::size_t begin, std::size_t stop) {
      for (std::size_t r = begin; r < stop; ++r)
        for (std::size_t b = first_; b < end; b += batch_) {
          const std::size_t width = std::min(batch_, instants_ - b);
          const std::size_t from = (b - first_) * rows_ + r * width, to = result_.at(r, b);
          each_array([&](auto& stage, auto& table) { std::copy_n(stage.data() + from, width, table.data() + to); });
        }
    });
  }

  /// f(stage, table) for each of the four results: the stage's array and the table's.
  template <class F>
  void each_array(F&& f) {
    f(lit_area_, result_.lit_area);
    f(lit_fraction_, result_.lit_fraction);
    f(bound_, result_.lit_area_error_bound);
    f(faces_light_, result_.faces_light);
  }

  SeriesResult& result_;
  std::size_t rows_, instants_, batch_, length_;
  std::size_t first_ = 0;  ///< the stage's first position
  std::vector<double> lit_area_, lit_fraction_, bound_;
  std::vector<unsigned char> faces_light_;
};

/// The rows compute_series computes: every receiver (`rows`, face ids) but the given ones,
/// whose entries stay 0 (SeriesOptions::given_faces).
std::vector<std::size_t> rows_to_compute(const std::vector<std::size_t>& rows, const std::vector<std::size_t>& given_faces,
                                         std::size_t face_count) {
  std::vector<char> given(face_count, 0);
  for (std::size_t f : given_faces)
    if (f < face_count) given[f] = 1;
  std::vector<std::size_t> out;
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (!given[rows[r]]) out.push_back(r);
  return out;
}

/// The rows to compute (rows_to_compute) along a curve through the scene
/// (core/spatial_order.hpp), the order their items are computed in: neighbouring receivers share
/// casters, which the worker then still has.
std::vector<std::size_t> along_the_scene(const ShadowEngine::Impl& impl, const std::vector<std::size_t>& faces,
                                         const std::vector<std::size_t>& given, unsigned threads) {
  const std::vector<std::size_t> rows = rows_to_compute(faces, given, impl.scene->faces.size());
  const std::vector<std::size_t> along = core::spatial_order(
      impl.cull, impl.solid_of, impl.solids, rows.size(), [&](std::size_t c) { return faces[rows[c]]; }, threads);
  std::vector<std::size_t> out(rows.size());
  for (std::size_t i = 0; i < along.size(); ++i) out[i] = rows[along[i]];
  return out;
}

/// A batch's pairs turned away from their suns written into the table as attached shadows
/// (engine_detail::split_turned_away); `live` gets the batch's other items, c * count + k (c
/// indexing computed_rows, sun k: lights[instant[k]] at position first + k), in item order.
void split_batch(const core::CullScene& cull, const std::vector<Light>& lights, const std::size_t* instant,
                 std::size_t count, const std::vector<std::size_t>& faces, const std::vector<std::size_t>& computed_rows,
                 std::size_t first, StagedTable& table, std::vector<std::size_t>& live,
                 std::vector<ShadowEngine::Impl::ThreadState>& workers) {
  std::vector<std::optional<glm::dvec3>> suns(count);
  for (std::size_t k = 0; k < count; ++k) {
    const Light& light = lights[instant[k]];
    if (light.type == LightType::Directional) suns[k] = geometry::unit(light.to_light);
  }
  engine_detail::split_turned_away(
      cull, computed_rows.size(), suns, [&](std::size_t c) { return faces[computed_rows[c]]; },
      [&](std::size_t c, std::size_t k) { table.write(computed_rows[c], first + k, FaceLighting{}); }, live, workers);
}

}  // namespace

SeriesResult ShadowEngine::compute_series(const std::vector<Light>& lights_in, const SeriesOptions& options) const {
  const Impl& impl = *impl_;
  const Scene& scene = *impl.scene;
  for (std::size_t i = 0; i < lights_in.size(); ++i)
    shadow::detail::check_light(lights_in[i], "", "lights[" + std::to_string(i) + "]");
  // Lit areas only: an extended light counts as its centre (docs/area-lights.md), so a series of
  // sun disks has the sunlit fractions of the point suns.
  std::vector<Light> lights;
  lights.reserve(lights_in.size());
  for (const Light& light : lights_in) lights.push_back(shadow::detail::centre_light(light));
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));
  const bool fast = options.arithmetic == Arithmetic::Fast;

  SeriesResult result;
  result.arithmetic = options.arithmetic;
  result.instants = lights.size();
  result.faces = engine_detail::receiving_faces(scene, threads);
  const std::size_t rows = result.faces.size();
  const std::size_t instants = lights.size();
  result.area.resize(rows);
  for (std::size_t r = 0; r < rows; ++r) result.area[r] = impl.face_area[result.faces[r]];
  if (rows == 0 || instants == 0) {
    if (options.progress) options.progress(Progress{instants, instants});
    return result;
  }

  const std::vector<std::size_t> computed_rows = along_the_scene(impl, result.faces, options.given_faces, threads);
  const std::size_t computed = computed_rows.size();
  if (computed == 0) {  // every row given: no worker, grid or batch
    result.zero_entries();
    if (options.progress) options.progress(Progress{instants, instants});
    return result;
  }

  std::vector<Impl::ThreadState> workers = impl.make_workers(threads, fast);
  // A batch of instants at a time: their light-space grids are built together, then each
  // (receiver, instant) pair not turned away from its sun is a work item. A few instants per
  // thread keep the threads busy to the batch's end without holding a grid per instant of the year.
  const std::size_t batch = std::min<std::size_t>(instants, std::max<std::size_t>(8, 4 * static_cast<std::size_t>(threads)));
  // The instants in the order of their suns' directions, so that a batch holds neighbouring suns
  // (the same hour on neighbouring days), not neighbouring hours.
  const std::vector<std::size_t> order = by_direction(lights);
  // The grid items' local boxes, once for every sun: items (convex solids) that a receiver's
  // culling tests rule out whole are skipped before their faces are read. (Declared before the
  // grids, which keep a pointer to them.)
  const std::vector<core::LocalBounds> item_bounds =
      core::LightSpaceGrid::item_bounds(impl.cull, impl.prep, &impl.solid_of, threads);
  std::vector<std::optional<core::LightSpaceGrid>> grids(batch);
  // Each worker makes its own exact lights: no Epeck number's count is shared between threads.
  std::vector<std::vector<std::optional<exact::ExactLight>>> exact_lights(threads);

  Impl::ItemMode mode;
  mode.fast = fast;
  mode.polygons = false;
  mode.split_above = fast ? options.fast_tile_casters : options.tile_casters;
  StagedTable table(result, rows, instants, batch);
  // Progress in instants, moving through both rounds of a batch: a fraction of the batch is done,
  // the first round standing for (1 - tile_share) of it and the tile round for the rest.
  // tile_share is the tile round's share of the previous batch's time (neighbouring instants
  // cost about the same); on the first batch, or after one without tiles, a split receiver
  // counts as one item that is done when its tiles are, as compute() counts receivers.
  engine_detail::ForwardProgress report_instants(options.progress, 0, instants);
  double tile_share = 0.0;
  std::vector<std::size_t> live;  // a batch's work items (c * count + k), in item order

  for (std::size_t first = 0; first < instants; first += batch) {
    const std::size_t count = std::min(batch, instants - first);
    table.begin_batch(first, threads);
    runtime::parallel_for(count, threads, [&](unsigned, std::size_t k) {
      grids[k].reset();
      const Light& light = lights[order[first + k]];
      if (light.type == LightType::Directional) grids[k].emplace(impl.cull, impl.prep, light.to_light, &impl.solid_of, 1, &item_bounds);
      if (grids[k] && engine_detail::outlines_pay(options.arithmetic, true, computed_rows.size(), impl.solids.size())) grids[k]->find_outlines(impl.solids);
    });
    for (auto& per_worker : exact_lights) per_worker.assign(count, std::nullopt);
    split_batch(impl.cull, lights, order.data() + first, count, result.faces, computed_rows, first, table, live, workers);

    auto report_fraction = [&](double fraction) {
      report_instants(first + std::min(count, static_cast<std::size_t>(std::max(0.0, fraction) * static_cast<double>(count))));
    };
    double round_fraction = 0;  // of the batch, at the first round's end
    Impl::RoundProgress progress;
    if (report_instants) {
      progress.first = [&](std::size_t done) {
        round_fraction = (1 - tile_share) * static_cast<double>(done) / static_cast<double>(std::max<std::size_t>(1, live.size()));
        report_fraction(round_fraction);
      };
      // The tile round: the rest of the batch, in proportion to the tiles done.
      progress.tiles = [&](std::size_t done, std::size_t total, std::size_t) {
        report_fraction(total == 0 ? 1.0
                                   : round_fraction + (1 - round_fraction) * static_cast<double>(done) /
                                                          static_cast<double>(total));
      };
    }
    // Receiver-major items: one receiver under the batch's neighbouring suns one after another,
    // so that its casters (nearly the same faces from one sun to the next) are still in cache.
    // Whole faces are trimmed as in compute() (compute_item): above 4,096 faces a worker
    // rebuilds exact faces it had built before. Measured side by side without the trim
    // (docs/benchmarks.md, "Memory"): CPU time the same within noise, peak memory 38% higher at
    // 2,500 boxes.
    const Impl::RoundsDone done = impl.compute_rounds(
        live.size(),
        [&](std::size_t i) {
          const std::size_t item = live[i], k = item % count, instant = order[first + k];
          return Impl::WorkItem{result.faces[computed_rows[item / count]], instant, &lights[instant],
                                grids[k] ? &*grids[k] : nullptr, k};
        },
        mode, workers,
        [&](unsigned wi, std::size_t slot) -> std::optional<exact::ExactLight>& { return exact_lights[wi][slot]; },
        [&](std::size_t i, const Impl::Item& out) {
          const std::size_t item = live[i];
          table.write(computed_rows[item / count], first + item % count, out.lighting);
        },
        progress);
    const double seconds = done.first_seconds + done.tile_seconds;
    tile_share = done.split > 0 && seconds > 0 ? done.tile_seconds / seconds : 0.0;
    report_instants(first + count);
  }
  table.finish(order, threads);
  // Area lights and disks shine forward only: their centre's areas cut to the light's emitting
  // side, as compute() does (docs/area-lights.md).
  for (std::size_t i = 0; i < instants; ++i) {
    const Light& light_in = lights_in[i];
    if (light_in.type != LightType::Area && light_in.type != LightType::Disk) continue;
    const core::PreparedScene ctx = impl.prepared();
    const arealight::AreaLightPrep area = arealight::prepare_area_light(ctx, light_in, i);
    std::vector<arealight::AreaWorker> area_workers(threads);
    runtime::parallel_for(computed, threads, [&](unsigned wi, std::size_t c) {
      const std::size_t r = computed_rows[c], at = result.at(r, i);
      FaceLighting lighting;
      lighting.face_id = result.faces[r];
      lighting.light_id = i;
      lighting.area = result.area[r];
      lighting.lit_area = result.lit_area[at];
      lighting.shadow_area = lighting.area - lighting.lit_area;
      lighting.lit_fraction = result.lit_fraction[at];
      lighting.lit_area_error_bound = result.lit_area_error_bound[at];
      arealight::restrict_centre_to_emitting_side(ctx, workers[wi].exact, area_workers[wi], area, result.faces[r], i,
                                                  lights[i], workers[wi].stats, lighting);
      result.lit_area[at] = lighting.lit_area;
      result.lit_fraction[at] = lighting.lit_fraction;
      result.lit_area_error_bound[at] = lighting.lit_area_error_bound;
    });
  }
  for (const Impl::ThreadState& w : workers) result.stats += w.stats;
  Impl::release_workers(workers);
  report_instants(instants);
  return result;
}

double hours_per_instant(const SunPeriod& period) {
  if (period.times.empty()) return period.step_minutes / 60.0;
  std::vector<UtcSeconds> times = period.times;
  std::sort(times.begin(), times.end());
  std::vector<UtcSeconds> gaps;
  for (std::size_t i = 1; i < times.size(); ++i)
    if (times[i] != times[i - 1]) gaps.push_back(times[i] - times[i - 1]);
  if (gaps.empty()) return 1.0;
  std::sort(gaps.begin(), gaps.end());
  const std::size_t n = gaps.size();
  // The median of an even count is the mean of the middle two (in seconds, exact in a double).
  const double median = n % 2 ? static_cast<double>(gaps[n / 2])
                              : 0.5 * (static_cast<double>(gaps[n / 2 - 1]) + static_cast<double>(gaps[n / 2]));
  return median / 3600.0;
}

SunSeries sun_series(const Scene& scene) {
  if (!scene.sun)
    throw InputError({"", "sun"}, "the scene has no `sun` block: a series needs the sun's period or times");
  SunSeries series;
  series.all_instants = scene.sun_instants.size();
  series.explicit_times = !scene.sun->times.empty();
  series.hours_per_instant = hours_per_instant(*scene.sun);
  for (std::size_t i = 0; i < scene.sun_instants.size(); ++i) {
    const SunInstant& instant = scene.sun_instants[i];
    if (instant.light_id == SunInstant::none) continue;
    if (instant.light_id >= scene.lights.size() || scene.lights[instant.light_id].type != LightType::Directional)
      throw InputError({"", "sun_instants[" + std::to_string(i) + "]"},
                       "names light " + std::to_string(instant.light_id) + ", which is not a directional light of the scene");
    series.lights.push_back(scene.lights[instant.light_id]);
    series.times.push_back(instant.time);
    series.instants.push_back(i);
  }
  return series;
}

std::vector<double> sun_hours(const SeriesResult& series, double hours) {
  std::vector<double> out(series.faces.size(), 0.0);
  for (std::size_t r = 0; r < series.faces.size(); ++r) {
    double sum = 0.0;  // at most 1 per instant: a plain sum in time order loses nothing that matters
    for (std::size_t i = 0; i < series.instants; ++i) sum += series.lit_fraction[series.at(r, i)];
    out[r] = sum * hours;
  }
  return out;
}

std::vector<double> sun_hours_error_bound(const SeriesResult& series, double hours) {
  std::vector<double> out(series.faces.size(), 0.0);
  for (std::size_t r = 0; r < series.faces.size(); ++r) {
    if (!(series.area[r] > 0.0)) continue;
    double sum = 0.0;
    for (std::size_t i = 0; i < series.instants; ++i) sum += series.lit_area_error_bound[series.at(r, i)];
    // Rounding of the division and the sum is far below the bound's own slack (it is one-sided:
    // nudge up by a relative 1e-12 so that it stays a bound).
    out[r] = sum / series.area[r] * hours * (1.0 + 1e-12);
  }
  return out;
}

SurfaceSeries surface_series(const Scene& scene, const SeriesResult& series, double hours) {
  SurfaceSeries out;
  out.instants = series.instants;
  out.surfaces = named_surfaces(scene, true);
  std::vector<std::size_t> row_of(scene.faces.size(), SIZE_MAX);
  for (std::size_t r = 0; r < series.faces.size(); ++r) row_of[series.faces[r]] = r;
  out.area.assign(out.surfaces.size(), 0.0);
  out.lit_fraction.assign(out.surfaces.size() * series.instants, 0.0);
  out.sun_hours.assign(out.surfaces.size(), 0.0);
  std::vector<double> lit(series.instants);
  for (std::size_t s = 0; s < out.surfaces.size(); ++s) {
    std::fill(lit.begin(), lit.end(), 0.0);
    double area = 0.0;
    for (std::size_t f : out.surfaces[s].faces) {
      const std::size_t r = f < row_of.size() ? row_of[f] : SIZE_MAX;
      if (r == SIZE_MAX) continue;  // not computed (the series was made for another scene)
      area += series.area[r];
      for (std::size_t i = 0; i < series.instants; ++i) lit[i] += series.lit_area[series.at(r, i)];
    }
    out.area[s] = area;
    double hours_sum = 0.0;
    for (std::size_t i = 0; i < series.instants; ++i) {
      // A single face: its own exact lit fraction, not lit_area / area re-rounded.
      double fraction = 0.0;
      if (out.surfaces[s].faces.size() == 1 && row_of[out.surfaces[s].faces[0]] != SIZE_MAX)
        fraction = series.lit_fraction[series.at(row_of[out.surfaces[s].faces[0]], i)];
      else if (area > 0.0)
        fraction = std::min(1.0, lit[i] / area);
      out.lit_fraction[s * series.instants + i] = fraction;
      hours_sum += fraction;
    }
    out.sun_hours[s] = hours_sum * hours;
  }
  return out;
}

ObjectSunHours object_sun_hours(const Scene& scene, const SeriesResult& series, double hours, bool per_mesh) {
  ObjectSunHours out;
  std::vector<std::size_t> row_of(scene.faces.size(), SIZE_MAX);
  for (std::size_t r = 0; r < series.faces.size(); ++r)
    if (series.faces[r] < row_of.size()) row_of[series.faces[r]] = r;
  for (SceneObject& object : scene_objects(scene, true, per_mesh)) {
    std::size_t faces = 0;
    double area = 0.0, lit = 0.0;
    for (const std::size_t m : object.meshes) {
      const Mesh& mesh = scene.meshes[m];
      for (std::size_t f = mesh.first_face; f < mesh.first_face + mesh.face_count && f < row_of.size(); ++f) {
        const std::size_t r = row_of[f];
        if (r == SIZE_MAX) continue;  // not computed (the series was made for another scene)
        ++faces;
        area += series.area[r];
        // Per face in time order, then over the faces: the order Python's sun_hours(by="mesh") sums in.
        double face_lit = 0.0;
        for (std::size_t i = 0; i < series.instants; ++i) face_lit += series.lit_area[series.at(r, i)];
        lit += face_lit;
      }
    }
    if (faces == 0) continue;
    out.objects.push_back(std::move(object));
    out.faces.push_back(faces);
    out.area.push_back(area);
    out.sun_hours.push_back(area > 0.0 ? lit / area * hours : 0.0);
    out.sunlit_area_hours.push_back(lit * hours);
  }
  return out;
}

}  // namespace shadow
