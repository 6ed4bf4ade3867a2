// SPDX-License-Identifier: GPL-3.0-or-later
/// @file
/// A sun series as one job (`shadow series`, docs/series.md, docs/cluster.md): read the scene,
/// compute every sun instant on every receiving face in rounds, keep a resumable checkpoint,
/// share the instants among the ranks of a world, compute the sun-hours map and write the
/// series files into an output directory that the job locks.
///
/// The job knows nothing of MPI, signals or terminals: the ranks are a SeriesWorld that the
/// program implements (the `shadow` CLI over MPI; SingleProcessWorld here), a stop request is
/// a flag the program's signal handler sets, and progress and notices go to callbacks.
#pragma once

#include <shadow/energyplus.hpp>
#include <shadow/output.hpp>
#include <shadow/scene_io.hpp>
#include <shadow/series.hpp>
#include <shadow/series_files.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>
#include <shadow/validation.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadow {

/// The processes that share one series job: rank 0 (the root) owns the output directory and
/// gathers the table; every rank computes its share of the instants. Every collective must be
/// called by all ranks in the same order.
class SeriesWorld {
 public:
  virtual ~SeriesWorld() = default;
  [[nodiscard]] virtual int rank() const = 0;
  [[nodiscard]] virtual int size() const = 0;
  [[nodiscard]] bool root() const { return rank() == 0; }
  [[nodiscard]] bool distributed() const { return size() > 1; }

  /// Collective: each rank hands in how its part ended (null: it went well). When any rank
  /// failed, every rank throws (the world chooses what: typically the lowest failing rank's
  /// error, printed once); else it returns.
  virtual void agree(std::exception_ptr error) = 0;
  /// Collective: the largest of the ranks' values.
  virtual std::uint64_t max(std::uint64_t value) = 0;
  /// Collective: rank 0 gets every rank's bytes (index = rank), the others an empty vector.
  virtual std::vector<std::string> gather(const std::string& bytes) = 0;
  /// Collective: rank 0's `bytes` on every rank.
  virtual void broadcast(std::string& bytes) = 0;
};

/// A world of one process: every collective is a no-op, agree() rethrows the error it is given.
class SingleProcessWorld final : public SeriesWorld {
 public:
  [[nodiscard]] int rank() const override { return 0; }
  [[nodiscard]] int size() const override { return 1; }
  void agree(std::exception_ptr error) override {
    if (error) std::rethrow_exception(error);
  }
  std::uint64_t max(std::uint64_t value) override { return value; }
  std::vector<std::string> gather(const std::string& bytes) override { return {bytes}; }
  void broadcast(std::string&) override {}
};

/// What a series job is doing (for an out-of-memory message, say).
/// Mapping is the sun-hours map, after Computing's rounds; where its pass computes its faces'
/// lit areas for the series too (SeriesJobOptions::share_map_pass: never with a checkpoint),
/// before them (Computing, Mapping, Computing again, Writing).
enum class SeriesJobStage { Loading, Preparing, Computing, Mapping, Writing };

/// Progress of a series job, on rank 0 only.
struct SeriesJobProgress {
  enum class Part {
    Instants,  ///< sun instants of the whole job (every rank's, rank 0's share standing for all)
    MapFaces   ///< faces of the sun-hours map (rank 0's block when distributed)
  };
  Part part = Part::Instants;
  std::size_t done = 0;
  std::size_t total = 0;
  std::size_t base = 0;    ///< done before this run (instants from the checkpoint)
  bool finished = false;   ///< the part ended (or stops): a progress line may be erased
  // Each part's first report has nothing done in this run yet (done == base): it starts.
};

/// Thrown on every rank when the job stops on request (SeriesJobOptions::stop, stop_after) after
/// a round, with the instants so far kept in the checkpoint; the same options with `resume`
/// finish the job.
class SeriesJobStopped : public std::runtime_error {
 public:
  SeriesJobStopped(std::size_t done, std::size_t total, int signal, std::filesystem::path checkpoint);
  std::size_t done;                   ///< instants in the checkpoint
  std::size_t total;                  ///< instants of the job
  int signal;                         ///< the stop flag's value (a signal number); 0: stop_after
  std::filesystem::path checkpoint;   ///< the checkpoint file
};

/// The periods longer than this many days get a bounded number of per-instant files by default.
inline constexpr double kSeriesLongPeriodDays = 7.0;
/// At most this many per-instant files by default on a long period.
inline constexpr std::size_t kSeriesDefaultInstantFiles = 48;

