// SPDX-License-Identifier: GPL-3.0-or-later
// SeriesJob: `shadow series` as a library unit (shadow/series_job.hpp, docs/series.md,
// docs/cluster.md). Every rank reads the scene and prepares its engine; rank 0 owns the output
// directory, the checkpoint and the whole table; the instants still missing are dealt round
// robin to the ranks and computed in rounds, after each of which rank 0 gathers the columns.
#include "jobs/series_checkpoint.hpp"

#include <shadow/energyplus.hpp>
#include <shadow/error.hpp>
#include <shadow/series_job.hpp>
#include <shadow/sun.hpp>
#include <shadow/version.hpp>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <memory>
#include <new>
#include <system_error>
#include <thread>

namespace shadow {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

static_assert(std::atomic<int>::is_always_lock_free, "the stop flag is set from a signal handler");

/// Runs `part` on this rank; on a distributed world every rank then agrees on the outcome, so
/// that an error on any rank stops them all. On a world of one, exceptions pass unchanged.
template <typename Part>
void on_every_rank(SeriesWorld& world, Part&& part) {
  if (!world.distributed()) {
    part();
    return;
  }
  std::exception_ptr error;
  try {
    part();
  } catch (...) {
    error = std::current_exception();
  }
  world.agree(error);
}

/// An InputError without a file names the scene file.
[[noreturn]] void rethrow_naming_scene(const InputError& e, const fs::path& scene) {
  if (!e.where().file.empty()) throw;
  throw InputError({scene.string(), e.where().place}, e.problem());
}

std::string encode_u64s(const std::vector<std::uint64_t>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(std::uint64_t));
}

std::vector<std::uint64_t> decode_u64s(const std::string& bytes) {
  std::vector<std::uint64_t> values(bytes.size() / sizeof(std::uint64_t));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(std::uint64_t));
  return values;
}

/// A round's instants written to the files on a thread of their own (one process), so that the
/// next round computes meanwhile: writing (sunlit.csv's numbers, the series' compressed
/// datasets) was a tenth of a fast year's wall time with every worker idle. One round at a time
/// and in round order (each waits for the one before), so the stream gets the instants in the
/// same order as when they were written in line.
class RoundWriter {
 public:
  RoundWriter() = default;
  RoundWriter(const RoundWriter&) = delete;
  RoundWriter& operator=(const RoundWriter&) = delete;
  ~RoundWriter() { wait_quietly(); }

  /// Runs `write` once the round before has been written (rethrowing that one's error), on a new
  /// thread, or on this one when no thread can be started. The thread starts with every signal
  /// blocked, as the pool's do: a Ctrl-C stays the main thread's.
  void start(std::function<void()> write) {
    wait();
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    bool started = false;
    try {
      thread_ = std::thread([this, write] {
        try {
          write();
        } catch (...) {
          error_ = std::current_exception();
          failed_.store(true);
        }
      });
      started = true;
    } catch (const std::system_error&) {
    } catch (const std::bad_alloc&) {
    }
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    if (!started) write();
  }
  /// Whether the round being written has failed already (its error then comes from wait()): the
  /// job need not compute another round first.
  [[nodiscard]] bool failed() const { return failed_.load(); }
  /// Waits for the round being written and rethrows what it threw.
  void wait() {
    if (thread_.joinable()) thread_.join();
    failed_.store(false);
    if (error_) {
      const std::exception_ptr e = error_;
      error_ = nullptr;
      std::rethrow_exception(e);
    }
  }
  /// The same, dropping its error (the job is failing already).
  void wait_quietly() noexcept {
    if (thread_.joinable()) thread_.join();
    failed_.store(false);
    error_ = nullptr;
  }

 private:
  std::thread thread_;
  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
};

/// Hands `columns` on: to the files (each instant once, in any order: the stream orders them),
/// to the whole table when it is kept, and their counters to the table's stats.
void take_columns(const jobs::SeriesColumns& columns, SeriesFileStream& stream, SeriesResult& table, bool keep_table,
                  std::vector<bool>& seen) {
  const std::size_t rows = columns.rows;
  for (std::size_t k = 0; k < columns.instants.size(); ++k) {
    const std::uint64_t i = columns.instants[k];
    if (i >= seen.size() || seen[i]) continue;  // a checkpoint may hold an instant twice: the same bits
    seen[i] = true;
    const std::size_t at = k * rows;
    stream.add(i, SeriesColumn{columns.lit_area.data() + at, columns.lit_fraction.data() + at,
                               columns.faces_light.data() + at, columns.lit_area_error_bound.data() + at, 1});
  }
  stream.add_stats(columns.stats);
  if (keep_table)
    jobs::place_columns(columns, table);  // adds the stats too
  else
    table.stats += columns.stats;
}

