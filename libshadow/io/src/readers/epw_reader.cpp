// SPDX-License-Identifier: GPL-3.0-or-later
// EnergyPlus EPW weather files (shadow/weather.hpp): the LOCATION line, the data period, then
// one record per hour. Each record's hour ends it (hour 1 = 00:00-01:00 local standard time).
// Missing values are those EPW flags (9999 for irradiation, 999 for albedo) and blank fields.
#include <shadow/epw.hpp>

#include <shadow/error.hpp>

#include <cerrno>
#include <cstring>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace shadow {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The fields of one CSV line (EPW has no quoting in its records; header comments may hold
/// commas, but only LOCATION, HOLIDAYS and DATA PERIODS are read by field).
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(line.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin));
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return fields;
}

std::string trim(const std::string& text) {
  const std::size_t a = text.find_first_not_of(" \t");
  if (a == std::string::npos) return {};
  const std::size_t b = text.find_last_not_of(" \t");
  return text.substr(a, b - a + 1);
}

struct LineReader {
  const std::string& file;
  std::size_t line = 0;

  [[noreturn]] void fail(std::size_t field, const std::string& what, const std::string& problem) const {
    std::string place = "line " + std::to_string(line);
    if (field > 0) place += ", field " + std::to_string(field) + " (" + what + ")";
    throw InputError({file, place}, problem);
  }

  /// Field `index` (0-based) of `fields` as a number; NaN when blank and `blank_ok`.
  double number(const std::vector<std::string>& fields, std::size_t index, const char* what,
                bool blank_ok = false) const {
    if (index >= fields.size())
      fail(index + 1, what, "the line has only " + std::to_string(fields.size()) + " fields");
    const std::string text = trim(fields[index]);
    if (text.empty()) {
      if (blank_ok) return kNaN;
      fail(index + 1, what, "blank, a number is needed");
    }
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
      fail(index + 1, what, "'" + text + "' is not a number");
    return value;
  }

  int integer(const std::vector<std::string>& fields, std::size_t index, const char* what, int low, int high) const {
    const double value = number(fields, index, what);
    if (value != std::floor(value) || value < low || value > high)
      fail(index + 1, what, "'" + trim(fields[index]) + "' is not a whole number in [" + std::to_string(low) + ", " +
                                std::to_string(high) + "]");
    return static_cast<int>(value);
  }

  /// An irradiation field: >= 9999 (or blank) is missing; negative is an error.
  double irradiation(const std::vector<std::string>& fields, std::size_t index, const char* what) const {
    const double value = number(fields, index, what, true);
    if (std::isnan(value) || value >= 9999.0) return kNaN;
    if (value < 0.0) fail(index + 1, what, "negative irradiation " + trim(fields[index]));
    return value;
  }
};

void read_location(const std::vector<std::string>& f, const LineReader& r, WeatherLocation& loc) {
  if (f.empty() || trim(f[0]) != "LOCATION") r.fail(0, "", "the first line of an EPW file is LOCATION,...");
  if (f.size() < 10) r.fail(0, "", "LOCATION has " + std::to_string(f.size()) + " fields, 10 are needed");
  loc.city = trim(f[1]);
  loc.region = trim(f[2]);
  loc.country = trim(f[3]);
  loc.source = trim(f[4]);
  loc.wmo = trim(f[5]);
  loc.latitude = r.number(f, 6, "latitude");
  loc.longitude = r.number(f, 7, "longitude");
  loc.time_zone_hours = r.number(f, 8, "time zone");
  loc.elevation = r.number(f, 9, "elevation");
  if (loc.latitude < -90.0 || loc.latitude > 90.0) r.fail(7, "latitude", "not in [-90, 90]");
  if (loc.longitude < -180.0 || loc.longitude > 180.0) r.fail(8, "longitude", "not in [-180, 180]");
  if (loc.time_zone_hours < -14.0 || loc.time_zone_hours > 14.0) r.fail(9, "time zone", "not in [-14, 14] hours");
  if (loc.elevation < -1000.0 || loc.elevation > 100000.0) r.fail(10, "elevation", "not in [-1000, 100000] metres");
}

