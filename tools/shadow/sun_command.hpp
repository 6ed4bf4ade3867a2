// SPDX-License-Identifier: GPL-3.0-or-later
// The `shadow sun` subcommand: the sun's position at one place and instant, as one JSON line.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

struct SunArgs {
  double latitude = 0.0;
  double longitude = 0.0;
  std::string time;
  double elevation = 0.0;
  double pressure = 1013.25;
  double temperature = 12.0;
  double north_axis = 0.0;
  double delta_t = 69.0;
  bool rise_set = false;  ///< also print the day's sunrise and sunset
};

/// Declares the options of `shadow sun` on its subcommand.
void add_sun_options(CLI::App& sun, SunArgs& args);

/// Prints `{"time": ..., "elevation": .., "azimuth": .., "zenith": .., "to_light": [x, y, z]}`
/// on one line (with --rise-set also `"sunrise"` and `"sunset"`); returns the exit status. A time that does not parse throws shadow::InputError.
int run_sun(const SunArgs& args);