/// The default SeriesFiles::every for a series (instants above the horizon and their UTC times):
/// 1 (every instant) for a period of up to kSeriesLongPeriodDays; else the smallest K that writes
/// at most kSeriesDefaultInstantFiles files, spread evenly over the period.
std::size_t default_series_every(std::size_t instants, const std::vector<std::int64_t>& times);

/// How a series job runs. The names in error messages are those of `shadow series`'s options
/// (`--from`, `--sun-hours-map`, `--write-idf`), which these fields mirror.
struct SeriesJobOptions {
  std::filesystem::path scene;   ///< the scene file (every rank reads it)
  std::filesystem::path output;  ///< the output directory (rank 0 locks and writes it)
  LoadOptions load;              ///< how the scene is read
  /// Another period at the scene's site: the first and last local dates (YYYY-MM-DD; empty:
  /// keep) and the step in minutes (0: keep).
  std::string from, to;
  int step_minutes = 0;
  unsigned threads = 0;  ///< worker threads per rank (0: every hardware thread)
  Arithmetic arithmetic = Arithmetic::Exact;
  std::size_t tile_casters = SeriesOptions{}.tile_casters;            ///< docs/tiles.md
  std::size_t fast_tile_casters = SeriesOptions{}.fast_tile_casters;  ///< docs/tiles.md
  std::optional<std::size_t> every;  ///< SeriesFiles::every; empty: default_series_every()
  bool fragments = false;            ///< per-instant lit polygons for the instants in series.pvd
  std::optional<bool> energyplus_shading;  ///< SeriesFiles::energyplus_shading
  /// Meshes that get the sun-hours map besides the scene's `sun_hours_map` (mesh names,
  /// city/<id> or type:<CityJSON type>).
  std::vector<std::string> sun_hours_map;
  /// The threshold map's levels in hours (`--sun-hours-levels`, parse_sun_hours_levels): with
  /// the map, also sun_hours_levels.vtp and the levels' exact areas in report.json; an
  /// InputError naming `--sun-hours-levels` when there is no map.
  std::vector<double> sun_hours_levels;
  /// With levels (`--sun-hours-levels-only`): compute the threshold map alone
  /// (SunHoursOptions::full = false), whose memory follows the level boundaries instead of
  /// growing with the instants; no sun_hours.vtp. An InputError naming the flag without levels.
  bool sun_hours_levels_only = false;
  /// In an exact series on one process without a checkpoint, compute the map first and take its
  /// receiving faces' rows of the table from its pass (SunHoursOptions::series_table), while
  /// those rows x the instants are at most round_cells (that table is then held besides each
  /// round's): each such face-instant pair is computed once. False computes the map after the
  /// instants, as checkpointed runs and MPI ranks always do: the same files, report.json's
  /// counters aside (they count the pass that ran).
  bool share_map_pass = true;
  /// Keep every instant's table in memory for SeriesJobResult::series (faces x instants x 25
  /// bytes). The files never need it: they are written as the instants complete (docs/series.md,
  /// "Streaming"). `shadow series` sets it false, so that its memory does not grow with the
  /// number of instants; then SeriesJobResult::series has the rows, their areas, the number of
  /// instants and the stats, and empty per-cell arrays.
  bool keep_table = true;
  /// At most this many cells (receiving faces x instants) of the table per round: what a round
  /// holds in memory (about 25 bytes a cell; on rank 0, every rank's share) before its instants
  /// go to the files. The default, 2^21, is about 52 MB; fewer cells, more rounds. On one
  /// process without per-instant fragments a round's instants are written while the next round
  /// computes: each round then takes half as many cells, so that the two held at once stay
  /// within this. A map that shares its pass (share_map_pass) holds at most as many cells again
  /// through the rounds.
  std::size_t round_cells = std::size_t{1} << 21;
  bool checkpoint = false;  ///< keep OUTDIR/series.checkpoint as the run goes
  bool resume = false;      ///< start from OUTDIR/series.checkpoint (implies checkpoint)
  /// Testing: stop (SeriesJobStopped) after the round in which this many instants are in the
  /// checkpoint (0: never; implies checkpoint; rounds then keep their first size).
  std::size_t stop_after = 0;
  /// Also write this file: a copy of the EnergyPlus model given as `scene` that imports
  /// energyplus-shading.csv (empty: none). Checked before computing.
  std::filesystem::path write_idf;
  /// Set (to a signal number, say) to stop after the round in progress when checkpointing;
  /// read on every rank after every round. Lock-free, so a signal handler may store to it.
  const std::atomic<int>* stop = nullptr;
  std::function<void(const SeriesJobProgress&)> progress;  ///< rank 0 only
  /// One line for the user (a scene's warning as "warning: ...", resuming from a checkpoint),
  /// without a program's prefix; rank 0 only.
  std::function<void(const std::string&)> notice;
  std::function<void(SeriesJobStage)> stage;  ///< every rank, at each stage's start
  // Members are added here, at the end: the layout of those above stays as it was.
  /// With sun_hours_levels_only (`--sun-hours-held-segments`): SunHoursOptions::
  /// level_held_segments, the most exact boundary segments the threshold map holds (0 or more;
  /// fewer: less memory, more time computing lit regions again); unset: its default. An
  /// InputError naming the flag without sun_hours_levels_only.
  std::optional<std::size_t> sun_hours_held_segments;
};

