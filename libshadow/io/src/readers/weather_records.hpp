// SPDX-License-Identifier: GPL-3.0-or-later
// What the weather readers share (epw_reader.cpp, tmy3_reader.cpp): fields of a CSV line, numbers
// with errors that name the file, line and field, and the records placed in time.
#pragma once

#include <shadow/weather.hpp>

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace shadow::weather_detail {

/// The whole of weather file `path`, read as the scene's files are (shadow/input_file.hpp):
/// a regular file only, at most 1 GiB (an hourly year is some 2 MB), so that a directory, a FIFO
/// or /dev/zero is one error instead of a wait without end. Errors read "cannot open the weather
/// file: ...".
std::string read_weather_file(const std::string& path);

/// The fields of one CSV line. With `quotes`, a field in double quotes may hold commas (and ""
/// for a quote); EPW records have no quoting and are split at every comma.
std::vector<std::string> split_fields(const std::string& line, bool quotes = false);

/// `text` without leading and trailing blanks and tabs.
std::string trim(const std::string& text);

/// Numbers of the current line, with errors `FILE: line L, field F (WHAT): PROBLEM`.
struct LineReader {
  const std::string& file;
  std::size_t line = 0;

  /// Throws InputError; `field` is 1-based (0: the line only).
  [[noreturn]] void fail(std::size_t field, const std::string& what, const std::string& problem) const;

  /// Field `index` (0-based) of `fields` as a number; NaN when blank and `blank_ok`.
  double number(const std::vector<std::string>& fields, std::size_t index, const std::string& what,
                bool blank_ok = false) const;

  /// A whole number in [low, high].
  int integer(const std::vector<std::string>& fields, std::size_t index, const std::string& what, int low, int high) const;
};

/// Where the readers name the date and the hour of a record in errors: the 1-based field and its
/// name (EPW: 3 `day` and 4 `hour`).
struct RecordFields {
  std::size_t day_field = 3;
  const char* day_name = "day";
  std::size_t hour_field = 4;
  const char* hour_name = "hour";
};

/// Places the records in time (Weather::year, start_utc): consecutive hours from the first (a
/// year's end wraps to the next year's first hour). `lines` are the records' line numbers.
/// @throws InputError naming the record's line and field for a date that does not exist or a
/// record out of order, or for no record at all (at `header_lines`).
void place_records(Weather& w, const std::vector<std::size_t>& lines, std::size_t header_lines,
                   const RecordFields& fields = {});

/// Throws when the last record (at lines.back()) had `last_short` fields, fewer than the first's
/// `first_fields` (0: it had as many): a line cut in the middle by a file that stopped, whose cut
/// field would read as a smaller number.
void check_last_record_fields(const std::string& file, const std::vector<std::size_t>& lines, std::size_t last_short,
                              std::size_t first_fields);

/// The albedo of a record as the computation takes it: NaN (missing) unless in (0, 1]. Files
/// that do not measure it write 0 there (CWEC files and those converted from TMY2 write `0.000`
/// in EPW's field 33, which EnergyPlus does not read: its ground reflectance is
/// Site:GroundReflectance, 0.2 unless set). No ground reflects nothing, so 0 is read as missing
/// and the ground reflectance falls back to 0.2; read as written it took the ground-reflected
/// part off every wall (13% of a south wall's year in Mannheim). The zeros are counted for one
/// warning (warn_zero_albedo).
struct AlbedoReader {
  std::size_t zeros = 0, first_zero_line = 0;
  double operator()(double value, std::size_t line) {
    if (value == 0.0 && zeros++ == 0) first_zero_line = line;
    return value > 0.0 && value <= 1.0 ? value : std::numeric_limits<double>::quiet_NaN();
  }
  /// One warning on `w` when some records' albedo was 0, naming the first (`field`: its place).
  void warn_zero_albedo(Weather& w, const std::string& field) const;
};

/// Adds one warning to `w` when some hours' diffuse horizontal exceeds their global horizontal
/// by more than 50 Wh/m2 and 10% (diffuse is part of global: such values are misplaced columns
/// or bad data, read as written), naming the first such record's line and how many there are.
void check_diffuse_within_global(Weather& w, const std::vector<std::size_t>& lines);

}  // namespace shadow::weather_detail
