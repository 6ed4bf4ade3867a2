// SPDX-License-Identifier: GPL-3.0-or-later
/// @file epw.hpp
/// @brief Reading EnergyPlus EPW weather files into a Weather (shadow/weather.hpp).
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

}  // namespace shadow
