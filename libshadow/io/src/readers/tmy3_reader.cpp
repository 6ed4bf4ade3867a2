// SPDX-License-Identifier: GPL-3.0-or-later
// NREL TMY3 CSV weather files (shadow/weather.hpp): a line of site metadata (USAF station, name,
// state, time zone, latitude, longitude, elevation), a line of column names, then one record per
// hour, `Date (MM/DD/YYYY)` and `Time (HH:MM)` giving the hour that ends it (01:00..24:00, local
// standard time), as in EPW. Columns are found by their names. docs/irradiance.md.
#include <shadow/epw.hpp>

#include <shadow/error.hpp>
#include <shadow/sun.hpp>

#include "readers/weather_records.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace shadow {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using weather_detail::LineReader;
using weather_detail::split_fields;
using weather_detail::trim;

/// The columns read, by their TMY3 names.
struct Columns {
  std::size_t date = 0, time = 0, ghi = 0, dni = 0, dhi = 0;
  std::size_t dry_bulb = std::string::npos, albedo = std::string::npos;  // optional
  std::vector<std::string> names;
};

void read_site(const std::vector<std::string>& f, const LineReader& r, WeatherLocation& loc) {
  if (f.size() < 7)
    r.fail(0, "", "the first line of a TMY3 file is the site: USAF,name,state,time zone,latitude,longitude,elevation "
                  "(it has " + std::to_string(f.size()) + " fields, 7 are needed)");
  loc.wmo = trim(f[0]);
  loc.city = trim(f[1]);
  loc.region = trim(f[2]);
  loc.source = "TMY3";
  loc.time_zone_hours = r.number(f, 3, "time zone");
  loc.latitude = r.number(f, 4, "latitude");
  loc.longitude = r.number(f, 5, "longitude");
  loc.elevation = r.number(f, 6, "elevation");
  if (loc.time_zone_hours < -14.0 || loc.time_zone_hours > 14.0) r.fail(4, "time zone", "not in [-14, 14] hours");
  if (loc.latitude < -90.0 || loc.latitude > 90.0) r.fail(5, "latitude", "not in [-90, 90]");
  if (loc.longitude < -180.0 || loc.longitude > 180.0) r.fail(6, "longitude", "not in [-180, 180]");
  if (loc.elevation < -1000.0 || loc.elevation > 100000.0) r.fail(7, "elevation", "not in [-1000, 100000] metres");
}

Columns read_columns(const std::vector<std::string>& f, const LineReader& r) {
  Columns c;
  for (const std::string& name : f) c.names.push_back(trim(name));
  const auto find = [&](const char* name, bool required) {
    const auto it = std::find(c.names.begin(), c.names.end(), name);
    if (it == c.names.end()) {
      if (required) r.fail(0, "", std::string("no column named '") + name + "' (the second line of a TMY3 file names the columns)");
      return std::string::npos;
    }
    return static_cast<std::size_t>(it - c.names.begin());
  };
  c.date = find("Date (MM/DD/YYYY)", true);
  c.time = find("Time (HH:MM)", true);
  c.ghi = find("GHI (W/m^2)", true);
  c.dni = find("DNI (W/m^2)", true);
  c.dhi = find("DHI (W/m^2)", true);
  c.dry_bulb = find("Dry-bulb (C)", false);
  c.albedo = find("Alb (unitless)", false);
  return c;
}

/// Digits only, as a whole number; -1 when not.
int digits(const std::string& text) {
  if (text.empty() || text.size() > 4) return -1;
  int value = 0;
  for (char ch : text) {
    if (!std::isdigit(static_cast<unsigned char>(ch))) return -1;
    value = value * 10 + (ch - '0');
  }
  return value;
}

/// A value of the record that may be missing: blank, or NSRDB's -9900 (any value <= -9900).
double value_or_missing(const LineReader& r, const std::vector<std::string>& f, std::size_t index, const Columns& c) {
  const double value = r.number(f, index, c.names[index], true);
  return value <= -9900.0 ? kNaN : value;
}

double irradiation(const LineReader& r, const std::vector<std::string>& f, std::size_t index, const Columns& c) {
  const double value = value_or_missing(r, f, index, c);
  if (value < 0.0) r.fail(index + 1, c.names[index], "negative irradiation " + trim(f[index]));
  return value;
}

void read_record(const std::vector<std::string>& f, const LineReader& r, const Columns& c, Weather& w,
                 weather_detail::AlbedoReader& albedo_reader) {
  if (c.date >= f.size()) r.fail(c.date + 1, c.names[c.date], "the line has only " + std::to_string(f.size()) + " fields");
  const std::string date = trim(f[c.date]);
  const std::size_t s1 = date.find('/'), s2 = date.find('/', s1 == std::string::npos ? 0 : s1 + 1);
  const int month = s1 == std::string::npos ? -1 : digits(date.substr(0, s1));
  const int day = s2 == std::string::npos ? -1 : digits(date.substr(s1 + 1, s2 - s1 - 1));
  const int year = s2 == std::string::npos ? -1 : digits(date.substr(s2 + 1));
  if (month < 1 || month > 12 || day < 1 || day > 31 || year < 0)
    r.fail(c.date + 1, c.names[c.date], "'" + date + "' is not a date MM/DD/YYYY");
  if (c.time >= f.size()) r.fail(c.time + 1, c.names[c.time], "the line has only " + std::to_string(f.size()) + " fields");
  const std::string time = trim(f[c.time]);
  const std::size_t colon = time.find(':');
  const int hour = colon == std::string::npos ? -1 : digits(time.substr(0, colon));
  const int minute = colon == std::string::npos ? -1 : digits(time.substr(colon + 1));
  if (hour < 1 || hour > 24 || minute != 0)
    r.fail(c.time + 1, c.names[c.time], "'" + time + "' is not an hour 01:00..24:00 (the hour ending the record)");
  w.record_year.push_back(year);
  w.month.push_back(month);
  w.day.push_back(day);
  w.hour.push_back(hour);
  w.global_horizontal.push_back(irradiation(r, f, c.ghi, c));
  w.direct_normal.push_back(irradiation(r, f, c.dni, c));
  w.diffuse_horizontal.push_back(irradiation(r, f, c.dhi, c));
  w.dry_bulb.push_back(c.dry_bulb == std::string::npos ? kNaN : value_or_missing(r, f, c.dry_bulb, c));
  // (missing; 0: not measured, AlbedoReader; other values outside (0, 1] unusable)
  w.albedo.push_back(albedo_reader(c.albedo == std::string::npos ? kNaN : value_or_missing(r, f, c.albedo, c), r.line));
}

