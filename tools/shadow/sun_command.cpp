// SPDX-License-Identifier: GPL-3.0-or-later
#include "sun_command.hpp"

#include "cli_checks.hpp"

#include <shadow/error.hpp>
#include <shadow/sun.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace {

/// Sunrise and sunset: the geometric centre of the sun at -0.8333 degrees (its upper limb on
/// the horizon lifted by 34' of refraction, the usual almanac definition), found by stepping
/// 5 minutes through the local mean solar day that holds `time` (longitude / 15 hours from UTC)
/// and bisecting each crossing to the second. Nothing for a day without one (polar day or night).
struct RiseSet {
  std::optional<shadow::UtcSeconds> rise, set;
};

RiseSet rise_set(shadow::SolarSite site, shadow::UtcSeconds time, double delta_t) {
  site.pressure = 0.0;  // the geometric elevation
  constexpr double kHorizon = -0.8333;
  auto above = [&](shadow::UtcSeconds t) {
    return shadow::solar_position(site, t, 0.0, delta_t).elevation > kHorizon;
  };
  const auto mean_offset = static_cast<shadow::UtcSeconds>(std::llround(site.longitude / 15.0 * 3600.0));
  const shadow::UtcSeconds local = time + mean_offset;
  const shadow::UtcSeconds day_start = (local - ((local % 86400) + 86400) % 86400) - mean_offset;
  RiseSet result;
  constexpr shadow::UtcSeconds kStep = 300;
  bool before = above(day_start);
  for (shadow::UtcSeconds t = day_start; t < day_start + 86400; t += kStep) {
    const shadow::UtcSeconds next = std::min<shadow::UtcSeconds>(t + kStep, day_start + 86400);
    const bool after = above(next);
    if (after != before) {
      shadow::UtcSeconds lo = t, hi = next;  // above(lo) == before, above(hi) == after
      while (hi - lo > 1) {
        const shadow::UtcSeconds mid = lo + (hi - lo) / 2;
        (above(mid) == before ? lo : hi) = mid;
      }
      if (after && !result.rise) result.rise = hi;
      if (!after) result.set = hi;
    }
    before = after;
  }
  return result;
}

std::string json_time(const std::optional<shadow::UtcSeconds>& t) {
  return t ? "\"" + shadow::format_iso8601_utc(*t) + "\"" : std::string("null");
}

}  // namespace

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
  sun.add_option("--pressure", args.pressure,
                 "Mean annual pressure in millibars, for refraction (default 1013.25; 0: no refraction, the "
                 "geometric position)")
      ->check(shadow_cli::finite_in(0.0, 5000.0));
  sun.add_option("--temperature", args.temperature,
                 "Mean annual temperature in degrees Celsius, for refraction (default 12)")
      ->check(shadow_cli::finite_in(-273.0, 1000.0));
  sun.add_option("--north-axis", args.north_axis,
                 "Degrees clockwise from true north to the model's +y (EnergyPlus's Building North Axis); "
                 "turns to_light only (default 0)")
      ->check(shadow_cli::finite_in(-360.0, 360.0));
  sun.add_option("--delta-t", args.delta_t, "TT - UT in seconds (default 69, the 2020s)")
      ->check(shadow_cli::finite_in(-1e6, 1e6));
  sun.add_flag("--rise-set", args.rise_set,
               "Also print \"sunrise\" and \"sunset\" (UTC, to the second; null when the sun does not "
               "rise or set) of the local mean solar day that holds --time: the sun's centre at -0.8333 "
               "degrees, as almanacs give them");
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
              "\"to_light\": [%.17g, %.17g, %.17g]",
              shadow::format_iso8601_utc(*time).c_str(), p.elevation, p.azimuth, p.zenith, p.to_light.x,
              p.to_light.y, p.to_light.z);
  if (args.rise_set) {
    const RiseSet r = rise_set(site, *time, args.delta_t);
    std::printf(", \"sunrise\": %s, \"sunset\": %s", json_time(r.rise).c_str(), json_time(r.set).c_str());
  }
  std::printf("}\n");
  return 0;
}
