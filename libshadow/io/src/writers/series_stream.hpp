// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the files of a sun series written as its instants complete (docs/series.md,
// "Streaming"). The rows of sunlit.csv and energyplus-shading.csv and the per-instant datasets
// are written as each instant arrives, in instant order; the per-face and per-surface sums
// (sun hours, their bounds, the lit area-hours of the objects) are kept as running sums in the
// same order as the whole-table functions of shadow/series.hpp add them, so faces.vtp,
// sun_hours_by_object.csv and report.json are bit for bit those of the table. Memory: a few
// doubles per face and surface, whatever the number of instants.
#pragma once

#include "writers/series_outputs.hpp"
#include "writers/series_rows.hpp"
#include "writers/staged_files.hpp"

#include <shadow/output.hpp>
#include <shadow/series.hpp>
#include <shadow/shadows.hpp>

#include <vtkSmartPointer.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

class vtkPolyData;

namespace shadow::detail {

/// The series files of OutputDirectory::write_series, fed one instant at a time.
class SeriesStream {
 public:
  /// Stages the files in `outdir` (created; its report.json removed) and writes the headers.
  /// `shape` gives the rows (faces), their areas, the number of instants and the arithmetic;
  /// its per-cell arrays are not read.
  /// @throws OutputError
  SeriesStream(const std::filesystem::path& outdir, const Scene& scene, const SunSeries& suns,
               const SeriesResult& shape, const OutputDirectory::SeriesFiles& files);
  ~SeriesStream();
  SeriesStream(const SeriesStream&) = delete;
  SeriesStream& operator=(const SeriesStream&) = delete;

  /// Instant `instant`'s column, in any order: it is written when every instant before it has
  /// been (until then a copy waits). Each instant once.
  /// @throws OutputError, and whatever SeriesFiles::fragments throws
  void add(std::size_t instant, const SeriesColumn& column);
  /// Adds the counters of some instants (report.json's `stats`).
  void add_stats(const ShadowStats& stats) { shape_.stats += stats; }
  /// Instants written so far (every one before this index).
  [[nodiscard]] std::size_t written() const { return next_; }

  /// Writes the rest (sun_hours_by_object.csv, the .pvd files, faces.vtp, report.json) once
  /// every instant has come, and puts every file in place, report.json last.
  /// @returns the paths in the order placed
  /// @throws OutputError
  std::vector<std::filesystem::path> finish(const RunInfo* run);
  /// The named surfaces with their areas and (after finish) sun hours; no lit_fraction.
  [[nodiscard]] const SurfaceSeries& surfaces() const { return surfaces_; }

 private:
  struct Owned;
  void emit(std::size_t i, const SeriesColumn& column);
  void check_stream(std::ofstream& out, const StagedFiles::Target& target);
  void close_stream(std::ofstream& out, const StagedFiles::Target& target);

  std::filesystem::path outdir_;
  const Scene& scene_;
  const SunSeries& suns_;
  SeriesResult shape_;  ///< faces, area, instants, arithmetic, stats: no cells
  OutputDirectory::SeriesFiles files_;
  StagedFiles staged_;
  SurfaceSeries surfaces_;  ///< surfaces, area and instants; lit_fraction stays empty
  std::vector<std::size_t> row_of_;  ///< scene face -> row (SIZE_MAX: not a row)
  std::vector<double> fraction_sum_, bound_sum_, lit_sum_;  ///< per row, in instant order
  std::vector<double> surface_sum_;                         ///< per surface, in instant order
  std::vector<double> fractions_;                           ///< scratch: one instant's surfaces
  StagedFiles::Target sunlit_target_, energyplus_target_, by_object_target_;
  std::ofstream sunlit_, energyplus_;
  EnergyPlusSchedule energyplus_schedule_;
  std::optional<EnergyPlusRows> energyplus_rows_;
  vtkSmartPointer<vtkPolyData> base_;
  std::vector<std::pair<double, std::string>> steps_, fragment_steps_;
  std::vector<std::string> instant_files_;
  std::map<std::size_t, std::unique_ptr<Owned>> waiting_;
  std::size_t next_ = 0;
};

}  // namespace shadow::detail
