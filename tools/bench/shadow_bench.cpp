// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench: times the exact engine on procedurally generated scenes.
//
// Each case runs in a forked child so that its peak memory (ru_maxrss) is its own. Output: a
// Markdown table on stdout and, with --csv FILE, the same rows as CSV.
// `shadow-bench compare` runs the exact engine against the sampled baselines (speed against
// error) and `shadow-bench hard-cases` the hard cases through every method: bench_compare.cpp.
#include "bench_compare.hpp"
#include "bench_soft.hpp"
#include "bench_light_visibility.hpp"
#include "bench_prepare.hpp"
#include "bench_radiosity.hpp"

#include "bench_city.hpp"
#include <shadow/shadow.hpp>
#include <shadow/sun.hpp>

#include <CLI/CLI.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Case {
  std::string scene;   // "city", "city-fixed", "room", "city-plane" (plane shadows only)
  std::size_t size;    // boxes or tables
  double extent;       // city side (m)
  std::string light;   // description
  double elevation;    // sun elevation (deg) for cities
};

struct Measurement {
  double prepare_s = 0, compute_s = 0;
  long peak_kib = 0;
  std::size_t faces = 0;
  shadow::ShadowStats stats;
  double lit_fraction = 0;
  bool ok = false;
};

shadow::Scene build(const Case& c) {
  if (c.scene == "room") return shadow::make_furnished_room(c.size, 11);
  shadow::Scene scene = shadow::make_city(c.size, c.extent, 2026);
  scene.lights.push_back(shadow::directional_light("sun", shadow::sun_direction(c.elevation, 135.0)));
  if (c.scene == "city-plane") scene.planes.push_back({"ground", {0, 0, 0}, {0, 0, 1}});
  return scene;
}

/// Runs a case `repeat` times and keeps the fastest time of each phase: on a shared machine
/// the minimum is the least disturbed measurement.
Measurement run_case(const Case& c, unsigned threads, bool polygons, int repeat) {
  using Clock = std::chrono::steady_clock;
  Measurement m;
  shadow::Scene scene = build(c);
  shadow::validate_scene(scene);
  m.faces = scene.faces.size();
  shadow::ShadowResult result;
  m.prepare_s = m.compute_s = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = Clock::now();
    const shadow::ShadowEngine engine(scene);
    const auto t1 = Clock::now();
    shadow::ShadowOptions options;
    options.threads = threads;
    options.polygons = polygons;
    if (c.scene == "city-plane") {
      result.plane_shadows = shadow::compute_plane_shadows(scene, options);
    } else {
      result = engine.compute(options);
    }
    const auto t2 = Clock::now();
    m.prepare_s = std::min(m.prepare_s, std::chrono::duration<double>(t1 - t0).count());
    m.compute_s = std::min(m.compute_s, std::chrono::duration<double>(t2 - t1).count());
  }
  m.stats = result.stats;
  double area = 0, lit = 0;
  for (const shadow::FaceLighting& fl : result.lighting) {
    area += fl.area;
    lit += fl.lit_area;
  }
  m.lit_fraction = area > 0 ? lit / area : 0;
  // Plane shadows: report the shadowed fraction of the city's ground square instead.
  if (!result.plane_shadows.empty()) m.lit_fraction = result.plane_shadows[0].area / ((c.extent + 20) * (c.extent + 20));
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  m.peak_kib = usage.ru_maxrss;
  m.ok = true;
  return m;
}

/// Runs a case in a child process and reads its measurement back through a pipe.
Measurement run_isolated(const Case& c, unsigned threads, bool polygons, int repeat) {
  int fds[2];
  if (pipe(fds) != 0) return run_case(c, threads, polygons, repeat);
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    Measurement m = run_case(c, threads, polygons, repeat);
    std::ostringstream out;
    out.precision(17);
    out << m.prepare_s << ' ' << m.compute_s << ' ' << m.peak_kib << ' ' << m.faces << ' '
        << m.stats.receivers << ' ' << m.stats.back_facing << ' ' << m.stats.candidate_pairs << ' '
        << m.stats.casting_pairs << ' ' << m.stats.unshadowed << ' ' << m.lit_fraction;
    const std::string text = out.str();
    if (write(fds[1], text.data(), text.size()) < 0) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buffer[512];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  Measurement m;
  std::istringstream in(text);
  in >> m.prepare_s >> m.compute_s >> m.peak_kib >> m.faces >> m.stats.receivers >>
      m.stats.back_facing >> m.stats.candidate_pairs >> m.stats.casting_pairs >> m.stats.unshadowed >>
      m.lit_fraction;
  m.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 && !in.fail();
  return m;
}

