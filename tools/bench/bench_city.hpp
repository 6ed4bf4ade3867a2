// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench's city benchmarks (bench_city.cpp): the comb, a year of suns, plane shadows,
// tiles and the low sun, with their subcommands' options.
#pragma once

#include <shadow/shadows.hpp>

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace bench {

/// `shadow-bench series`'s options (defaults as the command's help shows them).
struct SeriesArgs {
  std::size_t boxes = 1000, sample = 100;
  bool baseline = false;
  unsigned threads = 2;
  double latitude = 48.0;
  std::string arithmetic = "both";
  bool no_ground = false;
  std::string sun_path = "spa";
  std::size_t runs = 0;  ///< the sample as this many runs of consecutive instants (0: every instant alone)
};

/// `shadow-bench planes`'s options (defaults as the command's help shows them).
struct PlanesArgs {
  std::vector<std::size_t> sizes{10000};
  std::vector<double> elevations{40.0, 5.0};
  std::vector<unsigned> threads{1, 2};
  int repeat = 1;
  std::string label = "this";
};

/// `shadow-bench low-sun`'s options (defaults as the command's help shows them).
struct LowSunArgs {
  std::vector<std::size_t> sizes{10000};
  std::vector<double> elevations{5.0, 40.0};
  std::vector<std::string> arithmetics{"exact", "fast"};
  std::vector<unsigned> threads{1};
  std::string label = "this";
};

/// `shadow-bench tiles`'s options (defaults as the command's help shows them).
struct TilesArgs {
  std::vector<std::size_t> sizes{10000};
  std::vector<double> elevations{40.0, 5.0};
  std::vector<std::string> arithmetics{"exact", "fast"};
  std::vector<unsigned> threads{1, 2};
  std::size_t casters = shadow::ShadowOptions{}.tile_casters;
  std::size_t fast_casters = shadow::ShadowOptions{}.fast_tile_casters;
  bool no_untiled = false;
  std::vector<std::string> grounds{"rectangle"};
};

/// `shadow-bench comb`'s options (defaults as the command's help shows them).
struct CombArgs {
  std::size_t teeth = 10000;
  bool areas_only = false;
  bool lamp = false;
  unsigned threads = 2;
  double lamp_height = 6;
};

/// The subcommands, registered on `app`, writing their options into `a`.
CLI::App* add_series_command(CLI::App& app, SeriesArgs& a);
CLI::App* add_planes_command(CLI::App& app, PlanesArgs& a);
CLI::App* add_low_command(CLI::App& app, LowSunArgs& a);
CLI::App* add_tiles_command(CLI::App& app, TilesArgs& a);
CLI::App* add_comb_command(CLI::App& app, CombArgs& a);

/// docs/benchmarks.md, "Large single faces": validation and computation on one thread.
int run_comb(std::size_t teeth, bool polygons);

/// docs/benchmarks.md, "A comb under a lamp" (issue 30): a 20 x 20 m ground, the comb of `teeth`
/// teeth scaled into the square [2, 18]^2 1 m above it, a sun and a point lamp at (10.25, 9.75,
/// lamp_height) over it. The time of the whole run (validation, both lights) and of each light
/// alone; the ground's shadow areas against the comb's area (the sun's shadow a translated copy,
/// the lamp's scaled by h / (h - 1) when it stays on the ground).
int run_comb_lamp(std::size_t teeth, bool polygons, unsigned threads, double lamp_height);

/// docs/benchmarks.md, "A year of suns": hourly suns of a year at `latitude`, of which `sample`
/// spread over the year are computed with compute_series and (with `baseline`) the same
/// instants one at a time with compute(light); the year is extrapolated from the cost per
/// instant. `sun_path` "spa": what `shadow series` runs, the library's solar position (SPA) at
/// every hour of 2026 in local standard time at longitude 2.35 E (UTC+1), suns above the horizon;
/// "solar-time": a simple model (Cooper's declination, solar time, no refraction), whose noon sun
/// lies in the plane of every east and west wall up to the rounding of its direction (exactly
/// edge-on walls stay on the fast path; those grazed by 1e-17 go to the exact engine), which no
/// clock-time series does.
int run_series_bench(std::size_t boxes, std::size_t sample, bool baseline, unsigned threads,
                     double latitude, const std::string& arithmetic, bool ground, const std::string& sun_path,
                     std::size_t runs = 0);

/// docs/benchmarks.md, "Plane shadows": the city's shadow on its ground plane (Blinn).
int run_planes_bench(const std::vector<std::size_t>& sizes, const std::vector<double>& elevations,
                     const std::vector<unsigned>& threads, int repeat, const std::string& label);

/// docs/tiles.md: the city at each elevation, untiled and tiled, on 1 and 2 threads: CPU time,
/// the longest work item's share of the items' CPU time, and whether the lit areas are the same
/// bits (a digest of every lit area) as untiled on one thread.
int run_tiles_bench(const std::vector<std::size_t>& sizes, const std::vector<double>& elevations,
                    const std::vector<std::string>& arithmetics, const std::vector<unsigned>& threads,
                    std::size_t tile_casters, std::size_t fast_tile_casters, bool untiled,
                    const std::vector<std::string>& grounds);

/// docs/benchmarks.md, "The fast path at a low sun": one sun on the city at each elevation, exact
/// and fast side by side (areas only), one child process per row.
int run_low_sun_bench(const std::vector<std::size_t>& sizes, const std::vector<double>& elevations,
                      const std::vector<std::string>& arithmetics, const std::vector<unsigned>& threads,
                      const std::string& label);

}  // namespace bench
