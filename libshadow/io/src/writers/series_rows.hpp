// SPDX-License-Identifier: GPL-3.0-or-later
// Internal: the text files of a sun series one instant at a time (sunlit.csv and
// energyplus-shading.csv), so that a series job writes them as its instants complete instead of
// holding the whole table (docs/series.md, "Streaming"). write_sunlit_csv() and
// write_energyplus_shading_csv() (shadow/series_files.hpp) are these rows over a whole table.
#pragma once

#include <shadow/series.hpp>
#include <shadow/series_files.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace shadow::detail {

/// sunlit.csv's header line: `time,<surface label>,...` (CRLF).
void write_sunlit_header(std::ostream& out, const std::vector<NamedSurface>& surfaces);

/// One row of sunlit.csv: instant `i`'s time (ISO 8601 UTC; empty past suns.times) and one lit
/// fraction per surface (CRLF).
void write_sunlit_row(std::ostream& out, const SunSeries& suns, std::size_t i, const std::vector<double>& fractions);

/// energyplus-shading.csv row by row: every time step of the year in order, each filled by the
/// instant that starts it (0 at night and outside the period). Instants come in any order; a
/// row is written as soon as every row before it can be, so for a period (instants in time order)
/// at most one instant's fractions wait.
class EnergyPlusRows {
 public:
  /// `schedule` must be energyplus_schedule(scene) with `written` set; `instants`: the series',
  /// `surfaces`: the number of columns.
  EnergyPlusRows(const Scene& scene, const SunSeries& suns, std::size_t instants, std::size_t surfaces,
                 EnergyPlusSchedule schedule);

  /// The header line `Surface Name,<SURFACE>,...` (upper case).
  void header(std::ostream& out, const std::vector<NamedSurface>& surfaces) const;
  /// Instant `i`'s surface fractions: writes the rows that are complete now.
  void instant(std::ostream& out, std::size_t i, const std::vector<double>& fractions);
  /// The remaining rows (nights to the year's end). @returns the schedule written
  const EnergyPlusSchedule& finish(std::ostream& out);

 private:
  void write_ready(std::ostream& out);
  EnergyPlusSchedule schedule_;
  std::int64_t year_start_ = 0, step_ = 0;
  std::size_t surfaces_ = 0;
  std::vector<std::size_t> column_;  ///< per row: the instant that fills it, or SIZE_MAX
  std::vector<bool> fills_;          ///< per instant: whether it fills a row
  std::map<std::size_t, std::vector<double>> waiting_;  ///< instants whose row is not written yet
  std::size_t next_row_ = 0;
  std::string row_;  ///< a row's text, its room kept from one row to the next
};

}  // namespace shadow::detail