/// A TMY3 file is a typical year: NREL's 8,760 records run from 1 January hour 1 to 31 December
/// hour 24, and it has no header that could state a shorter period. Records that begin at that
/// first hour and stop more than a day before the last are a file cut short (a download or a
/// copy that stopped), which would otherwise read as a shorter year without a word: an error.
/// A day or less is a warning, as for EPW. Records that begin later are read as they are (part
/// of a year, made so on purpose).
void check_year_end(Weather& w, const std::vector<std::size_t>& lines) {
  // (A year of records or more: whole, even where it runs on into the next year.)
  if (w.hours() == 0 || w.hours() >= 8760 || w.month[0] != 1 || w.day[0] != 1 || w.hour[0] != 1) return;
  const std::size_t last = w.hours() - 1;
  // Days to 31 December in a year of 365, as a typical year has, or of 366 where the records
  // hold 29 February (dates alone: the records' years are those of their months' sources).
  bool leap = false;
  for (std::size_t r = 0; r <= last && !leap; ++r) leap = w.month[r] == 2 && w.day[r] == 29;
  const int calendar = leap ? 2024 : 2001;
  const auto days = days_from_civil(calendar, 12, 31) - days_from_civil(calendar, w.month[last], w.day[last]);
  const auto missing = days * 24 + 24 - w.hour[last];
  if (missing <= 0) return;
  const std::string problem = "the records stop at " + std::to_string(w.month[last]) + "/" + std::to_string(w.day[last]) +
                              " hour " + std::to_string(w.hour[last]) +
                              ", but a TMY3 year runs from 1/1 hour 1 to 12/31 hour 24: " + std::to_string(missing) +
                              " hours missing";
  if (missing <= 24) {
    w.warnings.push_back({{w.source, "line " + std::to_string(lines.back())}, problem + "; read as it is"});
    return;
  }
  throw InputError({w.source, "line " + std::to_string(lines.back())},
                   problem + ": the file is cut short (" + std::to_string(w.hours()) +
                       " hourly records; for part of the year, read the whole file and choose the days: "
                       "`shadow irradiance --from/--to`)");
}

bool ends_with_csv(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  for (char& ch : tail) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return tail == ".csv";
}

}  // namespace

Weather parse_tmy3(std::istream& in, const std::string& name) {
  Weather w;
  w.source = name;
  LineReader r{name};
  std::string line;
  Columns columns;
  std::vector<std::size_t> record_lines;
  std::size_t record_fields = 0, last_short = 0;
  weather_detail::AlbedoReader albedo_reader;
  while (std::getline(in, line)) {
    ++r.line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (r.line == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
    const std::vector<std::string> f = split_fields(line, /*quotes=*/true);
    if (r.line == 1) {
      read_site(f, r, w.location);
    } else if (r.line == 2) {
      columns = read_columns(f, r);
    } else {
      if (trim(line).empty()) continue;  // a blank last line
      // A last record with fewer fields than the first is a line cut in the middle (a file that
      // stopped): its cut field would read as a smaller number.
      if (record_lines.empty()) record_fields = f.size();
      last_short = f.size() < record_fields ? f.size() : 0;
      read_record(f, r, columns, w, albedo_reader);
      record_lines.push_back(r.line);
    }
  }
  if (r.line == 0) throw InputError({name, ""}, "empty file: not a TMY3 weather file");
  if (r.line == 1) throw InputError({name, "line 2"}, "the second line of a TMY3 file names the columns; the file ends before it");
  weather_detail::check_last_record_fields(name, record_lines, last_short, record_fields);
  weather_detail::RecordFields fields;
  fields.day_field = columns.date + 1;
  fields.day_name = "Date (MM/DD/YYYY)";
  fields.hour_field = columns.time + 1;
  fields.hour_name = "Time (HH:MM)";
  weather_detail::place_records(w, record_lines, 2, fields);
  check_year_end(w, record_lines);
  if (columns.albedo != std::string::npos)
    albedo_reader.warn_zero_albedo(w, "field " + std::to_string(columns.albedo + 1) + " (" + columns.names[columns.albedo] + ")");
  weather_detail::check_diffuse_within_global(w, record_lines);
  return w;
}

Weather read_tmy3(const std::string& path) {
  std::istringstream in(weather_detail::read_weather_file(path));
  return parse_tmy3(in, path);
}

Weather read_weather(const std::string& path) { return ends_with_csv(path) ? read_tmy3(path) : read_epw(path); }

}  // namespace shadow
