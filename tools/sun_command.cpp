// SPDX-License-Identifier: GPL-3.0-or-later
#include "sun_command.hpp"

#include "cli_checks.hpp"

#include <shadow/error.hpp>
#include <shadow/sun.hpp>

#include <cstdio>
#include <optional>

void add_sun_options(CLI::App& sun, SunArgs& args) {
  sun.add_option("--latitude", args.latitude, "Degrees, north positive")
      ->required()
      ->check(shadow_cli::finite_in(-90.0, 90.0));
  sun.add_option("--longitude", args.longitude, "Degrees, east positive")
      ->required()
      ->check(shadow_cli::finite_in(-180.0, 180.0));
  sun.add_option("--time", args.time,
                 "ISO 8601 time with Z or an offset: 2026-06-21T12:00:00Z, 2026-06-21T14:00:00+02:00 "
                 "(fractional seconds are truncated)")
      ->required();
  sun.add_option("--elevation", args.elevation, "Metres above sea level (default 0)")
      ->check(shadow_cli::finite_in(-1000.0, 100000.0));
  sun.add_option("--pressure", args.pressure, "Mean annual pressure in millibars, for refraction (default 1013.25)")
      ->check(shadow_cli::positive_up_to(5000.0));
  sun.add_option("--temperature", args.temperature,
                 "Mean annual temperature in degrees Celsius, for refraction (default 12)")
      ->check(shadow_cli::finite_in(-273.0, 1000.0));
  sun.add_option("--north-axis", args.north_axis,
                 "Degrees clockwise from true north to the model's +y (EnergyPlus's Building North Axis); "
                 "turns to_light only (default 0)")
      ->check(shadow_cli::finite_in(-360.0, 360.0));
  sun.add_option("--delta-t", args.delta_t, "TT - UT in seconds (default 69, the 2020s)")
      ->check(shadow_cli::finite_in(-1e6, 1e6));
}

int run_sun(const SunArgs& args) {
  const std::optional<shadow::UtcSeconds> time = shadow::parse_iso8601(args.time);
  if (!time)
    throw shadow::InputError({"--time", ""},
                             "expected an ISO 8601 time that exists with Z or an offset, "
                             "YYYY-MM-DDThh:mm:ssZ or YYYY-MM-DDThh:mm:ss+hh:mm, got \"" +
                                 shadow::escape_control(args.time) + "\"");
  shadow::SolarSite site;
  site.latitude = args.latitude;
  site.longitude = args.longitude;
  site.elevation = args.elevation;
  site.pressure = args.pressure;
  site.temperature = args.temperature;
  const shadow::SunPosition p = shadow::solar_position(site, *time, args.north_axis, args.delta_t);
  std::printf("{\"time\": \"%s\", \"elevation\": %.17g, \"azimuth\": %.17g, \"zenith\": %.17g, "
              "\"to_light\": [%.17g, %.17g, %.17g]}\n",
              shadow::format_iso8601_utc(*time).c_str(), p.elevation, p.azimuth, p.zenith, p.to_light.x,
              p.to_light.y, p.to_light.z);
  return 0;
}
