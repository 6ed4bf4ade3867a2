// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow irradiance SCENE --weather FILE.epw -o OUTDIR`: the irradiation of every receiving face
// over a weather year, direct, sky diffuse and ground-reflected (docs/irradiance.md).
#include "irradiance_command.hpp"

#include "cli_checks.hpp"
#include "out_of_memory.hpp"
#include "progress_line.hpp"

#include <shadow/shadow.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <tuple>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// The comma-separated names of --map and --ground.
std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> names;
  std::size_t begin = 0;
  while (begin <= list.size()) {
    const std::size_t comma = std::min(list.find(',', begin), list.size());
    names.push_back(list.substr(begin, comma - begin));
    begin = comma + 1;
  }
  return names;
}

/// A date of --from or --to: `MM-DD`, or `YYYY-MM-DD` (year 0 when none is written).
struct PeriodDate {
  int year = 0, month = 0, day = 0;
  std::pair<int, int> month_day() const { return {month, day}; }
};

PeriodDate period_date(const std::string& text, const char* flag) {
  PeriodDate d;
  char tail = 0;
  const bool with_year = std::sscanf(text.c_str(), "%d-%d-%d%c", &d.year, &d.month, &d.day, &tail) == 3;
  if (!with_year) d.year = 0;
  const bool without = !with_year && std::sscanf(text.c_str(), "%d-%d%c", &d.month, &d.day, &tail) == 2;
  if ((!with_year && !without) || !shadow::is_valid_date(with_year ? d.year : 2024, d.month, d.day) ||
      (with_year && d.year < 1))
    throw shadow::InputError({"", flag}, "'" + text + "' is not a date: write MM-DD or YYYY-MM-DD");
  return d;
}

