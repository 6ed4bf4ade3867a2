// SPDX-License-Identifier: GPL-3.0-or-later
// EnergyPlus EPW weather files (shadow/weather.hpp): the LOCATION line, the data period, then
// one record per hour. Each record's hour ends it (hour 1 = 00:00-01:00 local standard time).
// Missing values are those EPW flags (9999 for irradiation, 999 for albedo) and blank fields.
#include <shadow/epw.hpp>

#include <shadow/error.hpp>

#include "readers/weather_records.hpp"

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
  w.global_horizontal.push_back(irradiation(r, f, 13, "global horizontal radiation"));
  w.direct_normal.push_back(irradiation(r, f, 14, "direct normal radiation"));
  w.diffuse_horizontal.push_back(irradiation(r, f, 15, "diffuse horizontal radiation"));
  double albedo = f.size() > 32 ? r.number(f, 32, "albedo", true) : kNaN;
  if (!(albedo >= 0.0 && albedo <= 1.0)) albedo = kNaN;  // 999: missing; other values unusable
  w.albedo.push_back(albedo);
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
  weather_detail::place_records(w, record_lines, 8);
  return w;
}

Weather read_epw(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, ""}, std::string("cannot open the weather file: ") + std::strerror(errno));
  return parse_epw(in, path);
}

}  // namespace shadow
