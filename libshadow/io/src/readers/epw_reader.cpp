// SPDX-License-Identifier: GPL-3.0-or-later
// EnergyPlus EPW weather files (shadow/weather.hpp): the LOCATION line, the data period, then
// one record per hour. Each record's hour ends it (hour 1 = 00:00-01:00 local standard time).
// Missing values are those EPW flags (9999 for irradiation, 999 for albedo) and blank fields.
#include <shadow/epw.hpp>

#include <shadow/error.hpp>
#include <shadow/sun.hpp>

#include "readers/weather_records.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace shadow {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using weather_detail::AlbedoReader;
using weather_detail::LineReader;
using weather_detail::split_fields;
using weather_detail::trim;

/// An irradiation field: >= 9999 (or blank) is missing; negative is an error.
double irradiation(const LineReader& r, const std::vector<std::string>& fields, std::size_t index, const char* what) {
  const double value = r.number(fields, index, what, true);
  if (std::isnan(value) || value >= 9999.0) return kNaN;
  if (value < 0.0) r.fail(index + 1, what, "negative irradiation " + trim(fields[index]));
  return value;
}

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

/// One hourly record appended to `w`.
void read_record(const std::vector<std::string>& f, const LineReader& r, Weather& w, AlbedoReader& albedo_reader) {
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
  w.global_horizontal.push_back(irradiation(r, f, 13, "global horizontal radiation"));
  w.direct_normal.push_back(irradiation(r, f, 14, "direct normal radiation"));
  w.diffuse_horizontal.push_back(irradiation(r, f, 15, "diffuse horizontal radiation"));
  // (999: missing; 0: not measured, AlbedoReader; other values outside (0, 1] unusable)
  w.albedo.push_back(albedo_reader(f.size() > 32 ? r.number(f, 32, "albedo", true) : kNaN, r.line));
}

/// A DATA PERIODS date: `M/D`, `M/D/YYYY` or `YYYY/M/D` (all written by real files'
/// generators); month 0 when the text is none of these, year 0 when it names none.
struct PeriodDate {
  int year = 0, month = 0, day = 0;
  [[nodiscard]] int key() const { return month * 100 + day; }
};

PeriodDate period_date(const std::string& text) {
  std::vector<int> parts;
  std::string digits;
  for (char c : trim(text) + "/") {
    if (c == '/') {
      if (digits.empty() || digits.size() > 4) return {};
      parts.push_back(std::stoi(digits));
      digits.clear();
    } else if (c >= '0' && c <= '9') {
      digits += c;
    } else if (c != ' ') {
      return {};
    }
  }
  PeriodDate date;
  if (parts.size() == 2) date = {0, parts[0], parts[1]};
  if (parts.size() == 3) date = parts[0] > 31 ? PeriodDate{parts[0], parts[1], parts[2]} : PeriodDate{parts[2], parts[0], parts[1]};
  if (date.month < 1 || date.month > 12 || date.day < 1 || date.day > 31) return {};
  return date;
}

/// What the header's DATA PERIODS line says the records cover: from the first period's start
/// (hour 1) to the last period's end (hour 24). Month 0: not stated in a form read here.
struct DataPeriod {
  std::size_t line = 0;
  PeriodDate start, end;
};

std::string date_text(int month, int day) { return std::to_string(month) + "/" + std::to_string(day); }