/// The rows of the series' faces that the sun-hours map's pass computed (State::map_rows: row in
/// `part`, row in `table`), written into `part`, the columns of `instants`, from `table`.
void fill_given_rows(SeriesResult& part, const std::vector<std::uint64_t>& instants, const SeriesResult& table,
                     const std::vector<std::pair<std::size_t, std::size_t>>& rows) {
  for (std::size_t k = 0; k < instants.size(); ++k)
    for (const auto& [r, m] : rows) {
      const std::size_t at = part.at(r, k), from = table.at(m, instants[k]);
      part.lit_area[at] = table.lit_area[from];
      part.lit_fraction[at] = table.lit_fraction[from];
      part.faces_light[at] = table.faces_light[from];
      part.lit_area_error_bound[at] = table.lit_area_error_bound[from];
    }
}

/// Another period at the scene's site (an IDF's RunPeriod, or the scene's `sun` block, replaced).
void replace_period(Scene& scene, const SeriesJobOptions& options) {
  const std::string file = options.scene.string();
  if (!scene.sun)
    throw InputError({file, "sun"}, "--from/--to/--step need a sun: the scene has no `sun` block "
                                    "(and the model no Site:Location)");
  SunPeriod period = *scene.sun;
  if (!period.times.empty() && (options.from.empty() || options.to.empty()))
    throw InputError({file, "sun.times"},
                     "the sun is given by explicit times: give both --from and --to to replace them by a period");
  period.times.clear();
  if (!options.from.empty()) period.start = options.from;
  if (!options.to.empty()) period.end = options.to;
  if (options.step_minutes > 0) period.step_minutes = options.step_minutes;
  try {
    replace_sun_lights(scene, period, options.threads);
  } catch (const InputError& e) {
    // The period's keys came from the options: name them as the command line does.
    const std::string& place = e.where().place;
    std::string flag = place == "sun.start" ? "--from" : place == "sun.end" ? "--to"
                     : place == "sun.step_minutes" ? "--step" : place;
    std::string problem = e.problem();
    // Only --from given, after the scene's own end: the option given is the one to name.
    if (flag == "--to" && options.to.empty() && !options.from.empty()) {
      flag = "--from";
      problem = "--from " + options.from + " is after the period's end " + period.end +
                " (the scene's or the model's): give --to too";
    }
    throw InputError({flag == place ? e.where().file : std::string(), flag}, problem);
  }
}

/// The objects handed back to EnergyPlus; with write_idf the model's copy, checked before any
/// computing (a copy that cannot be made must not cost a year of suns).
SeriesEnergyPlusHandBack prepare_hand_back(const SeriesJobOptions& options, const Scene& scene, int model_year,
                                           int model_step) {
  SeriesEnergyPlusHandBack back;
  back.csv = (fs::absolute(options.output) / "energyplus-shading.csv").lexically_normal().string();
  back.model = is_energyplus_model(options.scene);
  const std::string idf = options.write_idf.string();
  try {
    back.objects = energyplus_import_objects(back.csv);
  } catch (const InputError& e) {
    back.problem = e.problem();
    if (!idf.empty()) throw InputError({"", "--write-idf"}, "the CSV's path " + back.csv + ": " + e.problem());
  }
  const EnergyPlusSchedule schedule = energyplus_schedule(scene);
  if (schedule.written && !schedule.reason.empty()) back.note = "energyplus-shading.csv: " + schedule.reason;
  // --step against the model's Timestep: EnergyPlus refuses a file of another number of rows.
  if (schedule.written && model_step > 0 && 60 / model_step != schedule.timesteps_per_hour)
    back.note += std::string(back.note.empty() ? "" : "; ") + "the model's Timestep is " +
                 std::to_string(60 / model_step) + " per hour, the CSV's " +
                 std::to_string(schedule.timesteps_per_hour) +
                 " (--step): EnergyPlus reads the CSV only with the same Timestep (set it in the model, or run "
                 "without --step)";
  if (idf.empty()) return back;
  if (!schedule.written)
    throw InputError({"", "--write-idf"}, "energyplus-shading.csv cannot be written for this run: " + schedule.reason);
  // --from/--to in a year of another length: the copy still runs the model's RunPeriod, against
  // rows made for this one (a leap year's 366 days against 365, or the other way round).
  const auto leap = [](int y) { return is_valid_date(y, 2, 29); };
  if (model_year > 0 && leap(model_year) != leap(schedule.year))
    back.note += std::string(back.note.empty() ? "" : "; ") + "the copy keeps the model's RunPeriod, a year of " +
                 (leap(model_year) ? "366" : "365") + " days (" + std::to_string(model_year) +
                 (model_year == 2023 ? ", or the model names none" : "") + "), but the CSV's " +
                 std::to_string(schedule.rows) + " time steps are " + std::to_string(schedule.year) + "'s (" +
                 (leap(schedule.year) ? "366" : "365") + " days): EnergyPlus will not match them";
  std::error_code ec;
  if (fs::equivalent(options.scene, options.write_idf, ec))
    throw InputError({"", "--write-idf"}, idf + " is the model itself: name another file");
  const fs::path parent = fs::absolute(options.write_idf).parent_path();
  if (!fs::is_directory(parent, ec))
    throw InputError({"", "--write-idf"}, "no directory " + parent.string() + " to write " + idf + " in");
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    throw InputError({"", "--write-idf"}, "cannot write in " + parent.string() + ": " + std::strerror(errno));
  back.copy = energyplus_model_importing_shading(options.scene, back.csv);
  return back;
}

}  // namespace