/// The default run: the cities at constant density and fixed extent, the room and the plane
/// shadows, each case in a child process, as a Markdown table (and CSV rows).
int run_default(const std::vector<std::size_t>& sizes, const std::vector<unsigned>& threads, const std::string& csv_path,
                bool areas_only, bool quick, int repeat) {
  std::vector<Case> cases;
  // Constant density: 1,000 boxes on 500 m x 500 m; the side grows with sqrt(N).
  for (std::size_t n : sizes) {
    if (quick && n > 1000) continue;
    const double extent = 500.0 * std::sqrt(static_cast<double>(n) / 1000.0);
    for (double elevation : {40.0, 5.0}) {
      if (quick && elevation != 40.0) continue;
      cases.push_back({"city", n, extent, "sun " + std::to_string(static_cast<int>(elevation)) + " deg", elevation});
    }
  }
  if (!quick) {
    // Fixed extent: shadows pile up as N grows.
    for (std::size_t n : sizes) cases.push_back({"city-fixed", n, 500.0, "sun 40 deg", 40.0});
    cases.push_back({"room", 12, 0, "ceiling lamp", 0});
    // Blinn plane shadows of the whole city on the ground plane (the "lit fraction" column then
    // holds the shadow area over the ground square's area).
    for (std::size_t n : sizes)
      cases.push_back({"city-plane", n, 500.0 * std::sqrt(static_cast<double>(n) / 1000.0), "sun 40 deg", 40.0});
  }

  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    csv << "scene,size,extent_m,light,faces,threads,prepare_s,compute_s,peak_mib,receivers,back_facing,"
           "candidate_pairs,casting_pairs,unshadowed,lit_fraction\n";
  }
  std::printf("| scene | boxes/tables | extent (m) | light | faces | threads | prepare (s) | compute (s) | peak (MiB) | candidate pairs | casting pairs | lit fraction |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Case& c : cases) {
    for (unsigned t : threads) {
      const Measurement m = run_isolated(c, t, !areas_only, c.size >= 10000 ? 1 : repeat);
      if (!m.ok) {
        std::printf("| %s | %zu | %.0f | %s | - | %u | failed |\n", c.scene.c_str(), c.size, c.extent, c.light.c_str(), t);
        continue;
      }
      std::printf("| %s | %zu | %.0f | %s | %zu | %u | %.3f | %.3f | %.0f | %llu | %llu | %.6f |\n", c.scene.c_str(),
                  c.size, c.extent, c.light.c_str(), m.faces, t, m.prepare_s, m.compute_s, m.peak_kib / 1024.0,
                  static_cast<unsigned long long>(m.stats.candidate_pairs),
                  static_cast<unsigned long long>(m.stats.casting_pairs), m.lit_fraction);
      std::fflush(stdout);
      if (csv.is_open())
        csv << c.scene << ',' << c.size << ',' << c.extent << ',' << c.light << ',' << m.faces << ',' << t << ','
            << m.prepare_s << ',' << m.compute_s << ',' << m.peak_kib / 1024.0 << ',' << m.stats.receivers << ','
            << m.stats.back_facing << ',' << m.stats.candidate_pairs << ',' << m.stats.casting_pairs << ','
            << m.stats.unshadowed << ',' << m.lit_fraction << '\n';
    }
  }
  return 0;
}

}  // namespace

using namespace bench;

struct WriteCityArgs {
  std::size_t boxes = 166667;
  double elevation = 40;
  bool ground_only = false;
  std::string dir;
};

CLI::App* add_write_city_command(CLI::App& app, WriteCityArgs& a) {
  CLI::App* cmd = app.add_subcommand(
      "write-city", "Write the benchmark city as scene.json and OBJ files, to time `shadow compute` as a whole");
  cmd->add_option("--boxes", a.boxes, "Boxes (extent 500 sqrt(boxes / 1000) m, as low-sun)")->check(CLI::PositiveNumber);
  cmd->add_option("--elevation", a.elevation, "Sun elevation (degrees), azimuth 135");
  cmd->add_flag("--ground-only", a.ground_only, "Only the ground receives");
  cmd->add_option("--output", a.dir, "Folder to write")->required();
  return cmd;
}

