// SPDX-License-Identifier: GPL-3.0-or-later
/// @file output.hpp
/// @brief Writing results: VTK XML files for ParaView and report.json.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/series_files.hpp>
#include <shadow/series.hpp>
#include <shadow/shadows.hpp>
#include <shadow/sun_hours.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadow {

/// A file could not be written (the message names the path and the system's reason).
class OutputError : public std::runtime_error {
 public:
  /// The message with control bytes escaped (escape_control): one line, whatever OUTDIR is called.
  explicit OutputError(const std::string& message);
};

/// The identity of a run, written to report.json as its top-level "run" object, so that a
/// result can be told from an older one in the same directory.
struct RunInfo {
  std::string scene;            ///< the scene file as given
  std::string started_utc;      ///< start time, ISO 8601 UTC (`2026-11-23T13:40:00Z`); see utc_now()
  ShadowOptions options;        ///< threads, polygons, planes, plane_window, arithmetic, lights
  double planarity_tolerance = 1e-6;  ///< LoadOptions::planarity_tolerance of the run
  /// A series' sun-hours map (shadow/sun_hours.hpp), when the run made one: report.json gets a
  /// `sun_hours_map` section (its size and, with levels, the exact area at each level).
  const SunHoursMap* sun_hours_map = nullptr;
};

/// The current time as ISO 8601 UTC, to the second: `2026-11-23T13:40:00Z`.
std::string utc_now();

namespace detail {
class SeriesStream;
}

/// One instant's values for every row of a series (SeriesResult::faces): element r of each
/// array is at [r * stride]; stride is SeriesResult::instants for a column of the row-major
/// table, 1 for arrays that hold one instant's rows side by side.
struct SeriesColumn {
  const double* lit_area = nullptr;
  const double* lit_fraction = nullptr;
  const unsigned char* faces_light = nullptr;
  const double* lit_area_error_bound = nullptr;
  std::size_t stride = 1;
  /// Column `instant` of `series`' table (which must outlive the view).
  static SeriesColumn of(const SeriesResult& series, std::size_t instant) {
    return {series.lit_area.data() + instant, series.lit_fraction.data() + instant, series.faces_light.data() + instant,
            series.lit_area_error_bound.data() + instant, series.instants};
  }
};

/// The files of a sun series written as its instants complete (OutputDirectory::stream_series,
/// docs/series.md "Streaming"): each instant's rows of sunlit.csv and energyplus-shading.csv and
/// its dataset as it arrives, running sums for sun hours and the objects. Memory stays a few
/// numbers per face and surface whatever the number of instants; the files are byte for byte
/// those of write_series() on the whole table. Until finish() the files are temporaries: an
/// exception, a stop, or a stream dropped unfinished leaves nothing that looks complete.
class SeriesFileStream {
 public:
  /// @private (made by OutputDirectory::stream_series)
  explicit SeriesFileStream(std::unique_ptr<detail::SeriesStream> impl);
  SeriesFileStream(SeriesFileStream&&) noexcept;
  SeriesFileStream& operator=(SeriesFileStream&&) noexcept;
  ~SeriesFileStream();

  /// Instant `instant`'s column (0 <= instant < the shape's instants, each once, in any order:
  /// an instant that comes before its turn is copied and waits for the ones before it).
  /// @throws OutputError, std::logic_error for an instant out of range or given twice, and
  /// whatever SeriesFiles::fragments throws
  void add(std::size_t instant, const SeriesColumn& column);
  /// Adds the counters of some instants (report.json's `stats`).
  void add_stats(const ShadowStats& stats);
  /// The instants written so far: every one below this index.
  [[nodiscard]] std::size_t written() const;
  /// Writes the summaries (sun_hours_by_object.csv, the .pvd files, faces.vtp, report.json with
  /// `run` when given) and puts every file in place, report.json last.
  /// @returns the paths in the order placed
  /// @throws OutputError, std::logic_error when an instant is missing
  std::vector<std::filesystem::path> finish(const RunInfo* run = nullptr);
  /// After finish(): the named surfaces, their areas and sun hours, as surface_series() gives
  /// them on the whole table (its per-instant `lit_fraction` left empty).
  [[nodiscard]] const SurfaceSeries& surfaces() const;

