// SPDX-License-Identifier: GPL-3.0-or-later
/// @file weather.hpp
/// @brief A weather year: hourly solar irradiation read from an EnergyPlus EPW file.
///
/// Plain arrays, one entry per record (hour) in file order. EPW stamps each record with the hour
/// that *ends* it, in local standard time (hour 1 = 00:00-01:00): record r covers
/// [start_utc[r], start_utc[r] + 3600 s). Irradiation values are Wh/m2 over the hour, which is
/// also the hour's mean irradiance in W/m2. A value the file flags as missing (EPW's 9999 for
/// irradiation, 999 for albedo) is NaN here. Plain data for the computation (irradiance.hpp);
/// the reader of EPW files is shadow/epw.hpp. See docs/irradiance.md.
#pragma once

#include <shadow/error.hpp>
#include <shadow/sun.hpp>

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace shadow {

/// The EPW `LOCATION` line.
struct WeatherLocation {
  std::string city, region, country, source, wmo;  ///< as written (may be empty)
  double latitude = 0.0;         ///< degrees, north positive
  double longitude = 0.0;        ///< degrees, east positive
  double time_zone_hours = 0.0;  ///< local standard time minus UTC, hours (+1 for Central Europe)
  double elevation = 0.0;        ///< metres above sea level
};

/// A weather file's hourly records.
struct Weather {
  std::string source;        ///< the file, as named to the reader
  WeatherLocation location;
  /// The calendar year the records are placed in (the sun is computed in it): the first
  /// record's year, unless the file holds 29 February and that year is not a leap year (typical
  /// years mix years), then 2024. Typical meteorological years are "any year": the sun moves by
  /// hundredths of a degree between years.
  int year = 0;
  bool leap_year_observed = false;  ///< the HOLIDAYS/DAYLIGHT SAVINGS line says `Yes`
  std::vector<int> record_year;     ///< per record: the year field as written
  std::vector<int> month;           ///< 1..12
  std::vector<int> day;             ///< 1..31
  std::vector<int> hour;            ///< 1..24: the hour that ends the record (local standard time)
  std::vector<UtcSeconds> start_utc;  ///< the record's start instant (UTC), in `year`
  std::vector<double> global_horizontal;   ///< Wh/m2 (EPW field 14); NaN when missing
  std::vector<double> direct_normal;       ///< Wh/m2 (field 15); NaN when missing
  std::vector<double> diffuse_horizontal;  ///< Wh/m2 (field 16); NaN when missing
  std::vector<double> dry_bulb;            ///< degrees C (field 7); NaN when missing
  std::vector<double> albedo;              ///< ground reflectance (field 33); NaN when missing or absent
  /// What the reader found odd but read as written: hours whose diffuse horizontal exceeds the
  /// global horizontal (diffuse is part of global) by more than measurement allows.
  std::vector<Warning> warnings;

  [[nodiscard]] std::size_t hours() const { return month.size(); }
  /// The mean of the albedo values present, or NaN when the file has none.
  [[nodiscard]] double mean_albedo() const {
    double sum = 0.0;
    std::size_t count = 0;
    for (double a : albedo)
      if (a == a) {  // not NaN
        sum += a;
        ++count;
      }
    return count == 0 ? std::numeric_limits<double>::quiet_NaN() : sum / static_cast<double>(count);
  }
};

}  // namespace shadow