/// What the job hands back to EnergyPlus: the objects that import energyplus-shading.csv
/// (energyplus-objects.idf) and, with `write_idf`, a copy of the model with them in place.
struct SeriesEnergyPlusHandBack {
  std::string csv;      ///< the CSV's absolute path, as Schedule:File:Shading names it
  std::string objects;  ///< empty when the CSV cannot be named in an IDF field
  std::string problem;  ///< why `objects` is empty
  bool model = false;   ///< the scene file is an EnergyPlus model
  std::optional<EnergyPlusImportCopy> copy;  ///< written to SeriesJobOptions::write_idf
  /// What the user should know before running EnergyPlus on it: the CSV covers part of the year
  /// (the other time steps 0, fully shaded), or the copy's RunPeriod is another year than the
  /// CSV's. Empty when neither.
  std::string note;
};

/// A finished job, as rank 0 sees it (on the other ranks only `ranks` is set).
struct SeriesJobResult {
  Scene scene;
  SunSeries suns;
  SeriesResult series;                 ///< every instant's table (SeriesJobOptions::keep_table)
  /// The named surfaces with their areas and sun hours (surface_series() on the whole table,
  /// without its per-instant lit_fraction): what the summary shows, also without the table.
  SurfaceSeries surfaces;
  std::optional<SunHoursMap> map;      ///< when any face asked for the map
  std::vector<std::filesystem::path> written;  ///< the files written, report.json last
  std::size_t every = 1;               ///< SeriesFiles::every used
  std::size_t resumed = 0;             ///< instants that came from the checkpoint
  double compute_seconds = 0;          ///< from the start to the end of the instants' computation, the map's aside
  double map_seconds = 0;              ///< the sun-hours map (with its faces' lit areas when it shared its pass)
  double write_seconds = 0;            ///< writing the files
  int ranks = 1;
  SeriesEnergyPlusHandBack energyplus;
};

/// One series job on one rank of `world` (every rank constructs one with the same options).
class SeriesJob {
 public:
  SeriesJob(SeriesJobOptions options, SeriesWorld& world);
  ~SeriesJob();
  SeriesJob(const SeriesJob&) = delete;
  SeriesJob& operator=(const SeriesJob&) = delete;

  /// Runs the job to its end (once per SeriesJob). On a distributed world an error on any rank stops every rank
  /// (SeriesWorld::agree); on one process errors pass through unchanged.
  /// @throws InputError (the scene, the period, a checkpoint of another run), OutputError (the
  /// directory: locked by another job, not writable), SeriesJobStopped
  SeriesJobResult run();

 private:
  struct State;
  void run_steps();
  OutputDirectory::SeriesFiles series_files();
  void load();
  void check_same_scene();
  void open_output();
  void resume_or_start();
  void share_instants();
  void compute_instants();
  std::string compute_round(const std::vector<std::uint64_t>& instants, std::size_t done_before,
                            std::size_t round_total);
  void place_round(const std::string& bytes);
  /// Whether a round's files are written while the next round computes (one process).
  [[nodiscard]] bool writes_behind() const;
  void stop_if_asked(std::size_t done, bool more);
  void compute_map();
  void take_map_rows();
  void write_outputs();

  SeriesJobOptions options_;
  SeriesWorld& world_;
  std::unique_ptr<State> state_;
};

}  // namespace shadow