 private:
  std::unique_ptr<detail::SeriesStream> impl_;
};

/// An output directory held by one writer for the length of a run (POSIX).
///
/// Opening it, at the start of a run and before any computing: creates the directory (and its
/// parents), takes an exclusive lock on `OUTDIR/.shadow.lock` (flock; a second writer gets an
/// OutputError at once instead of mixing files), removes temporary files
/// (`.NAME.tmp-PID`, and `.report.json.old-PID`) left by killed processes that no longer exist,
/// and removes the old `report.json` (renamed at once to `.report.json.old-PID`, deleted in the
/// background until the directory is closed). report.json is written last, so while a run is under way, and after a run
/// was killed, the directory has no report.json: its absence means "incomplete". The lock file
/// is removed again when the directory is closed.
class OutputDirectory {
 public:
  /// @throws OutputError (not a directory, cannot create, locked by another writer, ...)
  explicit OutputDirectory(const std::filesystem::path& outdir);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  /// Writes every output file like write_outputs; report.json gets `run` when given. Files of
  /// an earlier `shadow series` in the directory (sunlit.csv, energyplus-shading.csv,
  /// series.pvd, fragments.pvd, sun_hours.vtp) are removed: they are not this run's.
  /// @throws OutputError
  std::vector<std::filesystem::path> write(const Scene& scene, const ShadowResult& result,
                                           const RunInfo* run = nullptr);

  /// Writes a sun series (docs/series.md): `sunlit.csv`, `energyplus-shading.csv` (when
  /// energyplus_shading_wanted(scene), series.hpp, and the period maps onto EnergyPlus's time
  /// steps), `series/sun_NNNNN.vtp` and `series.pvd` (every
  /// `every`-th instant; none when `every` is 0), `faces.vtp` (with `sun_hours`) and
  /// `report.json` (last), under the same discipline as write().
  /// @throws OutputError
  std::vector<std::filesystem::path> write_series(const Scene& scene, const SunSeries& suns,
                                                  const SeriesResult& series, std::size_t every = 1,
                                                  const RunInfo* run = nullptr);

  /// What write_series writes besides the tables.
  struct SeriesFiles {
    std::size_t every = 1;  ///< one dataset per `every`-th instant in series.pvd; 0: none
    /// When set: for each instant in series.pvd also `series/fragments_NNNNN.vtp` (that instant's
    /// lit and shadowed polygons, as fragments.vtp) and `fragments.pvd`. Called with the index
    /// of the instant in the series, one instant at a time (only one result in memory); the
    /// fragments' light_id should be the instant's light in Scene::lights.
    std::function<ShadowResult(std::size_t instant)> fragments;
    /// When not empty and `energyplus-shading.csv` is written: this text (IDF objects, see
    /// energyplus_import_objects() in shadow/energyplus.hpp) as `energyplus-objects.idf` beside
    /// it. Without it, or without the CSV, an older `energyplus-objects.idf` is removed.
    std::string energyplus_objects;
    /// Whether to write energyplus-shading.csv (when the period allows one): absent, as
    /// energyplus_shading_wanted(scene) says (an EnergyPlus model, or the scene file's
    /// `energyplus_shading`); true, also for a scene that is no EnergyPlus model; false, never.
    std::optional<bool> energyplus_shading;
  };

  /// write_series with the fragments of the instants shown (SeriesFiles::fragments).
  /// @throws OutputError, and whatever `files.fragments` throws
  std::vector<std::filesystem::path> write_series(const Scene& scene, const SunSeries& suns,
                                                  const SeriesResult& series, const SeriesFiles& files,
                                                  const RunInfo* run = nullptr);

  /// The files of write_series(), written as the instants are added to the stream instead of
  /// from a whole table. `shape` gives the rows (faces), their areas, the number of instants,
  /// the arithmetic and the stats so far (its per-cell arrays are not read). `scene`, `suns` and
  /// this directory must outlive the stream.
  /// @throws OutputError
  SeriesFileStream stream_series(const Scene& scene, const SunSeries& suns, const SeriesResult& shape,
                                 const SeriesFiles& files);