struct SunHoursArgs {
  std::size_t boxes = 10;
  std::vector<std::size_t> instants{24, 96};
  bench::SunHoursBench opt;
};

CLI::App* add_sun_hours_command(CLI::App& app, SunHoursArgs& a) {
  CLI::App* sun_cmd = app.add_subcommand(
      "sun-hours", "The exact sun-hours map of a generated city over an equinox day, against the per-instant engine");
  sun_cmd->add_option("--boxes", a.boxes, "Boxes in the city")->check(CLI::PositiveNumber);
  sun_cmd->add_option("--instants", a.instants, "Instants over the day (12 h of daylight split evenly)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  sun_cmd->add_option("--threads", a.opt.threads, "Threads")->check(CLI::PositiveNumber);
  sun_cmd->add_option("--write", a.opt.write_dir, "Write the ground's map (first instant count) as DIR/sun_hours.vtp, and the city");
  sun_cmd->add_option("--receivers", a.opt.receivers, "ground, all, or ground,all (default)");
  sun_cmd->add_option("--days", a.opt.days, "Days from the March equinox on, each split into the instants")
      ->check(CLI::PositiveNumber);
  sun_cmd->add_option("--levels", a.opt.levels, "Also time the threshold map of these levels (hours)")->delimiter(',');
  sun_cmd->add_option("--strip-edges", a.opt.strip_edges, "SunHoursOptions::strip_edges (0: one arrangement per face)");
  sun_cmd->add_option("--level-round-edges", a.opt.level_round_edges, "SunHoursOptions::level_round_edges");
  sun_cmd->add_option("--level-held-segments", a.opt.level_held_segments,
                      "SunHoursOptions::level_held_segments (exact boundary segments held at once)");
  sun_cmd->add_option("--instant-batch", a.opt.instant_batch, "SunHoursOptions::instant_batch (0: every instant at once)");
  sun_cmd->add_flag("--stream-levels", a.opt.stream_levels,
                    "SunHoursOptions::stream_levels: the threshold map alone fed each batch as it comes");
  sun_cmd->add_flag("--no-engine", a.opt.skip_engine, "Leave out the per-instant engine run (the peak is then the map's)");
  sun_cmd->add_flag("!--no-unmerged", a.opt.unmerged, "Leave out the unmerged run (its column shows -)");
  sun_cmd->add_flag("!--levels-only", a.opt.full, "With --levels: the threshold map alone, not the full map");
  return sun_cmd;
}

int main(int argc, char** argv) {
  CLI::App app{"shadow-bench: time libshadow's exact engine on generated cities and rooms"};
  std::vector<std::size_t> sizes{100, 1000, 10000};
  std::vector<unsigned> threads{1, 2};
  std::string csv_path;
  bool areas_only = false;
  bool quick = false;
  int repeat = 3;
  app.add_option("--sizes", sizes, "City sizes in boxes")->delimiter(',');
  app.add_option("--threads", threads, "Thread counts to run")->delimiter(',');
  app.add_option("--csv", csv_path, "Also write the rows as CSV to this file");
  app.add_flag("--areas-only", areas_only, "Compute areas only (no fragment polygons)");
  app.add_option("--repeat", repeat, "Runs per case below 10,000 boxes; the fastest is kept")->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick, "Only the 100- and 1,000-box cities at 40 degrees (smoke run)");

  bench::CompareOptions compare;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Exact against the baselines (shadow map, ray sampling): time, memory, error");
  compare_cmd->add_option("--sizes", compare.sizes, "City sizes in boxes")->delimiter(',');
  compare_cmd->add_option("--threads", compare.threads, "Threads for every method")->check(CLI::PositiveNumber);
  compare_cmd->add_option("--csv", compare.csv_path, "Write the rows as CSV to this file");
  compare_cmd->add_option("--json", compare.json_path, "Write the rows as JSON to this file");
  compare_cmd->add_option("--max-samples", compare.max_samples, "Skip ray spacings that cast more rays");
  compare_cmd->add_option("--methods", compare.only_methods, "Only these baselines (exact always runs)")->delimiter(',');
  compare_cmd->add_option("--scenes", compare.only_scenes, "Only these scenes (names as in the table)")->delimiter(',');
  compare_cmd->add_option("--spacings", compare.spacings, "Ray-sampling spacings (m) for every scene")->delimiter(',');
  compare_cmd->add_option("--resolutions", compare.resolutions, "Shadow-map resolutions")->delimiter(',');
  compare_cmd->add_option("--constant-bias", compare.constant_bias, "Shadow-map constant depth bias (m)");
  compare_cmd->add_option("--slope-bias", compare.slope_bias, "Shadow-map slope-scaled bias (texels)");
  compare_cmd->add_option("--max-error", compare.max_error,
                          "Fail (exit 1) when the fast path leaves its error bound on any face (exact is the reference), or a sampled "
                          "baseline's total lit rel. error or mean face error exceeds this")
      ->check(CLI::NonNegativeNumber);
  compare_cmd->add_flag("--quick", compare.quick, "Smoke run: 100-box city and the room, two parameters each");
  unsigned hard_threads = 2;
  std::string hard_csv;
  CLI::App* hard_cmd = app.add_subcommand("hard-cases", "The hard cases of the design notes through every method");
  hard_cmd->add_option("--threads", hard_threads, "Threads for every method")->check(CLI::PositiveNumber);
  hard_cmd->add_option("--csv", hard_csv, "Write the rows as CSV to this file");
  bool hard_quick = false;
  hard_cmd->add_flag("--quick", hard_quick, "Shadow maps at 256 and 1024 instead of 1024 and 4096");
  std::string golden_output, golden_check, golden_dir;
  bool golden_quick = false;
  unsigned golden_threads = 2;
  CLI::App* golden_cmd = app.add_subcommand(
      "golden", "Areas of the benchmark scenes, hard cases and example, bit for bit, as digests (exact and fast)");
  golden_cmd->add_option("--output", golden_output, "Write the digests to this file");
  golden_cmd->add_option("--check", golden_check, "Compare with digests written earlier; exit 1 on a difference");
  golden_cmd->add_option("--write-dir", golden_dir, "Also write every value, one file per case, into this folder");
  golden_cmd->add_option("--threads", golden_threads, "Threads (results do not depend on it)")->check(CLI::PositiveNumber);
  golden_cmd->add_flag("--quick", golden_quick, "Leave out the 1,000-box city; 10 spheres instead of 50");
  SeriesArgs series;
  CLI::App* series_cmd = add_series_command(app, series);
  CombArgs comb;
  CLI::App* comb_cmd = add_comb_command(app, comb);
  SunHoursArgs sun;
  CLI::App* sun_cmd = add_sun_hours_command(app, sun);
  PlanesArgs planes;
  CLI::App* planes_cmd = add_planes_command(app, planes);
  bench::SoftOptions soft;
  CLI::App* soft_cmd = app.add_subcommand(
      "soft", "Soft shadows of extended lights: PCF, PCSS and k rays per point against the exact visible fraction");
  soft_cmd->add_option("--threads", soft.threads, "Threads for every method")->check(CLI::PositiveNumber);
  soft_cmd->add_option("--csv", soft.csv_path, "Write the rows as CSV to this file");
  soft_cmd->add_option("--scenes", soft.only_scenes, "Only these scenes (luminaire, sun-city, room-disk)")->delimiter(',');
  soft_cmd->add_option("--reference-rays", soft.reference_rays, "Rays a point of the ray cross-check against the exact fractions")
      ->check(CLI::PositiveNumber);
  soft_cmd->add_option("--max-error", soft.max_error,
                       "Fail (exit 1) when the ray cross-check's mean error exceeds this, rays do not improve with k, "
                       "or a visibility leaves [0, 1]")
      ->check(CLI::NonNegativeNumber);
  soft_cmd->add_flag("--quick", soft.quick, "Smoke run: a small luminaire scene, two settings a method");
  std::size_t vis_boxes = 200, vis_points = 2000;
  unsigned vis_threads = 2;
  CLI::App* vis_cmd = app.add_subcommand(
      "light-visibility", "The exact visible fraction of extended lights at ground points of a city (area_lights.hpp)");
  vis_cmd->add_option("--boxes", vis_boxes, "Boxes in the city")->check(CLI::PositiveNumber);
  vis_cmd->add_option("--points", vis_points, "Ground points")->check(CLI::PositiveNumber);
  vis_cmd->add_option("--threads", vis_threads, "Most threads (1, 2, 4, ... up to it)")->check(CLI::PositiveNumber);
  std::vector<std::size_t> prepare_sizes{10000, 166667};
  std::vector<unsigned> prepare_threads{1, 2};
  int prepare_repeat = 1;
  CLI::App* prepare_cmd = app.add_subcommand(
      "prepare", "Validation and the convex-solid search on the city, against the reference implementations");
  prepare_cmd->add_option("--sizes", prepare_sizes, "City sizes in boxes")->delimiter(',')->check(CLI::PositiveNumber);
  prepare_cmd->add_option("--threads", prepare_threads, "Thread counts")->delimiter(',')->check(CLI::PositiveNumber);
  prepare_cmd->add_option("--repeat", prepare_repeat, "Runs per row; the fastest is kept")->check(CLI::PositiveNumber);
  bool prepare_new_only = false;
  prepare_cmd->add_flag("--new-only", prepare_new_only, "Leave the reference implementations out (for profiling)");
  WriteCityArgs write_city;
  CLI::App* write_cmd = add_write_city_command(app, write_city);
  LowSunArgs low;
  CLI::App* low_cmd = add_low_command(app, low);
  TilesArgs tiles;
  CLI::App* tiles_cmd = add_tiles_command(app, tiles);
  std::size_t city_boxes = 200;
  double city_diameter = 0.53;
  unsigned city_threads = 1;
  CLI::App* city_cmd = app.add_subcommand(
      "area-city", "ShadowEngine::compute for a city under a sun disk: regions and fragment visibility (docs/area-lights.md)");
  city_cmd->add_option("--boxes", city_boxes, "Boxes in the city")->check(CLI::PositiveNumber);
  city_cmd->add_option("--diameter", city_diameter, "The sun's angular diameter (degrees)")->check(CLI::PositiveNumber);
  city_cmd->add_option("--threads", city_threads, "Threads")->check(CLI::PositiveNumber);
  bench::RadiosityCompareOptions radiosity;
  CLI::App* radiosity_cmd = bench::add_radiosity_compare_command(app, radiosity);
  app.require_subcommand(0, 1);
  CLI11_PARSE(app, argc, argv);
  if (radiosity_cmd->parsed()) return bench::run_radiosity_compare(radiosity);
  if (compare_cmd->parsed()) return bench::run_compare(compare);
  if (soft_cmd->parsed()) return bench::run_soft(soft);
  if (tiles_cmd->parsed())
    return run_tiles_bench(tiles.sizes, tiles.elevations, tiles.arithmetics, tiles.threads, tiles.casters,
                           tiles.fast_casters, !tiles.no_untiled, tiles.grounds);
  if (low_cmd->parsed()) return run_low_sun_bench(low.sizes, low.elevations, low.arithmetics, low.threads, low.label);
  if (planes_cmd->parsed()) return run_planes_bench(planes.sizes, planes.elevations, planes.threads, planes.repeat, planes.label);
  if (hard_cmd->parsed()) return bench::run_hard_cases(hard_threads, hard_csv, hard_quick);
  if (comb_cmd->parsed())
    return comb.lamp ? run_comb_lamp(comb.teeth, !comb.areas_only, comb.threads, comb.lamp_height)
                     : run_comb(comb.teeth, !comb.areas_only);
  if (sun_cmd->parsed()) return bench::run_sun_hours(sun.boxes, sun.instants, sun.opt);
  if (city_cmd->parsed()) return bench::run_area_city(city_boxes, city_diameter, city_threads);
  if (vis_cmd->parsed()) return bench::run_light_visibility(vis_boxes, vis_points, vis_threads);
  if (write_cmd->parsed())
    return bench::write_city(write_city.boxes, write_city.elevation, write_city.ground_only, write_city.dir);
  if (prepare_cmd->parsed()) return bench::run_prepare(prepare_sizes, prepare_threads, prepare_repeat, prepare_new_only);
  if (golden_cmd->parsed())
    return bench::run_golden(LIBSHADOW_SOURCE_DIR, golden_output, golden_check, golden_dir, golden_quick, golden_threads);
  if (series_cmd->parsed())
    return run_series_bench(series.boxes, series.sample, series.baseline, series.threads, series.latitude,
                            series.arithmetic, !series.no_ground, series.sun_path, series.runs);

  return run_default(sizes, threads, csv_path, areas_only, quick, repeat);
}
