// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench sun-hours: the exact sun-hours map (shadow/sun_hours.hpp) on a generated city
// over one day, timed against the per-instant engine it is built from, with the size of the
// result; --write DIR also writes DIR/sun_hours.vtp (the picture in docs/sun-hours-map.md).
//
// The day is an equinox at latitude 48 degrees (declination 0): sin(elevation) =
// cos(latitude) cos(hour angle), azimuth from the same spherical triangle. Solar position proper
// is the `sun` block's business; this only needs a plausible path of suns.
#include "bench_compare.hpp"

#include <shadow/shadow.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace bench {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// `count` instants spread over the daylight of a day at latitude 48 with the sun at
/// `declination_deg` (0: an equinox): each weighs 12 / count hours; those below 2 degrees of
/// elevation are left out (no sun on the ground).
std::vector<shadow::SunHoursInstant> sun_day(std::size_t count, double declination_deg, const std::string& prefix) {
  constexpr double pi = 3.14159265358979323846;
  const double latitude = 48.0 * pi / 180.0, decl = declination_deg * pi / 180.0;
  const double step = 12.0 / static_cast<double>(count);
  std::vector<shadow::SunHoursInstant> out;
  for (std::size_t k = 0; k < count; ++k) {
    const double hour = 6.0 + (static_cast<double>(k) + 0.5) * step;  // solar time, mid-step
    const double h = (hour - 12.0) * 15.0 * pi / 180.0;                // hour angle
    const double sin_e = declination_deg == 0 ? std::cos(latitude) * std::cos(h)
                                              : std::sin(latitude) * std::sin(decl) + std::cos(latitude) * std::cos(decl) * std::cos(h);
    const double e = std::asin(sin_e);
    if (e * 180.0 / pi < 2.0) continue;
    // Azimuth clockwise from north: east in the morning, south at noon, west in the evening.
    // At the equinox the formula the earlier tables used, bit for bit (the same suns).
    const double cos_a = declination_deg == 0 ? -std::sin(latitude) * std::cos(h) / std::cos(e)
                                              : (std::sin(decl) - sin_e * std::sin(latitude)) / (std::cos(e) * std::cos(latitude));
    double a = std::acos(std::max(-1.0, std::min(1.0, cos_a))) * 180.0 / pi;
    if (h > 0) a = 360.0 - a;
    out.push_back({shadow::directional_light(prefix + std::to_string(k), shadow::sun_direction(e * 180.0 / pi, a)), step});
  }
  return out;
}

/// `days` days from the March equinox on (the declination grows by about 0.4 degrees a day).
std::vector<shadow::SunHoursInstant> sun_days(std::size_t count, std::size_t days) {
  constexpr double pi = 3.14159265358979323846;
  std::vector<shadow::SunHoursInstant> out;
  for (std::size_t d = 0; d < days; ++d) {
    const double declination = 23.44 * std::sin(2.0 * pi * static_cast<double>(d) / 365.0);
    for (shadow::SunHoursInstant& i : sun_day(count, declination, "d" + std::to_string(d) + "t")) out.push_back(std::move(i));
  }
  return out;
}

std::string fixed(double value, int digits = 3) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

double peak_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

}  // namespace