/// The records [first, end) of the period --from..--to (inclusive dates) in the weather file.
/// The dates are placed on the file's own timeline, which may run past 31 December (an actual
/// year from July to June, `--from 03-01` means the March in it): --from is the first time that
/// date begins at or after the day of the first record, --to the first time that date ends after
/// --from (so `--from 12-01 --to 02-28` is a winter, where the file holds one). A date with its
/// year is that day when the file's records hold it (a file of several years, or an actual
/// year); on a file of a year or less that does not hold it (a typical year, stamped with other
/// years) only its month and day count; on a longer file it is an error. Without --from the
/// period begins with the file, without --to it ends with it. A period that ends after the
/// file's last record is an error naming it, not a shorter period without a word.
std::pair<std::size_t, std::size_t> period_records(const shadow::Weather& w, const IrradianceArgs& args) {
  if (args.from.empty() && args.to.empty()) return {0, w.hours()};
  const auto offset = static_cast<std::int64_t>(std::llround(w.location.time_zone_hours * 3600.0));
  const auto local = [&](std::size_t r) { return w.start_utc[r] + offset; };  // local standard seconds
  const auto floor_day = [](std::int64_t t) { return t >= 0 ? t / 86400 : -((-t + 86399) / 86400); };
  const std::size_t last = w.hours() - 1;
  const std::int64_t file_begins = local(0), file_ends = local(last) + 3600;
  const std::int64_t first_day = floor_day(file_begins), last_day = floor_day(file_ends - 1);
  const auto record_text = [&](std::size_t r) {  // the record's day on the timeline (its hour ends it)
    const auto day = shadow::civil_from_days(floor_day(local(r)));
    return std::to_string(day.year) + "-" + std::to_string(w.month[r]) + "-" + std::to_string(w.day[r]) + " hour " +
           std::to_string(w.hour[r]);
  };
  const std::string span = " (the records run from " + record_text(0) + " to " + record_text(last) + ")";
  // The first midnight of month/day in the year of day `from_day` or a later one, at or after it.
  const auto day_on_or_after = [](std::pair<int, int> md, std::int64_t from_day) {
    std::int64_t year = shadow::civil_from_days(from_day).year;
    for (int k = 0; k < 8; ++k, ++year)
      if (shadow::is_valid_date(year, md.first, md.second) && shadow::days_from_civil(year, md.first, md.second) >= from_day)
        return shadow::days_from_civil(year, md.first, md.second);
    return from_day;  // (not reached: 29 February comes within 8 years)
  };
  // A date's day on the timeline: its own where the file holds it, else by month and day on a
  // file of a year or less, else an error.
  const bool longer_than_a_year = last_day - first_day + 1 > 366;
  const auto day_of = [&](const PeriodDate& d, const std::string& text, const char* flag, std::int64_t from_day) {
    if (d.year != 0) {
      const std::int64_t own = shadow::days_from_civil(d.year, d.month, d.day);
      if (own >= first_day && own <= last_day) return own;
      if (longer_than_a_year)
        throw shadow::InputError({args.weather, ""}, std::string(flag) + " " + text +
                                                         " is not a day of the weather file, which holds more than a "
                                                         "year: write a day in it, or MM-DD" + span);
    }
    return day_on_or_after(d.month_day(), from_day);
  };
  std::optional<PeriodDate> from, to;
  if (!args.from.empty()) from = period_date(args.from, "--from");
  if (!args.to.empty()) to = period_date(args.to, "--to");
  // 29 February where the records have none (a typical year is not a leap year) says so, rather
  // than that no record falls on or after it.
  bool has_leap_day = false;
  for (std::size_t r = 0; r < w.hours() && !has_leap_day; ++r) has_leap_day = w.month[r] == 2 && w.day[r] == 29;
  for (const auto& [date, text, flag] : {std::tuple{&from, &args.from, "--from"}, std::tuple{&to, &args.to, "--to"}})
    if (*date && (*date)->month == 2 && (*date)->day == 29 && !has_leap_day)
      throw shadow::InputError({args.weather, ""}, std::string(flag) + " " + *text +
                                                       ": the weather file has no 29 February (its records are not "
                                                       "of a leap year); write 02-28 or 03-01" + span);
  if (from && to && from->year == 0 && to->year == 0) {
    const bool across_new_year = shadow::civil_from_days(first_day).year != shadow::civil_from_days(last_day).year;
    if (from->month_day() > to->month_day() && !across_new_year)
      throw shadow::InputError({"", "--from"}, "the period ends (--to " + args.to + ") before it starts (a period across "
                                               "31 December needs a weather file whose records run across it)" + span);
  }
  std::int64_t begin = file_begins, end = file_ends;
  if (from) begin = day_of(*from, args.from, "--from", first_day) * 86400;
  if (begin >= file_ends)
    throw shadow::InputError({args.weather, ""}, "no record of the weather file falls on or after --from " + args.from + span);
  if (to) {
    end = (day_of(*to, args.to, "--to", floor_day(begin)) + 1) * 86400;
    if (end <= begin)
      throw shadow::InputError({"", "--to"}, "the period ends (--to " + args.to + ") before it starts (--from " +
                                                 args.from + ")" + span);
    if (end > file_ends)
      throw shadow::InputError({args.weather, ""}, "the period --from " + (args.from.empty() ? std::string("(the file's start)") : args.from) +
                                                       " --to " + args.to + " ends after the file's last record" + span);
  }
  std::size_t first = 0;
  while (first < w.hours() && local(first) < begin) ++first;
  std::size_t stop = first;
  while (stop < w.hours() && local(stop) < end) ++stop;
  if (first == stop)
    throw shadow::InputError({args.weather, ""}, "no record of the weather file falls between --from and --to" + span);
  return {first, stop};
}

}  // namespace

