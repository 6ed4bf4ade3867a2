// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow series SCENE.json -o OUTDIR`: every sun instant of the scene's `sun` block on every
// receiving face, areas only, written as sunlit.csv, energyplus-shading.csv, series.pvd,
// faces.vtp (sun_hours) and report.json (docs/series.md). The job itself is the library's
// shadow::SeriesJob; this file parses the options, turns signals into its stop flag, shows its
// progress and prints its summary.
#include "series_command.hpp"

#include "cli_checks.hpp"
#include "out_of_memory.hpp"
#include "progress_line.hpp"
#include "world.hpp"

#include <shadow/shadow.hpp>
#include <shadow/series_files.hpp>
#include <shadow/series_job.hpp>
#include <shadow/sun_hours.hpp>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

namespace {

namespace fs = std::filesystem;

}  // namespace

CLI::App* add_series_command(CLI::App& app, SeriesArgs& args) {
  CLI::App* series = app.add_subcommand(
      "series", "Compute every sun instant of the scene's `sun` block on every receiving face (areas only) and "
                "write sunlit.csv, sun_hours_by_object.csv (per building, zone or mesh), series.pvd, faces.vtp "
                "(sun_hours) and report.json; for an EnergyPlus model (or with --energyplus-shading) also "
                "energyplus-shading.csv and energyplus-objects.idf");
  series->footer(std::string(shadow_cli::exit_codes_help()) +
                 " Also 5: stopped by SIGINT or SIGTERM while keeping a checkpoint; --resume finishes the run. Across "
                 "machines: mpirun -np N shadow series ... (docs/cluster.md).");
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
                     "(1: all; 0: no series.pvd). Default: every instant for a period of up to 7 days; for a "
                     "longer one (a year) at most 48 instants spread evenly over it (every K-th, K as small as "
                     "that allows; the summary says which). sunlit.csv, energyplus-shading.csv and sun hours "
                     "always use every instant")
      ->default_str("1, or at most 48 files for a period over 7 days")
      ->check(shadow_cli::integer_in(0, 1000000))
      ->each([&args](const std::string&) { args.every_given = true; });
  series->add_flag("--fragments", args.fragments,
                   "Also write each instant's lit and shadowed polygons (series/fragments_NNNNN.vtp, fragments.pvd) "
                   "for the instants in series.pvd: one polygon computation per such instant, on top of the series");
  series->add_flag("--energyplus-shading", args.energyplus_shading,
                   "Write energyplus-shading.csv (EnergyPlus's Schedule:File:Shading, surface names in upper case as "
                   "EnergyPlus matches them) for any scene; without it only a scene read from an EnergyPlus model "
                   "(IDF/epJSON, as SCENE or a mesh file) or with \"energyplus_shading\": true gets one (docs/series.md)");
  series->add_option("--sun-hours-map", args.sun_hours_map,
                     "Write sun_hours.vtp: the exact sun-hours map of these meshes' faces (comma-separated mesh "
                     "names, city/<id> or type:<CityJSON type> such as type:TINRelief; adds to the scene's "
                     "`sun_hours_map`; docs/sun-hours-map.md)");
  series->add_option("--sun-hours-levels", args.sun_hours_levels,
                     "With the sun-hours map: also write sun_hours_levels.vtp, the exact regions getting at least "
                     "each of these hours (comma-separated, e.g. 2,4,6), and their areas to report.json")
      ->each([&args](const std::string&) { args.sun_hours_levels_given = true; });
  series->add_flag("--sun-hours-levels-only", args.sun_hours_levels_only,
                   "With --sun-hours-levels: compute the threshold map alone, not the full map (no sun_hours.vtp): "
                   "its memory follows the level boundaries instead of growing with the number of instants");
  series->add_option("--sun-hours-held-segments", args.sun_hours_held_segments,
                     "With --sun-hours-levels-only: the most exact boundary segments held at once (packed, some "
                     "120-200 bytes each; default 1048576); past it lit regions are computed again, in less memory and more time "
                     "(docs/sun-hours-map.md)")
      ->check(shadow_cli::integer_in(0, static_cast<long long>(shadow::kMaxLevelHeldSegments)));
  series->add_option("--planarity-tolerance", args.planarity_tolerance,
                     "Largest vertex distance from a face's plane, relative to the face's size")
      ->default_val(1e-6)
      ->check(shadow_cli::positive_up_to(1.0));
  series->add_flag("--orient-outward", args.orient_outward,
                   "Turn the closed parts of every mesh outward (as for `shadow compute`)");
  shadow_cli::add_tile_options<shadow::SeriesOptions>(
      *series, args.tile_casters, args.fast_tile_casters,
      {" at an instant", "sun hours and lit fractions", "--fragments", "--fast", "lit fractions"});
  series->add_option("--lod", args.lod, "CityJSON level of detail to read (default: the highest of each city object)");
  series->add_flag("--skip-invalid", args.skip_invalid, shadow_cli::skip_invalid_help());
  series->add_option("--from", args.from,
                     "First local date of the sun period (YYYY-MM-DD), replacing the scene's or the model's "
                     "(an EnergyPlus RunPeriod); its site stays");
  series->add_option("--to", args.to, "Last local date of the sun period (YYYY-MM-DD, inclusive)");
  series->add_option("--step", args.step_minutes, "Minutes between sun instants (dividing a day)")
      ->check(shadow_cli::integer_in(1, 1440));
  series->add_flag("--checkpoint", args.checkpoint,
                   "Keep the instants computed so far in OUTDIR/series.checkpoint as the run goes (flushed to "
                   "disk after every round), so that an interrupted run can be finished with --resume; removed "
                   "when the outputs are written (docs/cluster.md)");
  series->add_flag("--resume", args.resume,
                   "Compute only the instants that OUTDIR/series.checkpoint lacks (a checkpoint of another scene "
                   "or other options is refused); without a checkpoint, start from the first instant. Implies "
                   "--checkpoint. The outputs are byte for byte those of an uninterrupted run");
  series->add_option("--write-idf", args.write_idf,
                     "Also write FILE: a copy of the EnergyPlus model given as SCENE (IDF in, IDF out; epJSON "
                     "in, epJSON out) with ShadowCalculation (Imported) and Schedule:File:Shading naming "
                     "OUTDIR/energyplus-shading.csv in place of its own (docs/energyplus.md)");
  // A test hook (docs/cluster.md): interrupt deterministically, as a signal or a time limit would.
  series->add_option("--stop-after", args.stop_after,
                     "Testing: stop (exit 5) after the round in which N instants are in the checkpoint (rounds "
                     "then keep their first size: 4 instants per thread, at least 8, per rank)")
      ->check(shadow_cli::integer_in(1, 1000000000))
      ->group("");
  return series;
}

