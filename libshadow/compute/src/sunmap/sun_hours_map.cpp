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

#include <shadow/series.hpp>

#include <shadow/error.hpp>
#include <shadow/sun_hours.hpp>

#include <gmpxx.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <exception>
#include <map>
#include <optional>
#include <string>
#include <utility>

namespace shadow {
namespace {

using namespace exact;
using sunmap::Curve;

/// What one instant leaves on one face.
struct InstantPart {
  LitRegion::Kind kind = LitRegion::Kind::Dark;
  std::vector<Curve> curves;  ///< Partial: the lit region's boundary, tagged with the instant
  FT lit_area{0};             ///< the lit region's exact chart area
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

SunHoursMap compute_sun_hours_map(const ShadowEngine& engine, const std::vector<std::size_t>& faces_in,
                                  const std::vector<SunHoursInstant>& instants, const SunHoursOptions& options) {
  const core::PreparedScene ctx = shadow::engine::prepared_scene(engine);
  const Scene& scene = *ctx.scene;
  const unsigned threads = runtime::resolve_threads(runtime::checked_threads(options.threads));
  const std::vector<double> hours = checked_hours(instants);
  const std::vector<std::size_t> faces = checked_faces(scene, faces_in);

  SunHoursMap map;
  map.levels = checked_levels(options.levels);
  const bool full = options.full || map.levels.empty();
  map.full = full;
  for (double w : hours) map.total_hours += w;  // informative; cells are summed exactly
  // The culling grid of each directional light, built once and shared read-only by the threads.
  std::vector<std::optional<core::LightSpaceGrid>> grids(instants.size());
  for (std::size_t i = 0; i < instants.size(); ++i)
    if (instants[i].light.type == LightType::Directional) grids[i].emplace(*ctx.cull, *ctx.prep, instants[i].light.to_light);

  struct Worker {
    ExactWorker exact;
    ShadowStats stats;
  };
  std::vector<Worker> workers(threads);
  for (Worker& w : workers) w.exact.reset(scene.faces.size(), ctx.solids->size());
  const std::size_t n = instants.size();
  std::atomic<std::size_t> done{0};
  std::atomic<std::size_t> total{faces.size() * (n + 1)};
  std::function<void(std::size_t)> report;
  if (options.progress) report = [&](std::size_t) { options.progress(Progress{done.load(), total.load()}); };

  // 1. The lit regions, face-instant pairs in parallel (one large ground uses every thread).
  std::vector<InstantPart> parts(faces.size() * n);
  runtime::parallel_for(
      parts.size(), threads,
      [&](unsigned wi, std::size_t job) {
        runtime::check_stop();
        Worker& w = workers[wi];
        const std::size_t k = job / n, i = job % n, f = faces[k];
        if ((*ctx.prep)[f].degenerate) {
          ++done;
          return;
        }
        const ExactFace& P = w.exact.face(ctx, f);
        const ExactLight light = to_exact_light(instants[i].light);
        const int side = CGAL::sign(plane_at_light(P, light));
        LitRegion region = exact_lit_region(ctx, w.exact, f, i, light, side, instants[i].light,
                                            grids[i] ? &*grids[i] : nullptr, w.stats);
        InstantPart& part = parts[job];
        part.kind = region.kind;
        part.lit_area = region.lit_chart_area;
        if (region.kind == LitRegion::Kind::Partial) {
          std::vector<PolygonWithHoles2> regions;
          region.lit.polygons_with_holes(std::back_inserter(regions));
          for (const PolygonWithHoles2& r : regions) {
            sunmap::add_boundary(r.outer_boundary(), static_cast<long>(i), part.curves);  // counter-clockwise
            for (auto h = r.holes_begin(); h != r.holes_end(); ++h)
              sunmap::add_boundary(*h, static_cast<long>(i), part.curves);  // clockwise
          }
        }
        ++done;
      },
      report);
  grids.clear();

  // 2. Per face: its boundaries, its strips; then face-strip pairs in parallel.
  std::vector<sunmap::FaceBoundaries> bounds(faces.size());
  std::vector<std::vector<sunmap::Strip>> strips(faces.size());
  std::vector<std::vector<std::vector<std::size_t>>> buckets(faces.size());
  std::vector<SunHoursFace> face_info(faces.size());
  std::vector<mpq_class> scales(faces.size());
  std::vector<std::pair<std::size_t, std::size_t>> jobs;  // (face index, strip)
  std::vector<sunmap::OverlayRequest> requests(faces.size());
  std::vector<mpq_class> level_q;
  for (double h : map.levels) level_q.emplace_back(h);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const std::size_t f = faces[k];
    SunHoursFace& info = face_info[k];
    info.face_id = f;
    info.area = (*ctx.face_area)[f];
    info.level_areas.assign(map.levels.size(), 0.0);
    const core::FacePrep& fp = (*ctx.prep)[f];
    if (fp.degenerate) continue;
    const ExactFace& P = workers[0].exact.face(ctx, f);
    exact_to_mpq(P.area_scale_squared, scales[k].get_mpq_t());
    sunmap::FaceBoundaries& b = bounds[k];
    std::vector<FT> hour_area_terms;
    for (std::size_t i = 0; i < n; ++i) {
      InstantPart& part = parts[k * n + i];
      if (part.kind == LitRegion::Kind::Dark) continue;
      ++info.instants_lit;
      if (hours[i] != 0 && !CGAL::is_zero(part.lit_area)) hour_area_terms.push_back(FT(hours[i]) * part.lit_area);
      if (part.kind == LitRegion::Kind::Whole) b.base += mpq_class(hours[i]);
      for (Curve& c : part.curves) b.curves.push_back(std::move(c));
      part = InstantPart{};
    }
    // The integral of hours over the face, sum over instants of w_i x lit area_i: the same exact
    // rational as the sum over the overlay's faces of hours x area (the tests check the cells
    // against it), and far cheaper: n terms whose areas the lit regions already evaluated,
    // instead of thousands of cell areas with unrelated denominators.
    info.hour_area = area_3d(balanced_sum(hour_area_terms), P.area_scale_squared);
    sunmap::add_boundary(P.chart, static_cast<long>(n), b.curves);
    strips[k] = sunmap::choose_strips(b, P.chart, options.strip_edges);
    buckets[k] = sunmap::bucket_curves(b, strips[k]);
    requests[k] = sunmap::OverlayRequest{&P, &fp, f, &hours, options.merge_equal, full, level_q, options.level_round_edges};
    for (std::size_t s = 0; s < strips[k].size(); ++s) jobs.emplace_back(k, s);
  }
  parts.clear();
  parts.shrink_to_fit();
  total = faces.size() * n + jobs.size();
  std::vector<std::vector<sunmap::StripMap>> strip_maps(faces.size());
  for (std::size_t k = 0; k < faces.size(); ++k) strip_maps[k].resize(strips[k].size());
  runtime::parallel_for(
      jobs.size(), threads,
      [&](unsigned, std::size_t j) {
        runtime::check_stop();
        const auto [k, s] = jobs[j];
        strip_maps[k][s] = sunmap::overlay_strip(requests[k], bounds[k], buckets[k][s], strips[k][s]);
        buckets[k][s] = {};
        ++done;
      },
      report);

  // 3. The faces in order, region ids shifted by the earlier faces'.
  for (std::size_t k = 0; k < faces.size(); ++k) {
    FaceMap fm = assemble(strip_maps[k], face_info[k], scales[k], map.levels.size());
    if (!full) fm.face.areas.clear();
    for (SunHoursCell& c : fm.cells) {
      c.region_id += map.regions;
      map.cells.push_back(std::move(c));
    }
    map.regions += fm.regions;
    for (SunHoursCell& c : fm.level_cells) {
      c.region_id += map.level_regions;
      map.level_cells.push_back(std::move(c));
    }
    map.level_regions += fm.level_regions;
    map.faces.push_back(std::move(fm.face));
  }
  return map;
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

}  // namespace shadow