SeriesJobStopped::SeriesJobStopped(std::size_t done_in, std::size_t total_in, int signal_in,
                                   std::filesystem::path checkpoint_in)
    : std::runtime_error("series job stopped after " + std::to_string(done_in) + " of " + std::to_string(total_in) +
                         " instants"),
      done(done_in), total(total_in), signal(signal_in), checkpoint(std::move(checkpoint_in)) {}

std::size_t default_series_every(std::size_t instants, const std::vector<std::int64_t>& times) {
  if (instants == 0 || times.size() < 2) return 1;
  const double days = static_cast<double>(times.back() - times.front()) / 86400.0;
  if (!(days > kSeriesLongPeriodDays)) return 1;
  return std::max<std::size_t>(1, (instants + kSeriesDefaultInstantFiles - 1) / kSeriesDefaultInstantFiles);
}

struct SeriesJob::State {
  Clock::time_point start = Clock::now();
  RunInfo run;
  Scene scene;
  SunSeries suns;
  std::vector<std::size_t> map_faces;
  std::optional<ShadowEngine> engine;
  SeriesEnergyPlusHandBack hand_back;
  SeriesOptions series_options;
  std::size_t instants = 0;
  std::uint64_t digest = 0;
  bool checkpointing = false;
  // Rank 0 only: the directory, the checkpoint, the files as they are written, and the table's
  // rows (the whole table with keep_table).
  std::optional<OutputDirectory> output;
  std::optional<jobs::Checkpoint> checkpoint;
  std::optional<SeriesFileStream> stream;
  std::vector<bool> streamed;  ///< per instant: handed to the stream
  SeriesResult series;
  SurfaceSeries surfaces;
  std::vector<std::uint64_t> todo;  ///< the instants this run computes, ascending (every rank)
  std::size_t resumed = 0;
  std::optional<SunHoursMap> map;
  /// With the map sharing its pass (run_steps): its receiving faces' series table, and per
  /// series row of a map face (row, row in map_table).
  std::optional<SeriesResult> map_table;
  std::vector<std::pair<std::size_t, std::size_t>> map_rows;
  std::vector<fs::path> written;
  std::size_t every = 1;
  Clock::time_point computed, finished;
  double map_seconds = 0;
  bool map_first = false;  ///< the map ran before the instants, sharing its pass
  /// Writes a round into `stream` while the next computes. Declared after `stream`, so that it is
  /// destroyed (and its thread joined) first.
  RoundWriter writer;
};

SeriesJob::SeriesJob(SeriesJobOptions options, SeriesWorld& world)
    : options_(std::move(options)), world_(world), state_(std::make_unique<State>()) {}

SeriesJob::~SeriesJob() = default;

SeriesJobResult SeriesJob::run() {
  State& s = *state_;
  s.start = Clock::now();
  s.run.scene = options_.scene.string();
  s.run.started_utc = utc_now();
  s.run.planarity_tolerance = options_.load.planarity_tolerance;
  s.checkpointing = options_.checkpoint || options_.resume || options_.stop_after > 0;
  try {
    run_steps();
  } catch (...) {
    s.writer.wait_quietly();  // a round still being written into the stream
    s.stream.reset();  // its temporaries go now: nothing half-written stays behind
    throw;
  }

  SeriesJobResult result;
  result.ranks = world_.size();
  if (!world_.root()) return result;
  s.engine.reset();  // it points into the scene, which moves out
  result.scene = std::move(s.scene);
  result.suns = std::move(s.suns);
  result.series = std::move(s.series);
  result.surfaces = std::move(s.surfaces);
  result.map = std::move(s.map);
  result.written = std::move(s.written);
  result.every = s.every;
  result.resumed = s.resumed;
  // The map's time is its own: before the instants when it shared its pass, else after them.
  result.map_seconds = s.map_seconds;
  result.compute_seconds =
      std::chrono::duration<double>(s.computed - s.start).count() - (s.map_first ? s.map_seconds : 0);
  result.write_seconds =
      std::chrono::duration<double>(s.finished - s.computed).count() - (s.map_first ? 0 : s.map_seconds);
  result.energyplus = std::move(s.hand_back);
  return result;
}