namespace {

/// Set by SIGINT/SIGTERM while a checkpointed run computes: the job stops after the round in progress.
std::atomic<int> g_stop_signal{0};

extern "C" void on_stop_signal(int signal) { g_stop_signal.store(signal); }

/// SIGINT and SIGTERM set g_stop_signal while the instants are computed (a checkpointed run
/// only: elsewhere they end the process as usual); the previous handlers come back at release()
/// or at the end of the scope.
class StopSignals {
 public:
  StopSignals() = default;
  ~StopSignals() { release(); }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  void install() {
    if (installed_) return;
    installed_ = true;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    action.sa_flags = SA_RESETHAND;  // a second signal ends the process at once (the checkpoint stays valid)
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
  }
  void release() {
    if (!installed_) return;
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
    installed_ = false;
  }

 private:
  bool installed_ = false;
  struct sigaction previous_int_ {}, previous_term_ {};
};

/// The --sun-hours-map names, comma-separated.
std::vector<std::string> mesh_names(const std::string& list) {
  std::vector<std::string> names;
  std::size_t begin = 0;
  while (begin <= list.size()) {
    const std::size_t comma = std::min(list.find(',', begin), list.size());
    names.push_back(list.substr(begin, comma - begin));
    begin = comma + 1;
  }
  return names;
}

shadow::SeriesJobOptions job_options(const SeriesArgs& args) {
  shadow::SeriesJobOptions o;
  o.keep_table = false;  // the files are streamed: memory does not grow with the instants
  o.scene = args.scene;
  o.output = args.outdir;
  o.load = shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod, args.threads,
                                    args.skip_invalid);
  o.from = args.from;
  o.to = args.to;
  o.step_minutes = args.step_minutes;
  o.threads = args.threads;
  o.arithmetic = args.fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
  o.tile_casters = args.tile_casters;
  o.fast_tile_casters = args.fast_tile_casters;
  if (args.every_given) o.every = args.every;
  o.fragments = args.fragments;
  if (args.energyplus_shading) o.energyplus_shading = true;
  if (!args.sun_hours_map.empty()) o.sun_hours_map = mesh_names(args.sun_hours_map);
  // Given empty ("" from a script's unset variable): an error, not a run without the levels.
  if (args.sun_hours_levels_given) o.sun_hours_levels = shadow::parse_sun_hours_levels(args.sun_hours_levels);
  o.sun_hours_levels_only = args.sun_hours_levels_only;
  o.sun_hours_held_segments = args.sun_hours_held_segments;
  o.checkpoint = args.checkpoint;
  o.resume = args.resume;
  o.stop_after = args.stop_after;
  o.write_idf = args.write_idf;
  o.stop = &g_stop_signal;
  return o;
}

