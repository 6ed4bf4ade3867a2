// SPDX-License-Identifier: GPL-3.0-or-later
// `shadow series SCENE.json -o OUTDIR`: every sun instant of the scene's `sun` block on every
// receiving face, areas only, written as sunlit.csv, energyplus-shading.csv, series.pvd,
// faces.vtp (sun_hours) and report.json (docs/series.md).
#include "series_command.hpp"

#include "cli_checks.hpp"
#include "out_of_memory.hpp"
#include "progress_line.hpp"
#include "series_checkpoint.hpp"
#include "world.hpp"

#include <shadow/shadow.hpp>
#include <shadow/series_files.hpp>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

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

std::size_t default_every(std::size_t instants, const std::vector<std::int64_t>& times) {
  if (instants == 0 || times.size() < 2) return 1;
  const double days = static_cast<double>(times.back() - times.front()) / 86400.0;
  if (!(days > kLongSeriesDays)) return 1;
  return std::max<std::size_t>(1, (instants + kDefaultInstantFiles - 1) / kDefaultInstantFiles);
}

namespace {

/// Set by SIGINT/SIGTERM while a checkpointed run computes: stop after the round in progress.
volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal) { g_stop_signal = signal; }

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

/// major * 100 + minor of an EnergyPlus version identifier ("9.6", "24.1.0"); 0 if none.
int version_number(const std::string& text) {
  int major = 0, minor = 0;
  if (std::sscanf(text.c_str(), "%d.%d", &major, &minor) < 1) return 0;
  return major * 100 + minor;
}

/// What the run hands back to EnergyPlus: the objects that import energyplus-shading.csv
/// (energyplus-objects.idf) and, with --write-idf, a copy of the model with them in place.
struct EnergyPlusHandBack {
  std::string csv;      ///< the CSV's absolute path, as Schedule:File:Shading names it
  std::string objects;  ///< empty when the CSV cannot be named in an IDF field
  std::string problem;  ///< why `objects` is empty
  bool model = false;   ///< SCENE is an EnergyPlus model
  std::optional<shadow::EnergyPlusImportCopy> copy;  ///< --write-idf
};

EnergyPlusHandBack prepare_hand_back(const SeriesArgs& args, const shadow::Scene& scene) {
  EnergyPlusHandBack back;
  back.csv = (fs::absolute(args.outdir) / "energyplus-shading.csv").lexically_normal().string();
  back.model = shadow::is_energyplus_model(args.scene);
  try {
    back.objects = shadow::energyplus_import_objects(back.csv);
  } catch (const shadow::InputError& e) {
    back.problem = e.problem();
    if (!args.write_idf.empty()) throw shadow::InputError({"", "--write-idf"}, "the CSV's path " + back.csv + ": " + e.problem());
  }
  if (args.write_idf.empty()) return back;
  // Checked before computing: a model copy that cannot be made must not cost a year of suns.
  const shadow::EnergyPlusSchedule schedule = shadow::energyplus_schedule(scene);
  if (!schedule.written)
    throw shadow::InputError({"", "--write-idf"}, "energyplus-shading.csv cannot be written for this run: " + schedule.reason);
  std::error_code ec;
  if (fs::equivalent(args.scene, args.write_idf, ec))
    throw shadow::InputError({"", "--write-idf"}, args.write_idf + " is the model itself: name another file");
  const fs::path parent = fs::absolute(args.write_idf).parent_path();
  if (!fs::is_directory(parent, ec))
    throw shadow::InputError({"", "--write-idf"}, "no directory " + parent.string() + " to write " + args.write_idf + " in");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw shadow::InputError({"", "--write-idf"}, "cannot write in " + parent.string() + ": " + std::strerror(errno));
  back.copy = shadow::energyplus_model_importing_shading(args.scene, back.csv);
  return back;
}

std::string encode_u64s(const std::vector<std::uint64_t>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(std::uint64_t));
}

std::vector<std::uint64_t> decode_u64s(const std::string& bytes) {
  std::vector<std::uint64_t> values(bytes.size() / sizeof(std::uint64_t));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(std::uint64_t));
  return values;
}