void SeriesJob::run_steps() {
  State& s = *state_;
  on_every_rank(world_, [&] { load(); });
  check_same_scene();
  if (options_.stage) options_.stage(SeriesJobStage::Computing);
  on_every_rank(world_, [&] {
    if (!world_.root()) return;
    open_output();
    resume_or_start();
  });
  share_instants();
  // The map's exact pass computes its faces' lit areas too: in an exact series on one process
  // without a checkpoint it runs first and the instants' rounds leave those faces to it
  // (share_map_pass). Its table of those rows is held through the rounds: at most round_cells
  // entries, as one round's, so that the series' memory stays bounded (docs/series.md). A
  // checkpointed run keeps the map after the instants: its records then hold every row's values
  // and counters whatever later resumes them (one process or ranks), a stop loses no map work,
  // and a resume does not compute the map before it can go on; ranks compute the map by blocks
  // of faces, after the instants.
  std::size_t shared_rows = 0;
  for (std::size_t f : s.map_faces) shared_rows += s.scene.is_receiver(f) ? 1 : 0;
  const bool share = options_.share_map_pass && shared_rows > 0 && options_.arithmetic == Arithmetic::Exact &&
                     !world_.distributed() && !s.checkpointing && shared_rows * s.instants <= options_.round_cells;
  const auto map = [&] {
    const auto start = Clock::now();
    compute_map();
    s.map_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  };
  s.map_first = share;
  if (share) {
    s.map_table.emplace();
    map();
    if (options_.stage) options_.stage(SeriesJobStage::Computing);  // the instants' rounds
  }
  compute_instants();
  s.map_table.reset();
  s.computed = Clock::now();
  if (!share) map();
  write_outputs();
  s.finished = Clock::now();
}

void SeriesJob::load() {
  // Every rank reads the scene (the files must be visible on every node) and prepares its engine.
  State& s = *state_;
  if (options_.stage) options_.stage(SeriesJobStage::Loading);
  s.scene = load_scene(options_.scene, options_.load);
  // A model read whole that implies no sun (a CityJSON file; an IDF without Site:Location):
  // say how to give it one, as `shadow compute` says how to give it lights.
  if (!s.scene.sun && !s.scene.meshes.empty() && !s.scene.meshes.front().model.empty() &&
      s.scene.meshes.front().file == options_.scene.string())
    throw InputError({options_.scene.string(), ""},
                     "the model carries no sun (a series needs its period or times): write a scene JSON that names "
                     "this file as a mesh \"file\" and add a \"sun\" block (docs/series.md, docs/scene-format.md)");
  // The model's own year (an EnergyPlus model's RunPeriod), before --from/--to replace it.
  int model_year = 0;
  if (s.scene.sun && s.scene.sun->start.size() >= 4 && s.scene.sun->times.empty())
    model_year = std::atoi(s.scene.sun->start.substr(0, 4).c_str());
  const int model_step = s.scene.sun && s.scene.sun->times.empty() ? s.scene.sun->step_minutes : 0;
  if (!options_.from.empty() || !options_.to.empty() || options_.step_minutes > 0) replace_period(s.scene, options_);
  if (options_.energyplus_shading == true) {
    // energyplus-shading.csv asked for: each step's sun where EnergyPlus takes it
    // (SunPeriod::energyplus_times), whatever the scene's sun block says.
    if (s.scene.sun && s.scene.sun->times.empty() && !s.scene.sun->energyplus_times) {
      SunPeriod period = *s.scene.sun;
      period.energyplus_times = true;
      replace_sun_lights(s.scene, period, options_.threads);
    }
    // Impossible (a step that does not divide an hour, explicit times, names EnergyPlus would
    // confuse): refused before the engine is built and any sun computed, not a run that
    // silently lacks the file.
    const EnergyPlusSchedule schedule = energyplus_schedule(s.scene);
    if (!schedule.written)
      throw InputError({"", "--energyplus-shading"},
                       "energyplus-shading.csv cannot be written for this run: " + schedule.reason +
                           (s.scene.sun && !s.scene.sun->times.empty() ? " (--from and --to give a period instead)" : ""));
  }
  try {
    s.suns = sun_series(s.scene);
    // The exact sun-hours map (docs/sun-hours-map.md) on the scene's `sun_hours_map` meshes and
    // the options': a wrong name is found before any computing.
    s.map_faces = sun_hours_map_faces(s.scene);
    if (!options_.sun_hours_map.empty()) {
      for (std::size_t f : sun_hours_map_faces(s.scene, options_.sun_hours_map, "--sun-hours-map"))
        s.map_faces.push_back(f);
      std::sort(s.map_faces.begin(), s.map_faces.end());
      s.map_faces.erase(std::unique(s.map_faces.begin(), s.map_faces.end()), s.map_faces.end());
    }
    if (options_.sun_hours_levels_only && options_.sun_hours_levels.empty())
      throw InputError({"", "--sun-hours-levels-only"}, "needs levels: --sun-hours-levels H[,H]");
    if (options_.sun_hours_held_segments && !options_.sun_hours_levels_only)
      throw InputError({"", "--sun-hours-held-segments"},
                       "applies to the threshold map alone: --sun-hours-levels H[,H] --sun-hours-levels-only");
    if (!options_.sun_hours_levels.empty() && s.map_faces.empty())
      throw InputError({"", "--sun-hours-levels"},
                       "needs a sun-hours map: --sun-hours-map MESH or the scene's \"sun_hours_map\"");
    if (options_.stage) options_.stage(SeriesJobStage::Preparing);
    s.engine.emplace(s.scene, options_.threads);
  } catch (const InputError& e) {
    rethrow_naming_scene(e, options_.scene);
  }
  const bool model = is_energyplus_model(options_.scene);
  s.hand_back = prepare_hand_back(options_, s.scene, model ? model_year : 0, model ? model_step : 0);

  s.series_options.threads = options_.threads;
  s.series_options.arithmetic = options_.arithmetic;
  s.series_options.tile_casters = options_.tile_casters;
  s.series_options.fast_tile_casters = options_.fast_tile_casters;
  s.run.options.threads = options_.threads;
  s.run.options.polygons = false;
  s.run.options.planes = false;
  s.run.options.arithmetic = options_.arithmetic;
  s.run.options.tile_casters = options_.tile_casters;  // report.json names them when not the defaults
  s.run.options.fast_tile_casters = options_.fast_tile_casters;
  s.instants = s.suns.lights.size();
  s.digest = jobs::series_digest(s.scene, s.suns, s.series_options);
}