/// The job's progress on stderr: on a terminal one line rewritten in place; in a log (stderr
/// sent to a file, an MPI job's or a batch job's output) a line now and then.
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool distributed) : distributed_(distributed), log_lines_(isatty(STDERR_FILENO) == 0) {}
  void operator()(const shadow::SeriesJobProgress& p) {
    const bool instants = p.part == shadow::SeriesJobProgress::Part::Instants;
    std::optional<shadow_cli::ProgressLine>& line = instants ? instants_ : map_;
    if (!line) {  // a part's first report: nothing done in this run yet
      line.emplace(true,
                   instants ? "instants" : distributed_ ? "sun-hours map faces (rank 0's block)" : "sun-hours map faces",
                   p.base, log_lines_);
      return;
    }
    if (p.finished)
      line->finish();
    else
      line->update({p.done, p.total});
  }

 private:
  bool distributed_;
  bool log_lines_;
  std::optional<shadow_cli::ProgressLine> instants_, map_;
};

/// The summary's last words: what to do with energyplus-shading.csv.
void print_hand_back(const shadow::SeriesEnergyPlusHandBack& back, const SeriesArgs& args,
                     const std::vector<fs::path>& written) {
  const bool csv = std::any_of(written.begin(), written.end(),
                               [](const fs::path& p) { return p.filename() == "energyplus-shading.csv"; });
  if (!csv) return;
  if (!back.note.empty()) std::printf("  note: %s\n", back.note.c_str());
  if (back.objects.empty()) {
    std::printf("  EnergyPlus: no energyplus-objects.idf (%s)\n", back.problem.c_str());
    return;
  }
  if (back.copy) {
    std::printf("  EnergyPlus: %s is the model with ShadowCalculation (Imported) and Schedule:File:Shading reading\n"
                "    %s (%d object(s) of the model replaced); run EnergyPlus on it with the same weather file\n",
                args.write_idf.c_str(), back.csv.c_str(), back.copy->replaced);
    const int version = back.copy->version_code;
    if (version > 0 && version < 906)
      std::printf("  note: the model says Version %s; ShadowCalculation's fields are written in the order of "
                  "EnergyPlus 9.6 and later\n", back.copy->version.c_str());
    return;
  }
  if (!back.model) {
    std::printf("  EnergyPlus: energyplus-objects.idf holds the objects that make a model read energyplus-shading.csv\n");
    return;
  }
  // An EnergyPlus model in: say exactly what to add to it.
  std::printf("  EnergyPlus: add these objects (also in energyplus-objects.idf) to the model, replacing its own\n"
              "  ShadowCalculation, or run again with --write-idf FILE for a copy of the model with them in place:\n\n");
  std::size_t begin = 0;
  while (begin < back.objects.size()) {
    const std::size_t end = std::min(back.objects.find('\n', begin), back.objects.size());
    const std::string line = back.objects.substr(begin, end - begin);
    std::printf(line.empty() ? "\n" : "    %s\n", line.c_str());
    begin = end + 1;
  }
}

/// The files written, the series/ folder as one line.
std::size_t print_files(const SeriesArgs& args, const std::vector<fs::path>& written) {
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
  return instant_files;
}

/// Why there is no energyplus-shading.csv: unasked, or the period cannot be one.
void print_no_energyplus(const shadow::SeriesJobResult& r, const SeriesArgs& args) {
  const bool written = std::any_of(r.written.begin(), r.written.end(),
                                   [](const fs::path& p) { return p.filename() == "energyplus-shading.csv"; });
  if (written) return;
  const bool wanted = args.energyplus_shading || shadow::energyplus_shading_wanted(r.scene);
  if (wanted)
    std::printf("  no energyplus-shading.csv: %s\n", shadow::energyplus_schedule(r.scene).reason.c_str());
  else if (r.scene.energyplus_shading)
    std::printf("  no energyplus-shading.csv (the scene's \"energyplus_shading\" is false)\n");
  else
    std::printf("  no energyplus-shading.csv (not an EnergyPlus model; --energyplus-shading writes one)\n");
}

