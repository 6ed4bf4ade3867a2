// SPDX-License-Identifier: GPL-3.0-or-later
// What the weather readers share (readers/weather_records.hpp): CSV fields, numbers with errors
// naming the file, line and field, and the records placed in time.
#include "readers/weather_records.hpp"

#include "common/format.hpp"

#include <shadow/error.hpp>
#include <shadow/input_file.hpp>
#include <shadow/sun.hpp>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace shadow::weather_detail {

std::string read_weather_file(const std::string& path) {
  try {
    return read_input_file(path, path, std::uintmax_t{1} << 30, "the weather file limit");
  } catch (const InputError& e) {
    const std::string prefix = "cannot open";
    std::string problem = e.problem();
    if (problem.rfind(prefix, 0) == 0) problem.insert(prefix.size(), " the weather file");
    throw InputError(e.where(), problem);
  }
}

std::vector<std::string> split_fields(const std::string& line, bool quotes) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quotes && c == '"') {
      if (quoted && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else {
        quoted = !quoted;
      }
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

std::string trim(const std::string& text) {
  const std::size_t a = text.find_first_not_of(" \t");
  if (a == std::string::npos) return {};
  const std::size_t b = text.find_last_not_of(" \t");
  return text.substr(a, b - a + 1);
}

void LineReader::fail(std::size_t field, const std::string& what, const std::string& problem) const {
  std::string place = "line " + std::to_string(line);
  if (field > 0) place += ", field " + std::to_string(field) + " (" + what + ")";
  throw InputError({file, place}, problem);
}

double LineReader::number(const std::vector<std::string>& fields, std::size_t index, const std::string& what,
                          bool blank_ok) const {
  if (index >= fields.size()) fail(index + 1, what, "the line has only " + std::to_string(fields.size()) + " fields");
  const std::string text = trim(fields[index]);
  if (text.empty()) {
    if (blank_ok) return std::numeric_limits<double>::quiet_NaN();
    fail(index + 1, what, "blank, a number is needed");
  }
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
    fail(index + 1, what, "'" + text + "' is not a number");
  return value;
}

int LineReader::integer(const std::vector<std::string>& fields, std::size_t index, const std::string& what, int low,
                        int high) const {
  const double value = number(fields, index, what);
  if (value != std::floor(value) || value < low || value > high)
    fail(index + 1, what, "'" + trim(fields[index]) + "' is not a whole number in [" + std::to_string(low) + ", " +
                              std::to_string(high) + "]");
  return static_cast<int>(value);
}

namespace {

/// Whether record i starts a new year: 1 January hour 1 after a record of another day.
bool starts_next_year(const Weather& w, std::size_t i) {
  return i > 0 && w.month[i] == 1 && w.day[i] == 1 && w.hour[i] == 1 && !(w.month[i - 1] == 1 && w.day[i - 1] == 1);
}

/// The year of the first record: the first record's own year when the records fit it, else the
/// nearest year they fit (the later of two as near). Records fit a year when every calendar year
/// they run through (the k-th after a wrap past 31 December is the first's + k) is a leap year
/// where they hold 29 February and a common year where 1 March follows 28 February. Typical
/// years mix months of different years, so a file stamped 1996 in January may have no 29
/// February, and one stamped 2023 may hold it; an actual year from July 2023 to June 2024 holds
/// it in its second calendar year. When no year fits (29 February and 1 March after 28 February
/// in one year), the first record's year is kept and place_records names the record.
int placement_year(const Weather& w) {
  std::vector<int> needs;  // per calendar year run through: +1 leap, -1 common, 0 either
  needs.push_back(0);
  for (std::size_t i = 0; i < w.hours(); ++i) {
    if (starts_next_year(w, i)) needs.push_back(0);
    int need = 0;
    if (w.month[i] == 2 && w.day[i] == 29) need = 1;
    if (i > 0 && w.month[i] == 3 && w.day[i] == 1 && w.month[i - 1] == 2 && w.day[i - 1] == 28) need = -1;
    if (need == 0) continue;
    if (needs.back() == -need) return w.record_year[0];  // no year fits
    needs.back() = need;
  }
  const auto fits = [&](int first) {
    for (std::size_t k = 0; k < needs.size(); ++k) {
      const bool leap = is_valid_date(first + static_cast<int>(k), 2, 29);
      if ((needs[k] == 1 && !leap) || (needs[k] == -1 && leap)) return false;
    }
    return true;
  };
  const int stamped = w.record_year[0];
  for (int d = 0; d <= 8; ++d) {  // (leap years repeat every 4, every 8 across a century's end)
    if (stamped + d <= 9999 && fits(stamped + d)) return stamped + d;
    if (d > 0 && stamped - d >= -9999 && fits(stamped - d)) return stamped - d;
  }
  return stamped;
}

}  // namespace

/// Places the records in time: consecutive hours from the first (a year's end wraps to the
/// next year's first hour), in Weather::year.
void place_records(Weather& w, const std::vector<std::size_t>& lines, std::size_t header_lines,
                   const RecordFields& fields) {
  if (w.hours() == 0) throw InputError({w.source, "line " + std::to_string(lines.empty() ? header_lines : lines.back())},
                                       "no hourly records after the " + std::to_string(header_lines) + " header lines");
  w.year = placement_year(w);
  if (w.year != w.record_year[0])
    w.warnings.push_back({{w.source, "line " + std::to_string(lines.front()) + ", field 1 (year)"},
                          "the records are stamped " + std::to_string(w.record_year[0]) + ", but " +
                              (is_valid_date(w.record_year[0], 2, 29) ? "they have no 29 February"
                                                                      : "they hold 29 February") +
                              ": they are placed in " + std::to_string(w.year) +
                              ", the nearest year they fit (typical years mix months of different years)"});
  const auto offset = static_cast<std::int64_t>(std::llround(w.location.time_zone_hours * 3600.0));
  std::int64_t year = w.year;
  std::int64_t expected = 0;  // local seconds of the next record's start
  w.start_utc.resize(w.hours());
  for (std::size_t i = 0; i < w.hours(); ++i) {
    if (starts_next_year(w, i)) ++year;  // Dec 31 hour 24 -> Jan 1 hour 1
    const std::string place = "line " + std::to_string(lines[i]);
    if (!is_valid_date(year, w.month[i], w.day[i]))
      throw InputError({w.source, place + ", field " + std::to_string(fields.day_field) + " (" + fields.day_name + ")"},
                       std::to_string(w.month[i]) + "/" + std::to_string(w.day[i]) + " is not a date in " +
                           std::to_string(year));
    const std::int64_t local = days_from_civil(year, w.month[i], w.day[i]) * 86400 + (w.hour[i] - 1) * 3600;
    if (i > 0 && local != expected)
      throw InputError({w.source, place + ", field " + std::to_string(fields.hour_field) + " (" + fields.hour_name + ")"},
                       "records must follow hour by hour: the previous record was " + std::to_string(w.month[i - 1]) +
                           "/" + std::to_string(w.day[i - 1]) + " hour " + std::to_string(w.hour[i - 1]));
    w.start_utc[i] = local - offset;
    expected = local + 3600;
  }
}

void check_last_record_fields(const std::string& file, const std::vector<std::size_t>& lines, std::size_t last_short,
                              std::size_t first_fields) {
  if (last_short == 0) return;
  throw InputError({file, "line " + std::to_string(lines.back())},
                   "the last record has " + std::to_string(last_short) + " fields, the first " +
                       std::to_string(first_fields) + ": is the file cut short?");
}

void check_diffuse_within_global(Weather& w, const std::vector<std::size_t>& lines) {
  std::size_t count = 0, first = 0;
  for (std::size_t i = 0; i < w.hours(); ++i) {
    const double global = w.global_horizontal[i], diffuse = w.diffuse_horizontal[i];
    // (NaN, missing, compares false)
    if (diffuse > global + 50.0 && diffuse > 1.1 * global) {
      if (count++ == 0) first = i;
    }
  }
  if (count == 0) return;
  w.warnings.push_back({{w.source, "line " + std::to_string(lines[first])},
                        "diffuse horizontal " + detail::format_number(w.diffuse_horizontal[first]) +
                            " Wh/m2 exceeds global horizontal " + detail::format_number(w.global_horizontal[first]) +
                            " (diffuse is part of global); " + std::to_string(count) + (count == 1 ? " hour" : " hours") +
                            " like it" + (count == 1 ? "" : " (this is the first)") + ", read as written"});
}

void AlbedoReader::warn_zero_albedo(Weather& w, const std::string& field) const {
  if (zeros == 0) return;
  w.warnings.push_back({{w.source, "line " + std::to_string(first_zero_line) + ", " + field},
                        "albedo 0 in " + std::to_string(zeros) + (zeros == 1 ? " record" : " records") +
                            " (the first here), read as missing: files that do not measure the albedo write 0 there"});
}

}  // namespace shadow::weather_detail
