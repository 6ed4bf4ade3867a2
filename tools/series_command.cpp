// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow series SCENE.json -o OUTDIR`: every sun instant of the scene's `sun` block on every
// receiving face, areas only, written as sunlit.csv, energyplus-shading.csv, series.pvd,
// faces.vtp (sun_hours) and report.json (docs/series.md).
#include "series_command.hpp"

#include "cli_checks.hpp"
#include "progress_line.hpp"

#include <shadow/shadow.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

}  // namespace

CLI::App* add_series_command(CLI::App& app, SeriesArgs& args) {
  CLI::App* series = app.add_subcommand(
      "series", "Compute every sun instant of the scene's `sun` block on every receiving face (areas only) and "
                "write sunlit.csv, energyplus-shading.csv, series.pvd, faces.vtp (sun_hours) and report.json");
  series->footer(shadow_cli::exit_codes_help());
  series->add_option("scene", args.scene, "Scene file with a `sun` block (JSON; see docs/scene-format.md)")->required();
  series->add_option("-o,--output", args.outdir, "Output directory (created if missing)")->required();
  series->add_option("-t,--threads", args.threads, "Worker threads (0: all cores; at most 1024)")
      ->default_val(0)
      ->check(shadow_cli::integer_in(0, 1024));
  series->add_flag("--fast", args.fast,
                   "The fast path: doubles and an integer grid, with each face's sun-hours error bound in "
                   "report.json (docs/numeric-contract.md)");
  series->add_flag("-q,--quiet", args.quiet, "Print nothing but errors");
  series->add_option("--every", args.every,
                     "Write one series/sun_NNNNN.vtp for every K-th instant above the horizon into series.pvd "
                     "(1: all; 0: no series.pvd). sunlit.csv, energyplus-shading.csv and sun hours always use every instant")
      ->default_val(1)
      ->check(shadow_cli::integer_in(0, 1000000));
  series->add_flag("--fragments", args.fragments,
                   "Also write each instant's lit and shadowed polygons (series/fragments_NNNNN.vtp, fragments.pvd) "
                   "for the instants in series.pvd: one polygon computation per such instant, on top of the series");
  series->add_option("--sun-hours-map", args.sun_hours_map,
                     "Write sun_hours.vtp: the exact sun-hours map of these meshes' faces (comma-separated mesh "
                     "names; adds to the scene's `sun_hours_map`; docs/sun-hours-map.md)");
  series->add_option("--planarity-tolerance", args.planarity_tolerance,
                     "Largest vertex distance from a face's plane, relative to the face's size")
      ->default_val(1e-6)
      ->check(shadow_cli::positive_up_to(1.0));
  series->add_flag("--orient-outward", args.orient_outward,
                   "Turn the closed parts of every mesh outward (as for `shadow compute`)");
  series->add_option("--lod", args.lod, "CityJSON level of detail to read (default: the highest of each city object)");
  series->add_option("--from", args.from,
                     "First local date of the sun period (YYYY-MM-DD), replacing the scene's or the model's "
                     "(an EnergyPlus RunPeriod); its site stays");
  series->add_option("--to", args.to, "Last local date of the sun period (YYYY-MM-DD, inclusive)");
  series->add_option("--step", args.step_minutes, "Minutes between sun instants (dividing a day)")
      ->check(shadow_cli::integer_in(1, 1440));
  return series;
}