void print_summary(const shadow::SeriesJobResult& r, const SeriesArgs& args) {
  const shadow::SurfaceSeries& surfaces = r.surfaces;  // the job's sums: it keeps no table (keep_table false)
  std::printf("shadow %s series: %zu instants, %zu above the horizon, %zu receiving faces, %zu named surfaces (%s)\n",
              shadow::version(), r.suns.all_instants, r.suns.lights.size(), r.series.faces.size(),
              surfaces.surfaces.size(), args.fast ? "fast" : "exact");
  const std::size_t shown = std::min<std::size_t>(surfaces.surfaces.size(), 10);
  for (std::size_t s = 0; s < shown; ++s)
    std::printf("  %-24s sun hours %.6g\n", surfaces.surfaces[s].label.c_str(), surfaces.sun_hours[s]);
  if (shown < surfaces.surfaces.size()) std::printf("  ... %zu more in report.json\n", surfaces.surfaces.size() - shown);
  std::printf("  sun hours of %zu objects (buildings, zones, meshes; area-weighted) in sun_hours_by_object.csv\n",
              shadow::scene_objects(r.scene).size());
  const std::size_t computed_now = r.suns.lights.size() - r.resumed;
  std::printf("  computed in %.3f s (%.1f ms per instant), ", r.compute_seconds,
              computed_now == 0 ? 0.0 : 1000.0 * r.compute_seconds / static_cast<double>(computed_now));
  if (r.map) std::printf("sun-hours map in %.3f s, ", r.map_seconds);
  std::printf("written in %.3f s\n", r.write_seconds);
  if (args.skip_invalid || !r.scene.skipped_faces.empty())
    std::printf("  skipped: %zu invalid faces (--skip-invalid; report.json: skipped_faces)\n", r.scene.skipped_faces.size());
  if (r.ranks > 1) std::printf("  on %d MPI ranks\n", r.ranks);
  if (r.resumed > 0) std::printf("  resumed: %zu instants came from the checkpoint\n", r.resumed);
  const std::size_t instant_files = print_files(args, r.written);
  if (!args.every_given && r.every > 1)
    std::printf("  series.pvd shows %zu of the %zu instants above the horizon, one in %zu (by default at most %zu "
                "on a period over %g days; --every 1 shows them all, --every 0 none)\n",
                instant_files, r.suns.lights.size(), r.every, shadow::kSeriesDefaultInstantFiles,
                shadow::kSeriesLongPeriodDays);
  print_no_energyplus(r, args);
  if (r.map && r.map->full)
    std::printf("  sun-hours map: %zu cells on %zu faces (sun_hours.vtp)\n", r.map->cells.size(), r.map->faces.size());
  if (r.map && !r.map->full) std::printf("  sun-hours map: threshold map alone on %zu faces\n", r.map->faces.size());
  if (r.map) std::printf("%s", shadow::sun_hours_levels_summary(*r.map, "  ").c_str());
  print_hand_back(r.energyplus, args, r.written);
}

shadow_cli::Stage cli_stage(shadow::SeriesJobStage stage) {
  switch (stage) {
    case shadow::SeriesJobStage::Loading: return shadow_cli::Stage::Loading;
    case shadow::SeriesJobStage::Preparing: return shadow_cli::Stage::Preparing;
    case shadow::SeriesJobStage::Writing: return shadow_cli::Stage::Writing;
    default: return shadow_cli::Stage::Computing;
  }
}

std::string stopped_line(const shadow::SeriesJobStopped& stopped) {
  return "shadow: stopped after " + std::to_string(stopped.done) + " of " + std::to_string(stopped.total) +
         " instants (" +
         (stopped.signal != 0 ? std::string("signal ") + std::to_string(stopped.signal) : std::string("--stop-after")) +
         "); they are kept in " + stopped.checkpoint.string() +
         ": run the same command with --resume to compute the rest";
}

int run_series_in(shadow_cli::World& world, const SeriesArgs& args) {
  const bool talk = world.root() && !args.quiet;
  shadow::SeriesJobOptions options = job_options(args);
  const bool checkpointing = options.checkpoint || options.resume || options.stop_after > 0;
  StopSignals signals;
  ProgressPrinter printer(world.distributed());
  if (talk) {
    options.progress = [&](const shadow::SeriesJobProgress& p) { printer(p); };
    options.notice = [](const std::string& line) { std::cerr << "shadow: " << line << "\n"; };
  }
  options.stage = [&](shadow::SeriesJobStage stage) {
    shadow_cli::set_stage(cli_stage(stage));
    // Only the instants' rounds stop at a signal (after the round in progress).
    if (stage == shadow::SeriesJobStage::Computing && checkpointing) signals.install();
    if (stage == shadow::SeriesJobStage::Mapping) signals.release();
  };
  shadow::SeriesJob job(std::move(options), world);
  shadow::SeriesJobResult result;
  try {
    result = job.run();
  } catch (const shadow::SeriesJobStopped& stopped) {
    throw shadow_cli::RunStopped(5, stopped_line(stopped));
  }
  if (talk) print_summary(result, args);
  return 0;
}

}  // namespace

int run_series(const SeriesArgs& args) {
  // Several ranks print one message (rank 0's) and leave with the same status; a single process
  // lets its exceptions reach main() as before.
  std::optional<shadow_cli::World> world;
  try {
    world.emplace();
    return run_series_in(*world, args);
  } catch (const shadow_cli::RunStopped& stopped) {
    if ((!world || world->root()) && *stopped.what() != '\0') std::cerr << stopped.what() << "\n";
    return stopped.code;
  }
}