void SeriesJob::check_same_scene() {
  // Every rank must have read the same scene: its digest is rank 0's.
  if (!world_.distributed()) return;
  const std::uint64_t digest = state_->digest;
  std::string theirs = encode_u64s({digest});
  world_.broadcast(theirs);
  on_every_rank(world_, [&] {
    if (decode_u64s(theirs) != std::vector<std::uint64_t>{digest})
      throw InputError({options_.scene.string(), ""}, "this rank read another scene or period than rank 0 (digest " +
                                                          std::to_string(digest) +
                                                          "): every node must see the same files");
  });
}

void SeriesJob::open_output() {
  State& s = *state_;
  s.output.emplace(options_.output);  // lock, clear leftovers, remove the old report
  if (options_.notice)
    for (const Warning& warning : s.scene.warnings) options_.notice("warning: " + warning.to_string());
  // The table's rows (the receiving faces) and their areas, as compute_series makes them.
  s.series = s.engine->compute_series({}, s.series_options);
  s.series.instants = s.instants;
  if (options_.keep_table) s.series.zero_entries();
  // The files are written as the instants complete, in order; until the end they are temporaries.
  s.stream.emplace(s.output->stream_series(s.scene, s.suns, s.series, series_files()));
  s.streamed.assign(s.instants, false);
}

OutputDirectory::SeriesFiles SeriesJob::series_files() {
  State& s = *state_;
  OutputDirectory::SeriesFiles files;
  s.every = options_.every ? *options_.every : default_series_every(s.suns.lights.size(), s.suns.times);
  files.every = s.every;
  files.energyplus_objects = s.hand_back.objects;
  files.energyplus_shading = options_.energyplus_shading;
  if (options_.fragments) {
    files.fragments = [this](std::size_t i) {
      const State& st = *state_;
      ShadowOptions one;
      one.threads = options_.threads;
      one.planes = false;
      one.arithmetic = options_.arithmetic;
      one.tile_casters = options_.tile_casters;  // fragments cut at the same tile borders as compute's
      one.fast_tile_casters = options_.fast_tile_casters;
      // The instant's own light in the scene, so that fragments carry its light_id (and irradiance).
      const std::size_t light_id = st.scene.sun_instants[st.suns.instants[i]].light_id;
      return st.engine->compute(st.scene.lights[light_id], light_id, one);
    };
  }
  return files;
}