/// The summary's last words: what to do with energyplus-shading.csv.
void print_hand_back(const EnergyPlusHandBack& back, const SeriesArgs& args, const std::vector<fs::path>& written) {
  const bool csv = std::any_of(written.begin(), written.end(),
                               [](const fs::path& p) { return p.filename() == "energyplus-shading.csv"; });
  if (!csv) return;
  if (back.objects.empty()) {
    std::printf("  EnergyPlus: no energyplus-objects.idf (%s)\n", back.problem.c_str());
    return;
  }
  if (back.copy) {
    std::printf("  EnergyPlus: %s is the model with ShadowCalculation (Imported) and Schedule:File:Shading reading\n"
                "    %s (%d object(s) of the model replaced); run EnergyPlus on it with the same weather file\n",
                args.write_idf.c_str(), back.csv.c_str(), back.copy->replaced);
    const int version = version_number(back.copy->version);
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

int run_series_in(shadow_cli::World& world, const SeriesArgs& args) {
  using shadow_cli::on_every_rank;
  const auto start = Clock::now();
  const bool root = world.root();
  const bool talk = root && !args.quiet;
  shadow::RunInfo run;
  run.scene = args.scene;
  run.started_utc = shadow::utc_now();
  run.planarity_tolerance = args.planarity_tolerance;

  // Every rank reads the scene and prepares its engine (the scene files must be visible on
  // every node); a bad input on any rank stops all of them before OUTDIR is touched.
  shadow::Scene scene;
  shadow::SunSeries suns;
  std::vector<std::size_t> map_faces;
  std::optional<shadow::ShadowEngine> engine_holder;
  EnergyPlusHandBack hand_back;
  using shadow_cli::Stage;
  on_every_rank(world, [&] {
    shadow_cli::set_stage(Stage::Loading);
    scene = shadow::load_scene(args.scene,
                               shadow_cli::load_options(args.planarity_tolerance, args.orient_outward, args.lod, args.threads,
                                                        args.skip_invalid));
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
    try {
      suns = shadow::sun_series(scene);
      // The exact sun-hours map (docs/sun-hours-map.md) on the scene's `sun_hours_map` meshes
      // and those of --sun-hours-map: a wrong name is found before any computing.
      map_faces = shadow::sun_hours_map_faces(scene);
      if (!args.sun_hours_map.empty()) {
        for (std::size_t f : shadow::sun_hours_map_faces(scene, mesh_names(args.sun_hours_map), "--sun-hours-map"))
          map_faces.push_back(f);
        std::sort(map_faces.begin(), map_faces.end());
        map_faces.erase(std::unique(map_faces.begin(), map_faces.end()), map_faces.end());
      }
      shadow_cli::set_stage(Stage::Preparing);
      engine_holder.emplace(scene, args.threads);
    } catch (const shadow::InputError& e) {
      shadow_cli::rethrow_naming_scene(e, args.scene);
    }
    hand_back = prepare_hand_back(args, scene);
  });
  const shadow::ShadowEngine& engine = *engine_holder;

  shadow::SeriesOptions options;
  options.threads = args.threads;
  options.arithmetic = args.fast ? shadow::Arithmetic::Fast : shadow::Arithmetic::Exact;
  options.tile_casters = args.tile_casters;
  options.fast_tile_casters = args.fast_tile_casters;
  run.options.threads = args.threads;
  run.options.polygons = false;
  run.options.planes = false;
  run.options.arithmetic = options.arithmetic;
  run.options.tile_casters = options.tile_casters;  // report.json names them when not the defaults
  run.options.fast_tile_casters = options.fast_tile_casters;
  const std::size_t instants = suns.lights.size();

  // Every rank must have read the same scene: its digest is rank 0's.
  const std::uint64_t digest = shadow_cli::series_digest(scene, suns, options);
  if (world.distributed()) {
    std::string theirs = encode_u64s({digest});
    world.broadcast(theirs);
    on_every_rank(world, [&] {
      if (decode_u64s(theirs) != std::vector<std::uint64_t>{digest})
        throw shadow::InputError({args.scene, ""}, "this rank read another scene or period than rank 0 (digest " +
                                                       std::to_string(digest) + "): every node must see the same files");
    });
  }

  // Rank 0 owns OUTDIR (its lock, the checkpoint, every file written) and the whole table.
  const bool checkpointing = args.checkpoint || args.resume || args.stop_after > 0;
  std::optional<shadow::OutputDirectory> output;
  std::optional<shadow_cli::Checkpoint> checkpoint;
  shadow::SeriesResult series;
  std::vector<std::uint64_t> todo;  // the instants this run computes, ascending
  std::size_t resumed = 0;
  shadow_cli::set_stage(Stage::Computing);
  on_every_rank(world, [&] {
    if (!root) return;
    output.emplace(args.outdir);  // lock, clear leftovers, remove the old report
    if (!args.quiet)
      for (const shadow::Warning& warning : scene.warnings)
        std::cerr << "shadow: warning: " << warning.to_string() << "\n";
    // The table's rows (the receiving faces) and their areas, as compute_series makes them.
    series = engine.compute_series({}, options);
    series.instants = instants;
    const std::size_t cells = series.faces.size() * instants;
    series.lit_area.assign(cells, 0.0);
    series.lit_fraction.assign(cells, 0.0);
    series.faces_light.assign(cells, 0);
    series.lit_area_error_bound.assign(cells, 0.0);
    std::vector<bool> done(instants, false);
    const fs::path file = shadow_cli::Checkpoint::file(output->path());
    std::error_code ec;
    if (args.resume && fs::exists(file, ec)) {
      shadow_cli::Checkpoint::Contents contents = shadow_cli::Checkpoint::read(file, digest, series.faces.size(), instants);
      for (const shadow_cli::SeriesColumns& c : contents.records) {
        shadow_cli::place_columns(c, series);
        for (std::uint64_t i : c.instants) {
          if (!done[i]) ++resumed;
          done[i] = true;
        }
      }
      if (!contents.started_utc.empty()) run.started_utc = contents.started_utc;  // the run's start
      checkpoint.emplace(shadow_cli::Checkpoint::reopen(file, contents.valid_bytes));
      if (talk)
        std::fprintf(stderr, "shadow: resuming from %s: %zu of %zu instants done%s\n", file.c_str(), resumed, instants,
                     contents.torn ? " (an unfinished last record was dropped)" : "");
    } else if (checkpointing) {
      if (args.resume && talk)
        std::fprintf(stderr, "shadow: no checkpoint in %s: starting from the first instant\n", output->path().c_str());
      checkpoint.emplace(shadow_cli::Checkpoint::create(file, digest, series.faces.size(), instants, run.started_utc));
    }
    for (std::size_t i = 0; i < instants; ++i)
      if (!done[i]) todo.push_back(i);
  });
  if (world.distributed()) {
    std::string bytes = encode_u64s(todo);
    world.broadcast(bytes);
    todo = decode_u64s(bytes);
  }

  // Round robin over the missing instants: rank r takes todo[r], todo[r + size], ... (neighbouring
  // instants cost about the same, so every rank gets a like share of the work).
  std::vector<std::uint64_t> mine;
  for (std::size_t k = static_cast<std::size_t>(world.rank()); k < todo.size(); k += static_cast<std::size_t>(world.size()))
    mine.push_back(todo[k]);
  const std::size_t share = (todo.size() + static_cast<std::size_t>(world.size()) - 1) / static_cast<std::size_t>(world.size());
  // Rounds: after each, rank 0 gathers the columns (and appends them to the checkpoint). One
  // round of everything for a single process that keeps no checkpoint (as before); else a few
  // instants per thread to start with, then rounds of about a minute (sized below).
  const unsigned threads = args.threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : args.threads;
  std::uint64_t chunk = (!checkpointing && !world.distributed()) ? share : std::max<std::uint64_t>(8, 4 * threads);
  chunk = world.max(root ? chunk : 0);  // rank 0's choice
  struct sigaction previous_int {}, previous_term {};
  if (checkpointing) {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    action.sa_flags = SA_RESETHAND;  // a second signal ends the process at once (the checkpoint stays valid)
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_int);
    sigaction(SIGTERM, &action, &previous_term);
  }
  // On a terminal one line rewritten in place; in a log (stderr sent to a file, an MPI job's
  // or a batch job's output) a line now and then (ProgressLine: every 30 s at most).
  const bool terminal = isatty(STDERR_FILENO) != 0;
  const bool log_lines = !terminal;
  shadow_cli::ProgressLine progress(talk, "instants", resumed, log_lines);
  std::size_t done_total = resumed;
  for (std::size_t taken = 0; taken < share;) {
    const std::size_t count = std::min<std::size_t>(chunk, share - taken);
    const auto round_start = Clock::now();
    std::vector<std::uint64_t> part_instants;
    for (std::size_t k = taken; k < taken + count && k < mine.size(); ++k) part_instants.push_back(mine[k]);
    const std::size_t round_total = std::min(todo.size() - done_total + resumed, count * static_cast<std::size_t>(world.size()));
    std::string bytes;
    on_every_rank(world, [&] {
      std::vector<shadow::Light> lights;
      for (std::uint64_t i : part_instants) lights.push_back(suns.lights[i]);
      shadow::SeriesOptions round = options;
      // Rank 0 shows the whole job's progress, its own share standing for every rank's.
      if (progress.enabled())
        round.progress = [&](const shadow::Progress& p) {
          progress.update({done_total + std::min(p.done * static_cast<std::size_t>(world.size()), round_total), instants});
        };
      shadow::SeriesResult part;
      try {
        part = engine.compute_series(lights, round);
      } catch (const shadow::InputError& e) {
        shadow_cli::rethrow_naming_scene(e, args.scene);
      }
      if (root && !world.distributed() && !checkpoint && part_instants.size() == instants) {
        series = std::move(part);  // the whole series in one call: nothing to copy
        return;
      }
      shadow_cli::SeriesColumns columns = shadow_cli::columns_of(part, part_instants);
      part = shadow::SeriesResult{};
      if (!world.distributed()) {
        shadow_cli::place_columns(columns, series);
        if (checkpoint) checkpoint->append(columns);
        return;
      }
      bytes = shadow_cli::encode_columns(columns);
    });
    if (world.distributed()) {
      std::vector<std::string> parts = world.gather(bytes);
      bytes.clear();
      on_every_rank(world, [&] {
        if (!root) return;
        for (const std::string& p : parts) {
          const shadow_cli::SeriesColumns columns = shadow_cli::decode_columns(p);
          shadow_cli::place_columns(columns, series);
          if (checkpoint) checkpoint->append(columns);
        }
      });
    }
    taken += count;
    done_total += round_total;
    progress.update({done_total, instants});
    // Stop here (the checkpoint holds every instant so far) on a signal to any rank, or when
    // --stop-after's count is reached; else rank 0 sizes the next round.
    const bool stop_after = args.stop_after > 0 && done_total >= args.stop_after && taken < share;
    const std::uint64_t signal = world.max(static_cast<std::uint64_t>(g_stop_signal));
    if (checkpointing && (stop_after || (signal != 0 && taken < share))) {
      progress.finish();
      throw shadow_cli::RunStopped(
          5, "shadow: stopped after " + std::to_string(done_total) + " of " + std::to_string(instants) + " instants (" +
                 (signal != 0 ? std::string("signal ") + std::to_string(signal) : std::string("--stop-after")) +
                 "); they are kept in " + shadow_cli::Checkpoint::file(args.outdir).string() +
                 ": run the same command with --resume to compute the rest");
    }
    // Rounds of about a minute: each costs a little (fresh workers in compute_series, a gather,
    // a checkpoint record), and an interruption loses at most the one in progress. Grown from
    // rank 0's measured time per instant, at most eightfold at a time.
    const double seconds = std::chrono::duration<double>(Clock::now() - round_start).count();
    if (chunk < share && count > 0 && args.stop_after == 0) {  // --stop-after: fixed rounds, a fixed stop
      const double per_instant = seconds / static_cast<double>(count);
      const double wanted = per_instant > 0 ? 60.0 / per_instant : 8.0 * static_cast<double>(chunk);
      chunk = std::max<std::uint64_t>(chunk, static_cast<std::uint64_t>(std::min(wanted, 8.0 * static_cast<double>(chunk))));
    }
    chunk = world.max(root ? chunk : 0);
  }
  progress.finish();
  if (checkpointing) {
    sigaction(SIGINT, &previous_int, nullptr);
    sigaction(SIGTERM, &previous_term, nullptr);
  }
  const auto computed = Clock::now();

  shadow::OutputDirectory::SeriesFiles files;
  files.every = args.every_given ? args.every : default_every(suns.lights.size(), suns.times);
  files.energyplus_objects = hand_back.objects;
  if (args.energyplus_shading) files.energyplus_shading = true;
  if (args.fragments) {
    files.fragments = [&](std::size_t i) {
      shadow::ShadowOptions one;
      one.threads = args.threads;
      one.planes = false;
      one.arithmetic = options.arithmetic;
      one.tile_casters = options.tile_casters;  // fragments cut at the same tile borders as compute's
      one.fast_tile_casters = options.fast_tile_casters;
      // The instant's own light in the scene, so that fragments carry its light_id (and irradiance).
      const std::size_t light_id = scene.sun_instants[suns.instants[i]].light_id;
      return engine.compute(scene.lights[light_id], light_id, one);
    };
  }
  // The map, by faces: each face's overlay needs every instant's lit region on that face only,
  // so rank r takes a contiguous block of the ascending face list and rank 0 concatenates the
  // blocks (region ids shifted), which is what one call on every face gives.
  std::optional<shadow::SunHoursMap> map;
  if (!map_faces.empty()) {
    const std::size_t n = map_faces.size(), size = static_cast<std::size_t>(world.size()),
                      r = static_cast<std::size_t>(world.rank());
    const std::vector<std::size_t> block(map_faces.begin() + static_cast<std::ptrdiff_t>(r * n / size),
                                         map_faces.begin() + static_cast<std::ptrdiff_t>((r + 1) * n / size));
    std::string bytes;
    on_every_rank(world, [&] {
      shadow::SunHoursOptions map_options;
      map_options.threads = args.threads;
      shadow_cli::ProgressLine map_progress(talk,
                                            world.distributed() ? "sun-hours map faces (rank 0's block)"
                                                                : "sun-hours map faces",
                                            0, log_lines);
      map_options.progress = [&](const shadow::Progress& p) { map_progress.update(p); };
      shadow::SunHoursMap part = shadow::compute_sun_hours_map(engine, block, shadow::sun_hours_instants(scene), map_options);
      map_progress.finish();
      if (world.distributed())
        bytes = shadow_cli::encode_map(part);
      else
        map = std::move(part);
    });
    if (world.distributed()) {
      std::vector<std::string> parts = world.gather(bytes);
      on_every_rank(world, [&] {
        if (!root) return;
        std::vector<shadow::SunHoursMap> maps;
        for (const std::string& p : parts) maps.push_back(shadow_cli::decode_map(p));
        map = shadow_cli::merge_maps(maps);
      });
    }
  }

  std::vector<fs::path> written;
  shadow_cli::set_stage(Stage::Writing);
  on_every_rank(world, [&] {
    if (!root) return;
    if (map) {
      // Written before write_series puts report.json in place last.
      shadow::write_sun_hours_vtp(output->path() / "sun_hours.vtp", *map, scene);
    } else {
      std::error_code ignored;  // an earlier run's map is not this run's
      fs::remove(output->path() / "sun_hours.vtp", ignored);
    }
    // The model's copy first: report.json, written last by write_series, marks a complete run.
    if (hand_back.copy)
      shadow::write_file_staged(args.write_idf, [&](std::ostream& out) { out << hand_back.copy->text; });
    written = output->write_series(scene, suns, series, files, &run);
    if (map) written.insert(written.end() - 1, output->path() / "sun_hours.vtp");  // report.json stays last
    // The outputs are complete: a checkpoint left now (this run's, or an older one) is stale.
    if (checkpoint) checkpoint->remove();
    std::error_code ignored;
    fs::remove(shadow_cli::Checkpoint::file(output->path()), ignored);
  });
  const auto finished = Clock::now();

  if (talk) {
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
    std::printf("  sun hours of %zu objects (buildings, zones, meshes; area-weighted) in sun_hours_by_object.csv\n",
                shadow::scene_objects(scene).size());
    const std::size_t computed_now = instants - resumed;
    std::printf("  computed in %.3f s (%.1f ms per instant), written in %.3f s\n", seconds(computed - start),
                computed_now == 0 ? 0.0 : 1000.0 * seconds(computed - start) / static_cast<double>(computed_now),
                seconds(finished - computed));
    if (args.skip_invalid || !scene.skipped_faces.empty())
      std::printf("  skipped: %zu invalid faces (--skip-invalid; report.json: skipped_faces)\n",
                  scene.skipped_faces.size());
    if (world.distributed()) std::printf("  on %d MPI ranks\n", world.size());
    if (resumed > 0) std::printf("  resumed: %zu instants came from the checkpoint\n", resumed);
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
    if (!args.every_given && files.every > 1)
      std::printf("  series.pvd shows %zu of the %zu instants above the horizon, one in %zu (by default at most %zu "
                  "on a period over %g days; --every 1 shows them all, --every 0 none)\n",
                  instant_files, suns.lights.size(), files.every, kDefaultInstantFiles, kLongSeriesDays);
    // Say why there is no energyplus-shading.csv: unasked, or the period cannot be one.
    const bool ep_written = std::any_of(written.begin(), written.end(),
                                        [](const fs::path& p) { return p.filename() == "energyplus-shading.csv"; });
    if (!ep_written) {
      const bool wanted = args.energyplus_shading || shadow::energyplus_shading_wanted(scene);
      if (wanted)
        std::printf("  no energyplus-shading.csv: %s\n", shadow::energyplus_schedule(scene).reason.c_str());
      else if (scene.energyplus_shading)
        std::printf("  no energyplus-shading.csv (the scene's \"energyplus_shading\" is false)\n");
      else
        std::printf("  no energyplus-shading.csv (not an EnergyPlus model; --energyplus-shading writes one)\n");
    }
    if (map)
      std::printf("  sun-hours map: %zu cells on %zu faces (sun_hours.vtp)\n", map->cells.size(), map->faces.size());
    print_hand_back(hand_back, args, written);
  }
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
