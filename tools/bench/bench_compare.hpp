// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench's comparison modes: the exact engine against the sampled baselines.
#pragma once

#include <shadow/baselines.hpp>
#include <shadow/scene.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace bench {

/// What one method returns for one scene and parameter.
struct MethodRun {
  std::vector<shadow::FaceLighting> lighting;  ///< by face then light, as the exact engine
  double prepare_s = 0, compute_s = 0;
  std::uint64_t samples = 0;                    ///< sample points or rays (0 for exact)
};

/// A method the bench runs. To add one, append it in methods() (bench_compare.cpp): a name, its
/// parameter's name and values, and a function that runs it on a scene.
struct Method {
  std::string name;            ///< "exact", "shadow-map", "ray-sampling", ...
  std::string parameter_name;  ///< "resolution", "spacing_m", or "" for none
  /// The parameter values to run on a scene, coarse to fine; `{0}` for a method without one.
  /// `spacings` are the scene's ray-sampling spacings (m).
  /// `resolutions`: the shadow-map resolutions asked for on the command line (may be empty).
  std::function<std::vector<double>(const std::vector<double>& spacings, const std::vector<double>& resolutions,
                                    bool quick)>
      parameters;
  std::function<MethodRun(const shadow::Scene&, double parameter, unsigned threads)> run;
};

/// Errors of a method's lighting against the reference (exact) lighting: the lit fraction of
/// all receiving faces together, the relative error of the total lit area, and the mean and
/// maximum absolute error of per-face lit fractions (faces of non-zero area).
struct Errors {
  double lit_fraction = 0, total_rel = 0, mean_abs = 0, max_abs = 0;
  /// Entries whose lit area is further from the reference than their own lit_area_error_bound
  /// (plus two roundings of the face area): must be 0 for the exact engine and the fast path.
  std::uint64_t beyond_bound = 0;
};
/// Both sorted by (face, light); an entry missing from `got` counts as unlit.
Errors compare(const std::vector<shadow::FaceLighting>& got, const std::vector<shadow::FaceLighting>& ref);

struct CompareOptions;

/// Every method, exact first.
std::vector<Method> methods(const CompareOptions& options);

struct CompareOptions {
  std::vector<std::size_t> sizes{100, 1000, 10000};
  unsigned threads = 2;
  bool quick = false;
  double max_samples = 4e8;  ///< skip ray-sampling spacings that would cast more rays
  std::string csv_path, json_path;
  std::vector<std::string> only_methods;  ///< empty: all
  std::vector<std::string> only_scenes;   ///< empty: all (names as in the table)
  std::vector<double> spacings;           ///< ray-sampling spacings for every scene (empty: per scene)
  std::vector<double> resolutions;        ///< shadow-map resolutions (empty: 256 .. 8192)
  double constant_bias = shadow::ShadowMapOptions{}.constant_bias;  ///< shadow map (m)
  double slope_bias = shadow::ShadowMapOptions{}.slope_bias;        ///< shadow map (texels)
  /// Negative: report only. Otherwise run_compare fails (exit 1) when the exact engine or the
  /// fast path leaves its certified bound on any face (exact: bound 0), or when a sampled
  /// baseline's total lit-area relative error or mean per-face lit-fraction error exceeds it.
  double max_error = -1;
};

/// Runs every (scene, method, parameter) in a forked child; prints a Markdown table.
int run_compare(const CompareOptions& options);

/// Runs the hard cases of architecture.md through every method; prints a Markdown table.
/// Returns non-zero when the exact engine misses a closed-form answer. `quick`: coarser maps.
int run_hard_cases(unsigned threads, const std::string& csv_path, bool quick);

/// The hard cases' scenes, by name (lights included).
std::vector<std::pair<std::string, shadow::Scene>> hard_case_scenes();

/// Golden results: the exact and fast areas of the benchmark scenes, the hard cases and the
/// default example, bit for bit, as one digest line per case (`write_dir`: also every value, one
/// file per case, for diffing). With `check_path`, compares the digests with that file and
/// returns non-zero on any difference. See bench_golden.cpp.
int run_golden(const std::string& source_dir, const std::string& output_path, const std::string& check_path,
               const std::string& write_dir, bool quick, unsigned threads);

/// Options of `shadow-bench sun-hours` beyond the city and the instants.
struct SunHoursBench {
  unsigned threads = 2;
  std::string write_dir;             ///< --write DIR
  std::string receivers = "ground,all";  ///< which receivers: ground, all (comma-separated)
  bool unmerged = true;              ///< also time the map without merging (the "regions unmerged" column)
  std::vector<double> levels;        ///< --levels: also the threshold map (its own rows)
  bool full = true;                  ///< false (--levels-only): the threshold map alone
  std::size_t strip_edges = shadow::SunHoursOptions{}.strip_edges;  ///< --strip-edges
  std::size_t level_round_edges = shadow::SunHoursOptions{}.level_round_edges;  ///< --level-round-edges
  std::size_t days = 1;              ///< --days: the same day's suns repeated (a period of equal days)
  std::size_t instant_batch = shadow::SunHoursOptions{}.instant_batch;  ///< --instant-batch
  std::size_t level_held_segments = shadow::SunHoursOptions{}.level_held_segments;  ///< --level-held-segments
  bool stream_levels = false;                                            ///< --stream-levels
  bool skip_engine = false;          ///< --no-engine: leave out the per-instant engine run (its column shows -)
};

/// `shadow-bench sun-hours` (bench_sun_hours.cpp): the exact sun-hours map of a city of `boxes`
/// boxes over `days` days from the March equinox, each split into each of `instants`, timed
/// against the per-instant engine; with levels also the threshold map; `write_dir` non-empty:
/// also writes the ground's map there (sun_hours.vtp) and the city.
int run_sun_hours(std::size_t boxes, const std::vector<std::size_t>& instants, const SunHoursBench& options);

}  // namespace bench