void SeriesJob::resume_or_start() {
  State& s = *state_;
  std::vector<bool> done(s.instants, false);
  const fs::path file = jobs::Checkpoint::file(s.output->path());
  std::error_code ec;
  if (options_.resume && fs::exists(file, ec)) {
    // Record by record into the files (the checkpoint is not held whole in memory).
    const jobs::Checkpoint::Contents contents =
        jobs::Checkpoint::read(file, s.digest, s.series.faces.size(), s.instants, [&](const jobs::SeriesColumns& c) {
          take_columns(c, *s.stream, s.series, options_.keep_table, s.streamed);
          for (std::uint64_t i : c.instants) {
            if (!done[i]) ++s.resumed;
            done[i] = true;
          }
        });
    if (!contents.started_utc.empty()) s.run.started_utc = contents.started_utc;  // the run's start
    s.checkpoint.emplace(jobs::Checkpoint::reopen(file, contents.valid_bytes));
    if (options_.notice)
      options_.notice("resuming from " + file.string() + ": " + std::to_string(s.resumed) + " of " +
                      std::to_string(s.instants) + " instants done" +
                      (contents.torn ? " (an unfinished last record was dropped)" : ""));
  } else if (s.checkpointing) {
    if (options_.resume && options_.notice)
      options_.notice("no checkpoint in " + s.output->path().string() + ": starting from the first instant");
    s.checkpoint.emplace(jobs::Checkpoint::create(file, s.digest, s.series.faces.size(), s.instants, s.run.started_utc));
  }
  for (std::size_t i = 0; i < s.instants; ++i)
    if (!done[i]) s.todo.push_back(i);
}

void SeriesJob::share_instants() {
  if (!world_.distributed()) return;
  std::string bytes = encode_u64s(state_->todo);
  world_.broadcast(bytes);
  state_->todo = decode_u64s(bytes);
}

void SeriesJob::compute_instants() {
  State& s = *state_;
  const auto size = static_cast<std::size_t>(world_.size());
  const bool root = world_.root();
  // Round robin over the missing instants: rank r takes todo[r], todo[r + size], ... (neighbouring
  // instants cost about the same, so every rank gets a like share of the work).
  std::vector<std::uint64_t> mine;
  for (std::size_t k = static_cast<std::size_t>(world_.rank()); k < s.todo.size(); k += size) mine.push_back(s.todo[k]);
  const std::size_t share = (s.todo.size() + size - 1) / size;
  // Rounds: after each, rank 0 gathers the columns (and appends them to the checkpoint). One
  // round of everything for a single process that keeps no checkpoint; else a few instants per
  // thread to start with, then rounds of about a minute (sized below).
  const unsigned threads = options_.threads == 0 ? std::max(1u, std::thread::hardware_concurrency()) : options_.threads;
  std::uint64_t chunk = (!s.checkpointing && !world_.distributed()) ? share : std::max<std::uint64_t>(8, 4 * threads);
  // Whatever the length of the series, a round holds at most round_cells of the table (on rank 0
  // every rank's columns at once): its instants go to the files and are dropped, so the memory
  // of a series does not grow with its length (docs/series.md, "Streaming").
  const std::uint64_t rows = root ? std::max<std::size_t>(1, s.series.faces.size()) : 1;
  // One process writes a round while the next computes (writes_behind): two rounds' tables are
  // then held at once, so each holds half as many cells.
  const std::uint64_t halves = writes_behind() ? 2 : 1;
  const std::uint64_t cap = std::max<std::uint64_t>(1, options_.round_cells / (rows * size) / halves);
  chunk = std::min(chunk, cap);
  chunk = world_.max(root ? chunk : 0);  // rank 0's choice
  const bool report = root && options_.progress;
  if (report) options_.progress({SeriesJobProgress::Part::Instants, s.resumed, s.instants, s.resumed, false});
  std::size_t done_total = s.resumed;
  for (std::size_t taken = 0; taken < share;) {
    const std::size_t count = std::min<std::size_t>(chunk, share - taken);
    if (s.writer.failed()) s.writer.wait();  // the round written behind failed: its error now
    const auto round_start = Clock::now();
    std::vector<std::uint64_t> part_instants;
    for (std::size_t k = taken; k < taken + count && k < mine.size(); ++k) part_instants.push_back(mine[k]);
    const std::size_t round_total = std::min(s.todo.size() - done_total + s.resumed, count * size);
    std::string bytes;
    on_every_rank(world_, [&] { bytes = compute_round(part_instants, done_total, round_total); });
    if (world_.distributed()) place_round(bytes);
    taken += count;
    done_total += round_total;
    if (report) options_.progress({SeriesJobProgress::Part::Instants, done_total, s.instants, s.resumed, false});
    stop_if_asked(done_total, taken < share);
    // Rounds of about a minute: each costs a little (fresh workers in compute_series, a gather,
    // a checkpoint record), and an interruption loses at most the one in progress. Grown from
    // rank 0's measured time per instant, at most eightfold at a time.
    const double seconds = std::chrono::duration<double>(Clock::now() - round_start).count();
    if (chunk < share && count > 0 && options_.stop_after == 0) {  // stop_after: fixed rounds, a fixed stop
      const double per_instant = seconds / static_cast<double>(count);
      const double wanted = per_instant > 0 ? 60.0 / per_instant : 8.0 * static_cast<double>(chunk);
      chunk = std::max<std::uint64_t>(chunk, static_cast<std::uint64_t>(std::min(wanted, 8.0 * static_cast<double>(chunk))));
      chunk = std::min(chunk, cap);
    }
    chunk = world_.max(root ? chunk : 0);
  }
  s.writer.wait();  // the last round's files
  if (report) options_.progress({SeriesJobProgress::Part::Instants, done_total, s.instants, s.resumed, true});
}