/// The records should cover what DATA PERIODS states: they follow hour by hour (place_records),
/// so records that begin at the period's start and stop before its end miss the hours between,
/// and records that end at the period's end but begin after its start miss the hours before.
/// More than a day missing is a file cut short, or one that lost its beginning (a download or a
/// copy that stopped, an edit), which otherwise reads as a shorter year without a word: an
/// error. A day or less is a warning (converters of leap years are said to drop 31 December).
/// Records that match neither end of the period do not follow the header; they are read as they
/// are. The period's dates are placed in the calendar years of the records, from the end that
/// matches: checking for a cut end, its start in the first record's year; checking for a lost
/// beginning, its end in the last record's year. The other date lies as many years away as the
/// period's years say, else in the same year, or the next when the period runs past 31 December
/// (7/1 to 6/30).
void check_period(Weather& w, const DataPeriod& period, const std::vector<std::size_t>& lines) {
  if (period.start.month == 0 || period.end.month == 0) return;
  std::int64_t years = period.end.key() < period.start.key() ? 1 : 0;
  if (period.start.year > 0 && period.end.year - period.start.year >= years) years = period.end.year - period.start.year;
  const auto offset = static_cast<std::int64_t>(std::llround(w.location.time_zone_hours * 3600.0));
  const std::size_t last = w.hours() - 1;
  const std::int64_t begins = w.start_utc[0] + offset, ends = w.start_utc[last] + offset + 3600;  // local seconds
  const std::int64_t last_second = ends - 1;  // the day of the last record's last second
  const std::int64_t last_day = last_second >= 0 ? last_second / 86400 : -((-last_second + 86399) / 86400);
  // The period [start, end) in local seconds with its start in `start_year`; false for a date
  // that is not one there (29 February of a common year: not a period these records follow).
  const auto place = [&](std::int64_t start_year, std::int64_t& start, std::int64_t& end) {
    if (!is_valid_date(start_year, period.start.month, period.start.day) ||
        !is_valid_date(start_year + years, period.end.month, period.end.day))
      return false;
    start = days_from_civil(start_year, period.start.month, period.start.day) * 86400;
    end = (days_from_civil(start_year + years, period.end.month, period.end.day) + 1) * 86400;
    return true;
  };
  std::int64_t start = 0, end = 0, start_b = 0, end_b = 0;
  const bool from_start = place(w.year, start, end);
  const bool from_end = place(civil_from_days(last_day).year - years, start_b, end_b);
  // A day or less missing: a warning; more: the error, with the fix when it was on purpose.
  const auto missing_hours = [&](std::int64_t missing, std::size_t line, const std::string& problem,
                                 const std::string& what, const std::string& fix) {
    if (missing <= 24) {
      w.warnings.push_back({{w.source, "line " + std::to_string(line)}, problem + "; read as it is"});
      return;
    }
    throw InputError({w.source, "line " + std::to_string(line)},
                     problem + ": " + what + " (" + std::to_string(w.hours()) +
                         " hourly records; if it was shortened on purpose, set the DATA PERIODS " + fix + ")");
  };
  const auto hours_text = [](std::int64_t missing) { return ": " + std::to_string(missing) + " hours missing"; };
  if (from_start && begins == start && ends < end) {
    const std::int64_t missing = (end - ends) / 3600;
    missing_hours(missing, lines.back(),
                  "the records stop at " + date_text(w.month[last], w.day[last]) + " hour " +
                      std::to_string(w.hour[last]) + ", but DATA PERIODS (line " + std::to_string(period.line) +
                      ") runs the data to " + date_text(period.end.month, period.end.day) + " hour 24" + hours_text(missing),
                  "the file is cut short", "end to " + date_text(w.month[last], w.day[last]));
  } else if (from_end && ends == end_b && begins > start_b) {
    const std::int64_t missing = (begins - start_b) / 3600;
    missing_hours(missing, lines.front(),
                  "the records begin at " + date_text(w.month[0], w.day[0]) + " hour " + std::to_string(w.hour[0]) +
                      ", but DATA PERIODS (line " + std::to_string(period.line) + ") starts the data at " +
                      date_text(period.start.month, period.start.day) + " hour 1" + hours_text(missing),
                  "the file lost its beginning", "start to " + date_text(w.month[0], w.day[0]));
  }
}

}  // namespace

Weather parse_epw(std::istream& in, const std::string& name) {
  Weather w;
  w.source = name;
  LineReader r{name};
  std::string line;
  std::vector<std::size_t> record_lines;
  std::size_t record_fields = 0, last_short = 0;
  DataPeriod period;
  AlbedoReader albedo_reader;
  while (std::getline(in, line)) {
    ++r.line;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (r.line == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
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
        const int periods = r.integer(f, 1, "number of data periods", 1, 366);
        const std::size_t end_field = 6 + 4 * static_cast<std::size_t>(periods - 1);
        if (f.size() > end_field) {
          period.line = r.line;
          period.start = period_date(f[5]);
          period.end = period_date(f[end_field]);
        }
      }
    } else {
      if (trim(line).empty()) continue;  // a blank last line
      // A last record with fewer fields than the first is a line cut in the middle (a file that
      // stopped): its cut field would read as a smaller number. (Records before it may leave out
      // trailing fields they do not need.)
      if (record_lines.empty()) record_fields = f.size();
      last_short = f.size() < record_fields ? f.size() : 0;
      read_record(f, r, w, albedo_reader);
      record_lines.push_back(r.line);
    }
  }
  if (r.line == 0) throw InputError({name, ""}, "empty file: not an EPW weather file");
  weather_detail::check_last_record_fields(name, record_lines, last_short, record_fields);
  weather_detail::place_records(w, record_lines, 8);
  check_period(w, period, record_lines);
  albedo_reader.warn_zero_albedo(w, "field 33 (albedo)");
  weather_detail::check_diffuse_within_global(w, record_lines);
  return w;
}

Weather read_epw(const std::string& path) {
  std::istringstream in(weather_detail::read_weather_file(path));
  return parse_epw(in, path);
}

}  // namespace shadow
