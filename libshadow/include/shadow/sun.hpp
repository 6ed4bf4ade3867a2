// SPDX-License-Identifier: GPL-3.0-or-later
/// @file sun.hpp
/// @brief The sun: its position from a site and a UTC instant, and a scene's sun period.
///
/// Conventions (docs/scene-format.md): model coordinates in metres, +z up, +x east and +y
/// north when `north_axis` is 0. `north_axis` (degrees) is EnergyPlus's Building North Axis:
/// the angle, clockwise seen from above, from true north to the model's +y axis. Azimuths are
/// measured clockwise from true north (east 90), elevations up from the horizon.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace shadow {

/// A UTC instant: seconds since 1970-01-01T00:00:00Z, without leap seconds (POSIX time).
using UtcSeconds = std::int64_t;

/// Where the sun is seen from.
struct SolarSite {
  double latitude = 0.0;      ///< degrees, north positive, in [-90, 90]
  double longitude = 0.0;     ///< degrees, east positive, in [-180, 180]
  double elevation = 0.0;     ///< metres above sea level
  double pressure = 1013.25;  ///< mean annual local pressure in millibars, for refraction
  double temperature = 12.0;  ///< mean annual local temperature in degrees Celsius, for refraction
};

/// The sun seen from a site at an instant (topocentric, refraction included).
struct SunPosition {
  double zenith = 0.0;     ///< degrees from the vertical
  double elevation = 0.0;  ///< degrees above the horizon: 90 - zenith
  double azimuth = 0.0;    ///< degrees clockwise from true north, in [0, 360)
  /// Unit vector from the scene toward the sun in model coordinates (north_axis applied).
  glm::dvec3 to_light{0.0, 0.0, 1.0};
};

/// The scene file's `sun` block: a site and the instants whose suns become directional lights.
/// Either a period (`start`..`end` local standard dates, inclusive, one instant at the start of
/// every step) or explicit `times`.
struct SunPeriod {
  SolarSite site;
  double utc_offset_hours = 0.0;  ///< local standard time minus UTC, hours (-5 for EST)
  std::string start;              ///< first local date, `YYYY-MM-DD` (empty with `times`)
  std::string end;                ///< last local date, inclusive
  int step_minutes = 60;          ///< minutes between instants, dividing a day
  std::vector<UtcSeconds> times;  ///< explicit instants (instead of a period)
  double north_axis = 0.0;        ///< degrees clockwise from true north to the model's +y
  double min_elevation = 0.0;     ///< suns at or below this elevation (degrees) are skipped
};

/// One instant of a sun period.
struct SunInstant {
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  UtcSeconds time = 0;
  SunPosition position;
  /// Index of the instant's directional light in Scene::lights, or `none` when the sun is
  /// below the horizon (at or below SunPeriod::min_elevation) and no light was added.
  std::size_t light_id = none;
};

}  // namespace shadow