CLI::App* add_irradiance_command(CLI::App& app, IrradianceArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "irradiance", "Solar irradiation of every receiving face over a weather year (EPW or TMY3): direct through each "
                    "face's exact sunlit fraction, sky diffuse (Perez or isotropic) through its exact view of the "
                    "sky patches, ground-reflected through its exact view of the ground patches; writes report.json, irradiation.csv, faces.vtp (docs/irradiance.md)");
  cmd->footer(shadow_cli::exit_codes_help());
  cmd->add_option("scene", args.scene, "Scene file (JSON) or model (IDF, epJSON, CityJSON)")->required();
  cmd->add_option("--weather", args.weather, "Weather file: EnergyPlus EPW, or NREL TMY3 CSV (a name ending in .csv): site, time zone and hourly "
                  "irradiation")
      ->required();
  cmd->add_option("-o,--output", args.outdir, "Output directory (created if missing)")->required();
  cmd->add_option("--sky", args.sky, "Sky diffuse model")->check(CLI::IsMember({"perez", "isotropic"}))->default_val("perez");
  cmd->add_option("--sky-patches", args.sky_patches, "Sky patches: 145 (Tregenza), 577 or 2305 (Reinhart)")
      ->check(CLI::IsMember({145, 577, 2305}))
      ->default_val(145);
  cmd->add_option("--ground-reflectance", args.ground_reflectance,
                  "Ground reflectance in [0, 1] (default: the weather file's mean albedo, else 0.2)")
      ->check(shadow_cli::finite_in(0.0, 1.0));
  cmd->add_option("--from", args.from, "First day of the period (MM-DD, or YYYY-MM-DD: that day where the weather file holds it)");
  cmd->add_option("--to", args.to, "Last day of the period, inclusive");
  cmd->add_flag("--fast", args.fast, "The fast path for the sunlit fractions (doubles; docs/numeric-contract.md)");
  cmd->add_option("--map", args.map,
                  "Write irradiation_map.vtp: these meshes' faces (comma-separated mesh names, or type:<CityJSON "
                  "type>) cut along the exact shadow boundaries of every hour's beam, each cell with its direct "
                  "kWh/m2 plus its face's diffuse and reflected parts (exact sun-hours maps weighted by DNI cos)");
  cmd->add_option("--ground", args.ground,
                  "The meshes that are the ground (comma-separated mesh names, or type:<CityJSON type>), instead of "
                  "the scene's `ground` or the default (meshes named ground, CityJSON terrain and land): below the "
                  "horizon a face sees the ground where it sees one of them or no face at all");
  cmd->add_flag("--reflections", args.reflections,
                "Add what the scene's own faces reflect (radiosity on the period's irradiation; each face's material "
                "reflectance, else the ground reflectance; the period's total only; docs/irradiance.md)");
  cmd->add_flag("--hourly", args.hourly, "Also write irradiance_hourly.csv (W/m2 per named surface and hour)");
  cmd->add_flag("-q,--quiet", args.quiet, "Print nothing but errors");
  cmd->add_option("-t,--threads", args.threads, "Worker threads (0: all cores; at most 1024)")
      ->default_val(0)
      ->check(shadow_cli::integer_in(0, 1024));
  shadow_cli::add_scene_reading_options(cmd, args.planarity_tolerance, args.orient_outward, args.lod, args.skip_invalid);
  return cmd;
}

namespace {

/// The weather file's warnings, then the scene's, one line each on stderr.
void print_warnings(const std::vector<shadow::Warning>& weather, const std::vector<shadow::Warning>& scene) {
  for (const std::vector<shadow::Warning>* list : {&weather, &scene})
    for (const shadow::Warning& warning : *list) std::cerr << "shadow: warning: " << warning.to_string() << "\n";
}

/// The summary's stage times and the energy check (docs/irradiance.md, Energy check).
void print_times_and_check(const shadow::IrradianceResult& result, double seconds) {
  std::printf("  computed in %.3f s: sky patches %.3f s, ground patches %.3f s, sun %.3f s, sums %.3f s; energy check %s\n",
              seconds, result.seconds_sky, result.seconds_ground, result.seconds_sun, result.seconds_sums,
              result.energy_check_ok() ? "ok" : "FAILED (report.json: energy_check)");
  if (result.max_horizon_band_excess > 1e-6)
    std::printf("  sky diffuse up to %.3g W/m2 above the unshaded on faces whose horizon is hidden: Perez's horizon "
                "band is negative in some hours (a low sun), and hiding it takes that away (the model's own; "
                "docs/irradiance.md, Energy check)\n",
                result.max_horizon_band_excess);
}

}  // namespace