int run_series(const SeriesArgs& args) {
  const auto start = Clock::now();
  shadow::RunInfo run;
  run.scene = args.scene;
  run.started_utc = shadow::utc_now();
  run.planarity_tolerance = args.planarity_tolerance;
  shadow::Scene scene = shadow::load_scene(
      args.scene, shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod));
  if (!args.from.empty() || !args.to.empty() || args.step_minutes > 0) {
    // Another period at the same site: an IDF's RunPeriod, or a scene's `sun` block, overridden.
    if (!scene.sun)
      throw shadow::InputError({args.scene, "sun"}, "--from/--to/--step need a sun: the scene has no `sun` block "
                                                    "(and the model no Site:Location)");
    shadow::SunPeriod period = *scene.sun;
    if (!period.times.empty() && (args.from.empty() || args.to.empty()))
      throw shadow::InputError({args.scene, "sun.times"},
                               "the sun is given by explicit times: give both --from and --to to replace them by a period");
    period.times.clear();
    if (!args.from.empty()) period.start = args.from;
    if (!args.to.empty()) period.end = args.to;
    if (args.step_minutes > 0) period.step_minutes = args.step_minutes;
    try {
      shadow::replace_sun_lights(scene, period);
    } catch (const shadow::InputError& e) {
      // The period's keys came from the command line: name the flag.
      const std::string& place = e.where().place;
      const std::string flag = place == "sun.start" ? "--from" : place == "sun.end" ? "--to"
                             : place == "sun.step_minutes" ? "--step" : place;
      throw shadow::InputError({flag == place ? e.where().file : std::string(), flag}, e.problem());
    }
  }
  shadow::SunSeries suns;
  try {
    suns = shadow::sun_series(scene);
  } catch (const shadow::InputError& e) {
    shadow_cli::rethrow_naming_scene(e, args.scene);
  }
  shadow::OutputDirectory output(args.outdir);  // lock, clear leftovers, remove the old report
  if (!args.quiet)
    for (const shadow::Warning& warning : scene.warnings)
      std::cerr << "shadow: warning: " << warning.to_string() << "\n";

  shadow::SeriesOptions options;
  options.threads = args.threads;
  options.arithmetic = args.fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
  run.options.threads = args.threads;
  run.options.polygons = false;
  run.options.planes = false;
  run.options.arithmetic = options.arithmetic;
  shadow_cli::ProgressLine progress(!args.quiet && isatty(STDERR_FILENO), "instants");
  options.progress = [&](const shadow::Progress& p) { progress.update(p); };
  shadow::SeriesResult series;
  std::optional<shadow::ShadowEngine> engine_holder;
  try {
    engine_holder.emplace(scene, args.threads);
    series = engine_holder->compute_series(suns.lights, options);
  } catch (const shadow::InputError& e) {
    progress.finish();
    shadow_cli::rethrow_naming_scene(e, args.scene);
  }
  progress.finish();
  const auto computed = Clock::now();
  const shadow::ShadowEngine& engine = *engine_holder;
  shadow::OutputDirectory::SeriesFiles files;
  files.every = args.every;
  if (args.fragments) {
    files.fragments = [&](std::size_t i) {
      shadow::ShadowOptions one;
      one.threads = args.threads;
      one.planes = false;
      one.arithmetic = options.arithmetic;
      // The instant's own light in the scene, so that fragments carry its light_id (and irradiance).
      const std::size_t light_id = scene.sun_instants[suns.instants[i]].light_id;
      return engine.compute(scene.lights[light_id], light_id, one);
    };
  }
  // The exact sun-hours map (docs/sun-hours-map.md) on the scene's `sun_hours_map` meshes and
  // those of --sun-hours-map, written before write_series puts report.json in place last.
  std::vector<std::size_t> map_faces = shadow::sun_hours_map_faces(scene);
  if (!args.sun_hours_map.empty()) {
    std::vector<std::string> names;
    std::size_t begin = 0;
    while (begin <= args.sun_hours_map.size()) {
      const std::size_t comma = std::min(args.sun_hours_map.find(',', begin), args.sun_hours_map.size());
      names.push_back(args.sun_hours_map.substr(begin, comma - begin));
      begin = comma + 1;
    }
    for (std::size_t f : shadow::sun_hours_map_faces(scene, names, "--sun-hours-map")) map_faces.push_back(f);
    std::sort(map_faces.begin(), map_faces.end());
    map_faces.erase(std::unique(map_faces.begin(), map_faces.end()), map_faces.end());
  }
  std::optional<shadow::SunHoursMap> map;
  if (!map_faces.empty()) {
    shadow::SunHoursOptions map_options;
    map_options.threads = args.threads;
    shadow_cli::ProgressLine map_progress(!args.quiet && isatty(STDERR_FILENO), "sun-hours map faces");
    map_options.progress = [&](const shadow::Progress& p) { map_progress.update(p); };
    map = shadow::compute_sun_hours_map(engine, map_faces, shadow::sun_hours_instants(scene), map_options);
    map_progress.finish();
    shadow::write_sun_hours_vtp(output.path() / "sun_hours.vtp", *map, scene);
  } else {
    std::error_code ignored;  // an earlier run's map is not this run's
    fs::remove(output.path() / "sun_hours.vtp", ignored);
  }
  std::vector<fs::path> written = output.write_series(scene, suns, series, files, &run);
  if (map) written.insert(written.end() - 1, output.path() / "sun_hours.vtp");  // report.json stays last
  const auto finished = Clock::now();

  if (!args.quiet) {
    auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    const shadow::SurfaceSeries surfaces = shadow::surface_series(scene, series, suns.hours_per_instant);
    std::printf("shadow %s series: %zu instants, %zu above the horizon, %zu receiving faces, %zu named surfaces (%s)\n",
                shadow::version(), suns.all_instants, suns.lights.size(), series.faces.size(),
                surfaces.surfaces.size(), args.fast ? "fast" : "exact");
    const std::size_t shown = std::min<std::size_t>(surfaces.surfaces.size(), 10);
    for (std::size_t s = 0; s < shown; ++s)
      std::printf("  %-24s sun hours %.6g\n", surfaces.surfaces[s].label.c_str(), surfaces.sun_hours[s]);
    if (shown < surfaces.surfaces.size())
      std::printf("  ... %zu more in report.json\n", surfaces.surfaces.size() - shown);
    std::printf("  computed in %.3f s (%.1f ms per instant), written in %.3f s\n", seconds(computed - start),
                suns.lights.empty() ? 0.0 : 1000.0 * seconds(computed - start) / static_cast<double>(suns.lights.size()),
                seconds(finished - computed));
    std::size_t instant_files = 0;
    std::printf("  output: %s\n", fs::absolute(args.outdir).lexically_normal().c_str());
    for (const fs::path& p : written) {
      if (p.parent_path().filename() == "series") {
        ++instant_files;
        continue;
      }
      std::printf("    %s\n", p.filename().c_str());
    }
    if (instant_files > 0) std::printf("    series/ (%zu files, one per instant shown in series.pvd)\n", instant_files);
    if (map)
      std::printf("  sun-hours map: %zu cells on %zu faces (sun_hours.vtp)\n", map->cells.size(), map->faces.size());
  }
  return 0;
}