int run_sun_hours(std::size_t boxes, const std::vector<std::size_t>& instant_counts, const SunHoursBench& opt) {
  const unsigned threads = opt.threads;
  shadow::Scene scene = shadow::make_city(boxes, 10.0 * std::sqrt(static_cast<double>(boxes)) + 30.0, 20261123);
  shadow::validate_scene(scene);
  std::vector<std::size_t> ground, all;
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    all.push_back(f);
    if (scene.faces[f].mesh == 0) ground.push_back(f);
  }
  const shadow::ShadowEngine engine(scene, threads);
  std::printf("| boxes | faces | instants | receivers | engine, areas (s) | map (s) | regions | regions unmerged | cells | "
              "max cells/face | peak (MiB) |\n");
  std::printf("|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n");
  std::vector<std::pair<std::string, const std::vector<std::size_t>*>> receivers;
  if (opt.receivers.find("ground") != std::string::npos) receivers.emplace_back("ground", &ground);
  if (opt.receivers.find("all") != std::string::npos) receivers.emplace_back("all", &all);
  for (std::size_t count : instant_counts) {
    const std::vector<shadow::SunHoursInstant> instants = sun_days(count, opt.days);
    for (const auto& [label, faces] : receivers) {
      shadow::ShadowOptions options;
      options.threads = threads;
      options.polygons = false;
      auto start = std::chrono::steady_clock::now();
      if (!opt.skip_engine)  // its peak would hide the map's (every instant's result at once)
        for (std::size_t i = 0; i < instants.size(); ++i) (void)engine.compute(instants[i].light, i, options);
      const double engine_s = seconds_since(start);
      // The threshold map alone first (full = false), so that the peak after it is its own.
      std::string levels_row, levels_summary;
      if (!opt.levels.empty()) {
        shadow::SunHoursOptions level_options;
        level_options.threads = threads;
        level_options.strip_edges = opt.strip_edges;
        level_options.level_round_edges = opt.level_round_edges;
        level_options.instant_batch = opt.instant_batch;
        level_options.stream_levels = opt.stream_levels;
        level_options.level_held_segments = opt.level_held_segments;
        level_options.levels = opt.levels;
        level_options.full = false;
        start = std::chrono::steady_clock::now();
        const shadow::SunHoursMap levels = shadow::compute_sun_hours_map(engine, *faces, instants, level_options);
        const double levels_s = seconds_since(start);
        levels_row = "| " + std::to_string(boxes) + " | " + std::to_string(scene.faces.size()) + " | " +
                     std::to_string(instants.size()) + " | " + label + ", levels only | | " + fixed(levels_s) + " | " +
                     std::to_string(levels.level_regions) + " | - | " + std::to_string(levels.level_cells.size()) +
                     " | | " + fixed(peak_mib(), 0) + " |\n";
        levels_summary = shadow::sun_hours_levels_summary(levels, "    ");
      }
      if (!opt.full) {
        std::printf("%s%s", levels_row.c_str(), levels_summary.c_str());
        std::fflush(stdout);
        continue;
      }
      shadow::SunHoursOptions map_options;
      map_options.threads = threads;
      map_options.strip_edges = opt.strip_edges;
      map_options.instant_batch = opt.instant_batch;
      start = std::chrono::steady_clock::now();
      const shadow::SunHoursMap map = shadow::compute_sun_hours_map(engine, *faces, instants, map_options);
      const double map_s = seconds_since(start);
      const double map_peak = peak_mib();
      const auto regions = [](const shadow::SunHoursMap& m) { return m.cells.empty() ? 0 : m.cells.back().region_id + 1; };
      std::string unmerged = "-";
      if (opt.unmerged) {
        map_options.merge_equal = false;
        unmerged = std::to_string(regions(shadow::compute_sun_hours_map(engine, *faces, instants, map_options)));
      }
      std::map<std::size_t, std::size_t> per_face;
      std::size_t most = 0;
      for (const shadow::SunHoursCell& c : map.cells) most = std::max(most, ++per_face[c.face_id]);
      std::printf("| %zu | %zu | %zu | %s | %.3f | %.3f | %zu | %s | %zu | %zu | %.0f |\n", boxes, scene.faces.size(),
                  instants.size(), label.c_str(), engine_s, map_s, regions(map), unmerged.c_str(), map.cells.size(), most,
                  map_peak);
      std::fflush(stdout);
      if (!levels_row.empty()) std::printf("%s%s", levels_row.c_str(), levels_summary.c_str());
      std::fflush(stdout);
      if (!opt.write_dir.empty() && label == "ground" && count == instant_counts.front()) {
        std::filesystem::create_directories(opt.write_dir);
        shadow::ShadowOptions noon;
        noon.threads = threads;
        noon.planes = false;
        // The city itself, for context in pictures: faces.vtp and friends under the noon sun.
        shadow::Scene with_noon = scene;
        with_noon.lights = {instants[instants.size() / 2].light};
        shadow::write_outputs(opt.write_dir, with_noon, engine.compute(with_noon.lights[0], 0, noon));
        // After write_outputs, which removes a sun-hours map left by an earlier run.
        shadow::write_sun_hours_vtp(std::filesystem::path(opt.write_dir) / "sun_hours.vtp", map);
      }
    }
  }
  return 0;
}

}  // namespace bench