bool SeriesJob::writes_behind() const {
  // Not with per-instant fragments: the stream would then run the engine on the writer's thread
  // while the round's workers run.
  return !world_.distributed() && !options_.fragments;
}

std::string SeriesJob::compute_round(const std::vector<std::uint64_t>& instants, std::size_t done_before,
                                     std::size_t round_total) {
  State& s = *state_;
  const auto size = static_cast<std::size_t>(world_.size());
  std::vector<Light> lights;
  for (std::uint64_t i : instants) lights.push_back(s.suns.lights[i]);
  SeriesOptions round = s.series_options;
  // Rank 0 shows the whole job's progress, its own share standing for every rank's.
  if (world_.root() && options_.progress)
    round.progress = [&](const Progress& p) {
      options_.progress({SeriesJobProgress::Part::Instants, done_before + std::min(p.done * size, round_total),
                         s.instants, s.resumed, false});
    };
  SeriesResult part;
  try {
    part = s.engine->compute_series(lights, round);
  } catch (const InputError& e) {
    rethrow_naming_scene(e, options_.scene);
  }
  if (s.map_table) fill_given_rows(part, instants, *s.map_table, s.map_rows);
  if (world_.distributed()) return jobs::encode_columns(jobs::columns_of(part, instants));
  // One process: the round into the files, written behind while the next round computes
  // (writes_behind) or here, after the checkpoint has it, so that a failure while writing loses
  // nothing computed.
  if (s.checkpoint) s.checkpoint->append(jobs::columns_of(part, instants));
  if (options_.keep_table)
    jobs::place_columns(jobs::columns_of(part, instants), s.series);  // adds the stats too
  else
    s.series.stats += part.stats;
  for (std::uint64_t i : instants) s.streamed[i] = true;
  auto written = std::make_shared<const SeriesResult>(std::move(part));
  auto write = [&s, written, instants] {
    for (std::size_t k = 0; k < instants.size(); ++k) s.stream->add(instants[k], SeriesColumn::of(*written, k));
    s.stream->add_stats(written->stats);
  };
  if (writes_behind())
    s.writer.start(write);
  else
    write();
  return {};
}

void SeriesJob::place_round(const std::string& bytes) {
  State& s = *state_;
  std::vector<std::string> parts = world_.gather(bytes);
  on_every_rank(world_, [&] {
    if (!world_.root()) return;
    for (const std::string& p : parts) {
      const jobs::SeriesColumns columns = jobs::decode_columns(p);
      if (s.checkpoint) s.checkpoint->append(columns);
      take_columns(columns, *s.stream, s.series, options_.keep_table, s.streamed);
    }
  });
}

void SeriesJob::stop_if_asked(std::size_t done, bool more) {
  // Stop here (the checkpoint holds every instant so far) on a stop request to any rank, or when
  // stop_after's count is reached.
  const State& s = *state_;
  const bool stop_after = options_.stop_after > 0 && done >= options_.stop_after && more;
  const int mine = options_.stop != nullptr ? options_.stop->load() : 0;
  const std::uint64_t signal = world_.max(static_cast<std::uint64_t>(std::max(mine, 0)));
  if (!s.checkpointing || !(stop_after || (signal != 0 && more))) return;
  if (world_.root() && options_.progress)
    options_.progress({SeriesJobProgress::Part::Instants, done, s.instants, s.resumed, true});
  throw SeriesJobStopped(done, s.instants, static_cast<int>(signal), jobs::Checkpoint::file(options_.output));
}