int run_irradiance(const IrradianceArgs& args) {
  const auto start = Clock::now();
  const bool talk = !args.quiet;
  shadow::IrradianceRunInfo run;
  run.scene = args.scene;
  run.weather = args.weather;
  run.from = args.from;
  run.to = args.to;
  run.threads = args.threads;
  run.started_utc = shadow::utc_now();

  using shadow_cli::Stage;
  shadow_cli::set_stage(Stage::Loading);
  const shadow::Weather weather = shadow::read_weather(args.weather);
  const auto [first, end] = period_records(weather, args);
  shadow::LoadOptions load = shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod,
                                                      args.threads, args.skip_invalid);
  load.require_lights = false;  // the suns come from the weather file
  shadow::Scene scene = shadow::load_scene(args.scene, load);
  std::vector<std::size_t> map_faces;
  if (!args.map.empty()) {
    map_faces = shadow::sun_hours_map_faces(scene, split_names(args.map), "--map");
  }
  if (!args.ground.empty()) {
    scene.ground.emplace();
    for (const std::string& name : split_names(args.ground))
      for (std::size_t m : shadow::select_meshes(scene, name, {args.scene, "--ground"}))
        if (std::find(scene.ground->begin(), scene.ground->end(), m) == scene.ground->end()) scene.ground->push_back(m);
  }
  if (talk) print_warnings(weather.warnings, scene.warnings);

  shadow::IrradianceOptions options;
  options.sky = args.sky == "isotropic" ? shadow::SkyModel::Isotropic : shadow::SkyModel::Perez;
  options.sky_patches = args.sky_patches;
  if (args.ground_reflectance >= 0.0) options.ground_reflectance = args.ground_reflectance;
  options.first_record = first;
  options.end_record = end;
  // The model's north: a scene's `sun` block (or an EnergyPlus Building's north axis) turns it.
  if (scene.sun) {
    options.north_axis = scene.sun->north_axis;
    options.delta_t = scene.sun->delta_t;
    const shadow::SolarSite& site = scene.sun->site;
    if (talk && (std::abs(site.latitude - weather.location.latitude) > 0.5 ||
                 std::abs(site.longitude - weather.location.longitude) > 0.5))
      std::fprintf(stderr,
                   "shadow: warning: %s: the scene's sun block is at %.2f N %.2f E, the weather file at %.2f N %.2f E: "
                   "the weather file's site is used\n",
                   args.scene.c_str(), site.latitude, site.longitude, weather.location.latitude,
                   weather.location.longitude);
  }
  options.series.threads = args.threads;
  options.series.arithmetic = args.fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
  const bool log_lines = isatty(STDERR_FILENO) == 0;
  std::optional<shadow_cli::ProgressLine> progress;
  std::string stage;
  options.progress = [&](const std::string& what, const shadow::Progress& p) {
    if (what != stage) {
      if (progress) progress->finish();
      progress.emplace(talk, what == "sun" ? "sun instants" : what, 0, log_lines);
      stage = what;
    }
    progress->update(p);
  };

  // OUTDIR held for the whole run, as `shadow series` holds it (shadow::OutputDirectory): a second
  // run into it is refused at once (OutputError, exit 3) instead of mixing files; the lock is
  // taken once the inputs are read and checked, before any computing, and freed at the end.
  const shadow::OutputDirectory output(args.outdir);

  std::optional<shadow::ShadowEngine> engine;
  shadow::IrradianceResult result;
  std::optional<shadow::SunHoursMap> map;
  try {
    shadow_cli::set_stage(Stage::Preparing);
    engine.emplace(scene, args.threads);
    shadow_cli::set_stage(Stage::Computing);
    result = shadow::compute_irradiance(*engine, scene, weather, options);
    if (args.reflections) {
      shadow::ReflectionOptions reflections;
      reflections.default_reflectance = result.ground_reflectance;
      reflections.threads = args.threads;
      reflections.progress = [&](const shadow::RadiosityProgress& p) {
        // Progress as the share of the power shot, in thousandths; a hierarchical solution spends
        // most of its time on its links first.
        const double shot = std::clamp(1.0 - p.unshot_fraction, 0.0, 1.0);
        const double done = !p.shots_are_iterations ? shot : p.links_fraction < 1.0 ? 0.9 * p.links_fraction : 0.9 + 0.1 * shot;
        options.progress("reflections", {static_cast<std::size_t>(1000.0 * done), 1000});
      };
      shadow::add_scene_reflections(scene, result, reflections);
    }
    if (!map_faces.empty()) {
      shadow::SunHoursOptions map_options;
      map_options.threads = args.threads;
      map_options.progress = [&](const shadow::Progress& p) { options.progress("irradiation map", p); };
      map.emplace(shadow::irradiation_map(*engine, result, map_faces, map_options));
    }
  } catch (const shadow::InputError& e) {
    shadow_cli::rethrow_naming_scene(e, args.scene);
  }
  if (progress) progress->finish();
  const auto computed = Clock::now();

  shadow_cli::set_stage(Stage::Writing);
  shadow::IrradianceFiles files;
  files.hourly = args.hourly;
  files.energyplus = shadow::energyplus_shading_wanted(scene);
  if (map) files.map = &*map;
  run.seconds_total = std::chrono::duration<double>(computed - start).count();
  const std::vector<fs::path> written = shadow::write_irradiance_outputs(args.outdir, scene, weather, result, run, files);
  if (!talk) return 0;

  std::printf("shadow irradiance: %zu receiving faces, %zu hours of %s (%s, %.2f N %.2f E), %zu suns, %zu sky patches, "
              "%s sky, ground reflectance %.3g\n",
              result.faces.size(), result.hours.size(), args.weather.c_str(), weather.location.city.c_str(),
              weather.location.latitude, weather.location.longitude, result.sun_lights.size(), result.patches.size(),
              args.sky.c_str(), result.ground_reflectance);
  if (result.missing_hours > 0)
    std::printf("  %zu hours with direct normal or diffuse horizontal irradiation missing in the weather file: "
                "the missing value counted as 0\n",
                result.missing_hours);
  const std::vector<shadow::IrradianceGroup> surfaces =
      shadow::irradiance_groups(scene, result, shadow::IrradianceGrouping::Surface);
  const std::size_t shown = std::min<std::size_t>(surfaces.size(), 10);
  for (std::size_t s = 0; s < shown; ++s)
    std::printf("  %-24s %.6g kWh/m2 (direct %.4g, sky %.4g, ground %.4g), sky view %.3f, ground view %.3f\n",
                surfaces[s].name.c_str(), surfaces[s].total, surfaces[s].direct, surfaces[s].sky_diffuse,
                surfaces[s].ground_reflected, surfaces[s].sky_view_factor, surfaces[s].ground_view_factor);
  if (surfaces.size() > shown) std::printf("  ... %zu more in irradiation.csv\n", surfaces.size() - shown);
  print_times_and_check(result, std::chrono::duration<double>(computed - start).count());
  if (!result.scene_reflected.empty() && result.reflections.hierarchical)
    std::printf("  reflections: %zu radiosity elements, hierarchical (%zu near and %zu far links, %zu iterations), "
                "unshot %.3g%%, error estimate %.3g%%, in %.3f s (in the totals above)\n",
                result.reflections.elements, result.reflections.near_links, result.reflections.far_links,
                result.reflections.iterations, 100.0 * result.reflections.unshot_fraction,
                100.0 * result.reflections.error_estimate, result.reflections.seconds);
  else if (!result.scene_reflected.empty())
    std::printf("  reflections: %zu radiosity elements, %zu shots, unshot %.3g%%, in %.3f s (in the totals above)\n",
                result.reflections.elements, result.reflections.shots, 100.0 * result.reflections.unshot_fraction,
                result.reflections.seconds);
  if (map) std::printf("  irradiation map: %zu cells on %zu faces (irradiation_map.vtp)\n", map->cells.size(), map->faces.size());
  std::printf("  output: %s\n", fs::absolute(args.outdir).lexically_normal().c_str());
  for (const fs::path& p : written) std::printf("    %s\n", p.filename().c_str());
  return 0;
}
