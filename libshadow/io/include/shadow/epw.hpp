// SPDX-License-Identifier: GPL-3.0-or-later
/// @file epw.hpp
/// @brief Reading weather files into a Weather (shadow/weather.hpp): EnergyPlus EPW and NREL
/// TMY3 CSV.
#pragma once

#include <shadow/weather.hpp>

#include <istream>
#include <string>

namespace shadow {

/// Reads an EnergyPlus EPW file (the 8 header lines, then hourly records).
/// @throws InputError naming `path`, the line and the field (`line 12, field 15 (direct normal
/// radiation)`) for an unreadable file, a malformed header, a record out of order, a date that
/// does not exist, a value that is not a number or is out of EPW's range, or a file that is not
/// hourly.
Weather read_epw(const std::string& path);

/// As read_epw, from a stream; `name` is the file named in errors.
Weather parse_epw(std::istream& in, const std::string& name);

/// Reads an NREL TMY3 CSV file: line 1 the site (USAF station, name, state, time zone in hours,
/// latitude, longitude, elevation in metres; the name may be quoted), line 2 the column names,
/// then one record per hour. Columns are found by name: `Date (MM/DD/YYYY)`, `Time (HH:MM)` (the
/// hour that ends the record, 01:00..24:00 local standard time, as EPW's hour field), `GHI
/// (W/m^2)`, `DNI (W/m^2)`, `DHI (W/m^2)`, and when present `Dry-bulb (C)` and `Alb (unitless)`.
/// A blank value or one of -9900 or below (NSRDB's missing flag) is missing (NaN). The records
/// are placed in time as EPW's (Weather::year); location.wmo holds the USAF number, city the
/// name, region the state, source `TMY3`.
/// @throws InputError naming `path`, the line and the field (`line 14, field 8 (DNI (W/m^2)):
/// 'x' is not a number`), or the column missing from line 2.
Weather read_tmy3(const std::string& path);

/// As read_tmy3, from a stream; `name` is the file named in errors.
Weather parse_tmy3(std::istream& in, const std::string& name);

/// read_tmy3 for a path ending in `.csv` (any case), read_epw for any other.
/// @throws InputError as those
Weather read_weather(const std::string& path);

}  // namespace shadow