  [[nodiscard]] const std::filesystem::path& path() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes every output file into `outdir` (created if missing):
/// `fragments.vtp`, `faces.vtp`, `plane_shadows.vtp`, `lights.vtp`, `report.json` and
/// `scene.vtm` (ParaView multiblock of all of them). An existing `report.json` is removed
/// first; files are written under temporary names and renamed into place only when all of them
/// are complete, `report.json` last. So `report.json` is the sign of a complete set: an
/// interrupted run never leaves a directory that looks complete.
/// @returns the paths written, in the order they were put in place.
/// @throws OutputError
/// It opens an OutputDirectory for the writing (lock, stale temporaries, old report); a caller
/// that computes for long should open one itself before computing and use its write().
/// @throws OutputError
std::vector<std::filesystem::path> write_outputs(const std::filesystem::path& outdir,
                                                 const Scene& scene, const ShadowResult& result);

/// write_outputs with the run's identity in report.json's `run` object.
std::vector<std::filesystem::path> write_outputs(const std::filesystem::path& outdir,
                                                 const Scene& scene, const ShadowResult& result,
                                                 const RunInfo& run);

/// Writes one file under the rule every output of write_outputs follows: `write` fills
/// `.NAME.tmp-PID` beside `path`, the stream is closed and checked (a full disk, a quota or a
/// file size limit shows up at the latest when the last buffer is flushed), and only a complete
/// file is renamed onto `path`. On any failure, including an exception thrown by `write`, the
/// temporary is removed and whatever was at `path` stays as it was. The directory must exist
/// (`shadow render` checks it before drawing).
/// @throws OutputError naming `path`, with the system's reason; whatever `write` throws
void write_file_staged(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// The report: libshadow_version, scene, lights[], faces[] (id, mesh, area, lights[] with
/// light, lit_area, shadow_area, lit_fraction, faces_light), planes[] (name, plane, light,
/// shadow_area, reaches_window, ...), summary, stats, warnings; and `run` (after `scene`):
/// scene, started_utc (null when unknown), libshadow_version, arithmetic, and with a RunInfo
/// also options (threads, polygons, planes, plane_window, lights, planarity_tolerance). `summary.arithmetic` is "exact"
/// or "fast"; for the fast path each face's light entries, and `summary.per_light`, also carry
/// `lit_area_error_bound`, and `stats` carries `fast_exact_fallbacks` and `fast_collapsed`.
void write_report_json(std::ostream& out, const Scene& scene, const ShadowResult& result);

/// write_report_json with the run's identity (`run.options` and `run.started_utc`).
void write_report_json(std::ostream& out, const Scene& scene, const ShadowResult& result,
                       const RunInfo& run);

/// The exact sun-hours map (shadow/sun_hours.hpp) as a VTK file.
/// Writes `map` as VTK XML PolyData to `path` (normally OUTDIR/sun_hours.vtp): one polygon cell
/// per SunHoursCell, points Float64, cell arrays `sun_hours` (Float64), `face_id`, `region_id`,
/// `area` (Float64); field data `total_hours`. Written under a temporary name in the same
/// folder (`.NAME.tmp-PID`) and renamed into place when complete, like OutputDirectory::write;
/// call it before the run's report.json is written.
/// @throws OutputError
void write_sun_hours_vtp(const std::filesystem::path& path, const SunHoursMap& map);

/// write_sun_hours_vtp with the points shifted like the scene's other VTK files: relative to
/// Scene::origin when it has one (a CityJSON model at projected coordinates; field data `origin`).
/// @throws OutputError
void write_sun_hours_vtp(const std::filesystem::path& path, const SunHoursMap& map, const Scene& scene);

/// Writes the threshold map (SunHoursMap::level_cells) as VTK XML PolyData to `path` (normally
/// OUTDIR/sun_hours_levels.vtp), points shifted like write_sun_hours_vtp(path, map, scene): one
/// polygon cell per level cell, cell arrays `level` (Float64, the highest level reached, 0 below
/// the lowest; the active scalars), `face_id`, `region_id`, `area` (Float64); field data
/// `levels`, `level_areas` (the map's area at each level), `area` (the faces' area) and
/// `total_hours`. Written under a temporary name and renamed into place, like every output file.
/// @throws OutputError
void write_sun_hours_levels_vtp(const std::filesystem::path& path, const SunHoursMap& map, const Scene& scene);

}  // namespace shadow