void SeriesJob::compute_map() {
  // The map, by faces: each face's overlay needs every instant's lit region on that face only,
  // so rank r takes a contiguous block of the ascending face list and rank 0 concatenates the
  // blocks (region ids shifted), which is what one call on every face gives.
  State& s = *state_;
  if (options_.stage) options_.stage(SeriesJobStage::Mapping);
  if (s.map_faces.empty()) return;
  const std::vector<SunHoursInstant> instants = sun_hours_instants(s.suns);  // the series' columns
  const std::size_t n = s.map_faces.size(), size = static_cast<std::size_t>(world_.size()),
                    r = static_cast<std::size_t>(world_.rank());
  const std::vector<std::size_t> block(s.map_faces.begin() + static_cast<std::ptrdiff_t>(r * n / size),
                                       s.map_faces.begin() + static_cast<std::ptrdiff_t>((r + 1) * n / size));
  if (options_.sun_hours_levels_only) {
    // The threshold map alone, on rank 0 (it is not gathered from blocks as the full map is).
    on_every_rank(world_, [&] {
      if (!world_.root()) return;
      SunHoursOptions map_options;
      map_options.threads = options_.threads;
      map_options.levels = options_.sun_hours_levels;
      map_options.full = false;
      if (options_.sun_hours_held_segments) map_options.level_held_segments = *options_.sun_hours_held_segments;
      if (options_.progress)
        map_options.progress = [&](const Progress& p) {
          options_.progress({SeriesJobProgress::Part::MapFaces, p.done, p.total, 0, false});
        };
      map_options.series_table = s.map_table ? &*s.map_table : nullptr;
      s.map = compute_sun_hours_map(*s.engine, s.map_faces, instants, map_options);
    });
    take_map_rows();
    return;
  }
  std::string bytes;
  on_every_rank(world_, [&] {
    SunHoursOptions map_options;
    map_options.threads = options_.threads;
    if (!world_.distributed()) map_options.levels = options_.sun_hours_levels;  // else rank 0 adds them below
    const bool report = world_.root() && options_.progress;
    if (report) {
      options_.progress({SeriesJobProgress::Part::MapFaces, 0, block.size(), 0, false});
      map_options.progress = [&](const Progress& p) {
        options_.progress({SeriesJobProgress::Part::MapFaces, p.done, p.total, 0, false});
      };
    }
    map_options.series_table = s.map_table ? &*s.map_table : nullptr;  // (one process only)
    SunHoursMap part = compute_sun_hours_map(*s.engine, block, instants, map_options);
    if (report) options_.progress({SeriesJobProgress::Part::MapFaces, block.size(), block.size(), 0, true});
    if (world_.distributed())
      bytes = jobs::encode_map(part);
    else
      s.map = std::move(part);
  });
  if (!world_.distributed()) {
    take_map_rows();
    return;
  }
  std::vector<std::string> parts = world_.gather(bytes);
  on_every_rank(world_, [&] {
    if (!world_.root()) return;
    std::vector<SunHoursMap> maps;
    for (const std::string& p : parts) maps.push_back(jobs::decode_map(p));
    s.map = jobs::merge_maps(maps);
    if (!options_.sun_hours_levels.empty())
      add_sun_hours_levels(*s.map, *s.engine, s.map_faces, instants, options_.sun_hours_levels,
                           options_.threads);
  });
}

void SeriesJob::take_map_rows() {
  // The map's pass computed its faces' rows: the rounds skip them and copy them from its table.
  State& s = *state_;
  if (!s.map_table) return;
  const SeriesResult& table = *s.map_table;
  s.map_rows.clear();
  for (std::size_t r = 0, m = 0; r < s.series.faces.size(); ++r) {
    while (m < table.faces.size() && table.faces[m] < s.series.faces[r]) ++m;
    if (m < table.faces.size() && table.faces[m] == s.series.faces[r]) s.map_rows.emplace_back(r, m);
  }
  for (const auto& [r, m] : s.map_rows) s.series_options.given_faces.push_back(s.series.faces[r]);
  s.series.stats += table.stats;  // the pass's counters for those rows, once
  s.stream->add_stats(table.stats);
}

void SeriesJob::write_outputs() {
  State& s = *state_;
  if (options_.stage) options_.stage(SeriesJobStage::Writing);
  on_every_rank(world_, [&] {
    if (!world_.root()) return;
    const fs::path& dir = s.output->path();
    std::error_code ignored;
    if (s.map && !s.map->full) fs::remove(dir / "sun_hours.vtp", ignored);  // the threshold map alone
    if (s.map) {
      if (s.map->full) write_sun_hours_vtp(dir / "sun_hours.vtp", *s.map, s.scene);  // before report.json, written last
      if (!s.map->levels.empty()) write_sun_hours_levels_vtp(dir / "sun_hours_levels.vtp", *s.map, s.scene);
      s.run.sun_hours_map = &*s.map;  // report.json's sun_hours_map (the levels' exact areas)
    } else {  // an earlier run's map is not this run's
      fs::remove(dir / "sun_hours.vtp", ignored);
    }
    // The model's copy first: report.json, written last by write_series, marks a complete run.
    if (s.hand_back.copy)
      write_file_staged(options_.write_idf, [&](std::ostream& out) { out << s.hand_back.copy->text; });
    s.written = s.stream->finish(&s.run);  // the summaries, then every file into place
    s.surfaces = s.stream->surfaces();
    s.stream.reset();
    if (s.map && s.map->full) s.written.insert(s.written.end() - 1, dir / "sun_hours.vtp");  // report.json stays last
    if (s.map && !s.map->levels.empty()) s.written.insert(s.written.end() - 1, dir / "sun_hours_levels.vtp");
    // The outputs are complete: a checkpoint left now (this run's, or an older one) is stale.
    if (s.checkpoint) s.checkpoint->remove();
    fs::remove(jobs::Checkpoint::file(dir), ignored);
  });
}

}  // namespace shadow