/// One hourly record appended to `w`; `previous_day` (days since 1970, local) and hour check order.
void read_record(const std::vector<std::string>& f, const LineReader& r, Weather& w) {
  const int year = r.integer(f, 0, "year", -9999, 9999);
  const int month = r.integer(f, 1, "month", 1, 12);
  const int day = r.integer(f, 2, "day", 1, 31);
  const int hour = r.integer(f, 3, "hour", 1, 24);
  w.record_year.push_back(year);
  w.month.push_back(month);
  w.day.push_back(day);
  w.hour.push_back(hour);
  w.dry_bulb.push_back(r.number(f, 6, "dry bulb temperature", true));
  if (w.dry_bulb.back() >= 99.9) w.dry_bulb.back() = kNaN;
  w.global_horizontal.push_back(r.irradiation(f, 13, "global horizontal radiation"));
  w.direct_normal.push_back(r.irradiation(f, 14, "direct normal radiation"));
  w.diffuse_horizontal.push_back(r.irradiation(f, 15, "diffuse horizontal radiation"));
  double albedo = f.size() > 32 ? r.number(f, 32, "albedo", true) : kNaN;
  if (!(albedo >= 0.0 && albedo <= 1.0)) albedo = kNaN;  // 999: missing; other values unusable
  w.albedo.push_back(albedo);
}

/// Places the records in time: consecutive hours from the first (a year's end wraps to the
/// next year's first hour), in Weather::year.
void place_records(Weather& w, const std::vector<std::size_t>& lines) {
  if (w.hours() == 0) throw InputError({w.source, "line " + std::to_string(lines.empty() ? 8 : lines.back())},
                                       "no hourly records after the 8 header lines");
  bool has_feb29 = false;
  for (std::size_t i = 0; i < w.hours(); ++i) has_feb29 |= (w.month[i] == 2 && w.day[i] == 29);
  w.year = w.record_year[0];
  if (has_feb29 && !is_valid_date(w.year, 2, 29)) w.year = 2024;
  const auto offset = static_cast<std::int64_t>(std::llround(w.location.time_zone_hours * 3600.0));
  std::int64_t year = w.year;
  std::int64_t expected = 0;  // local seconds of the next record's start
  w.start_utc.resize(w.hours());
  for (std::size_t i = 0; i < w.hours(); ++i) {
    if (i > 0 && w.month[i] == 1 && w.day[i] == 1 && w.hour[i] == 1 && !(w.month[i - 1] == 1 && w.day[i - 1] == 1))
      ++year;  // Dec 31 hour 24 -> Jan 1 hour 1
    const std::string place = "line " + std::to_string(lines[i]);
    if (!is_valid_date(year, w.month[i], w.day[i]))
      throw InputError({w.source, place + ", field 3 (day)"},
                       std::to_string(w.month[i]) + "/" + std::to_string(w.day[i]) + " is not a date in " +
                           std::to_string(year));
    const std::int64_t local = days_from_civil(year, w.month[i], w.day[i]) * 86400 + (w.hour[i] - 1) * 3600;
    if (i > 0 && local != expected)
      throw InputError({w.source, place + ", field 4 (hour)"},
                       "records must follow hour by hour: the previous record was " + std::to_string(w.month[i - 1]) +
                           "/" + std::to_string(w.day[i - 1]) + " hour " + std::to_string(w.hour[i - 1]));
    w.start_utc[i] = local - offset;
    expected = local + 3600;
  }
}

}  // namespace

Weather parse_epw(std::istream& in, const std::string& name) {
  Weather w;
  w.source = name;
  LineReader r{name};
  std::string line;
  std::vector<std::size_t> record_lines;
  while (std::getline(in, line)) {
    ++r.line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> f = split_fields(line);
    if (r.line == 1) {
      read_location(f, r, w.location);
    } else if (r.line <= 8) {
      const std::string key = trim(f[0]);
      if (key == "HOLIDAYS/DAYLIGHT SAVINGS" && f.size() > 1) w.leap_year_observed = trim(f[1]) == "Yes";
      if (key == "DATA PERIODS" && f.size() > 2) {
        const int per_hour = r.integer(f, 2, "records per hour", 1, 60);
        if (per_hour != 1) r.fail(3, "records per hour", "only hourly EPW files are read (this one has " +
                                                             std::to_string(per_hour) + " records per hour)");
      }
    } else {
      if (trim(line).empty()) continue;  // a blank last line
      read_record(f, r, w);
      record_lines.push_back(r.line);
    }
  }
  if (r.line == 0) throw InputError({name, ""}, "empty file: not an EPW weather file");
  place_records(w, record_lines);
  return w;
}

Weather read_epw(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, ""}, std::string("cannot open the weather file: ") + std::strerror(errno));
  return parse_epw(in, path);
}

}  // namespace shadow
