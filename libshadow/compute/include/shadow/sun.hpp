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
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace shadow {

/// A UTC instant: seconds since 1970-01-01T00:00:00Z, without leap seconds (POSIX time).
using UtcSeconds = std::int64_t;

/// Where the sun is seen from.
struct SolarSite {
  double latitude = 0.0;      ///< degrees, north positive, in [-90, 90]
  double longitude = 0.0;     ///< degrees, east positive, in [-180, 180]
  double elevation = 0.0;     ///< metres above sea level
  double pressure = 1013.25;  ///< mean annual local pressure in millibars, for refraction; 0: none (geometric position)
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
  /// Where a period's instants fall in their steps. False: at each step's start (00:00, 01:00,
  /// ... local standard time). True: where EnergyPlus takes the sun for its time steps
  /// (SolarShading.cc, FigureSunCosines): at each step's end for a step shorter than an hour
  /// (00:15, 00:30, ..., 24:00 with 15 minutes), mid-step otherwise (00:30, 01:30, ... with an
  /// hour), so that energyplus-shading.csv holds, for each time step, the sun EnergyPlus would
  /// use there. Set by the EnergyPlus reader (a model's RunPeriod and Timestep) and, unless the
  /// scene's `sun` block says otherwise (`"energyplus_times"`), for any scene that writes
  /// energyplus-shading.csv.
  bool energyplus_times = false;
  std::vector<UtcSeconds> times;  ///< explicit instants (instead of a period)
  double north_axis = 0.0;        ///< degrees clockwise from true north to the model's +y
  double min_elevation = 0.0;     ///< suns at or below this elevation (degrees) are skipped
  /// The sun's angular diameter in degrees given to every sun light (Light::angular_diameter):
  /// 0, the default, keeps them points; about 0.53 makes them the sun's disk, with exact
  /// penumbrae (docs/area-lights.md). In [0, 60].
  double angular_diameter = 0.0;
  /// TT - UT1 in seconds for solar_position (about 69 s in the 2020s; docs/sun.md).
  double delta_t = 69.0;
  /// The time zone as the input named it (`UTC`, `UTC+05:30`); empty when `utc_offset_hours`
  /// was given as a number. Informative only: `utc_offset_hours` is what counts.
  std::string time_zone;
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

struct Scene;

// ---- solar position ----------------------------------------------------------------------------

/// The sun seen from `site` at `time`: NREL's Solar Position Algorithm (Reda & Andreas 2004,
/// NREL/TP-560-34302), topocentric, with atmospheric refraction from the site's pressure and
/// temperature. Stated accuracy +-0.0003 degrees for the years -2000..6000 (docs/sun.md).
/// Refraction is applied while the geometric elevation is at or above -0.8333 degrees (the
/// sun's upper limb on the refracted horizon); below that the elevation is the geometric one.
/// `north_axis_degrees` only turns `to_light` into model coordinates (EnergyPlus's Building
/// North Axis: clockwise from true north to the model's +y); zenith, elevation and azimuth stay
/// relative to true north. `delta_t_seconds` is TT - UT1.
/// Never throws; non-finite input gives non-finite output.
SunPosition solar_position(const SolarSite& site, UtcSeconds time, double north_axis_degrees = 0.0,
                           double delta_t_seconds = 69.0);

/// Unit vector toward a sun at `elevation_degrees` above the horizon and `azimuth_degrees`
/// clockwise from true north, in model coordinates whose +y is `north_axis_degrees` clockwise
/// from true north: (cos e sin a, cos e cos a, sin e) with a = azimuth - north_axis.
glm::dvec3 sun_to_light(double elevation_degrees, double azimuth_degrees,
                        double north_axis_degrees = 0.0);

// ---- times -------------------------------------------------------------------------------------

/// Days since 1970-01-01 of a proleptic Gregorian date (no range limit within int64; month 1..12,
/// day 1..31, not checked: use is_valid_date).
std::int64_t days_from_civil(std::int64_t year, int month, int day);

/// A proleptic Gregorian calendar date.
struct CivilDate {
  std::int64_t year = 1970;
  int month = 1;  ///< 1..12
  int day = 1;    ///< 1..31
};

/// The date `days` days after 1970-01-01 (inverse of days_from_civil).
CivilDate civil_from_days(std::int64_t days);

/// True when `day` exists in `month` of `year` (leap years of the Gregorian calendar).
bool is_valid_date(std::int64_t year, int month, int day);

/// Parses an ISO 8601 date and time with its offset from UTC, `YYYY-MM-DDThh:mm:ssZ` or
/// `YYYY-MM-DDThh:mm:ss+hh:mm` (also `-hh:mm`, `+hhmm`, `+hh`; seconds may be left out:
/// `YYYY-MM-DDThh:mmZ`). Years 0000..9999. Fractional seconds (`12:00:00.75Z`) are accepted
/// and truncated to the whole second. `24:00:00` is the end of the day (the next day's
/// 00:00:00); any other hour 24, minute 60 or second 60 (leap seconds: POSIX time has none),
/// and dates that do not exist (2026-02-30) are rejected. A time without `Z` or an offset is
/// rejected (use the overload with a local offset). Thread-safe, no time zone database.
std::optional<UtcSeconds> parse_iso8601(std::string_view text);

/// As parse_iso8601(text), but a time without `Z` or an offset is local time `local_offset_minutes`
/// ahead of UTC (local standard time with the scene's utc_offset).
std::optional<UtcSeconds> parse_iso8601(std::string_view text, int local_offset_minutes);

/// `YYYY-MM-DDThh:mm:ssZ` (years outside 0000..9999 are written with a sign and more digits).
std::string format_iso8601_utc(UtcSeconds time);

/// Parses a `YYYY-MM-DD` date: days since 1970-01-01, or nothing when malformed or not a date.
std::optional<std::int64_t> parse_iso_date(std::string_view text);

/// The offset from UTC in minutes of a time zone written `UTC`, `Z`, `UTC+hh:mm`, `UTC-hh:mm`,
/// `UTC+h` (also `GMT...`); nothing for anything else, IANA names (`Europe/Paris`) included:
/// their offsets change with daylight saving, and the library works in local standard time.
std::optional<int> parse_utc_offset(std::string_view time_zone);

// ---- sun periods -------------------------------------------------------------------------------

/// The most instants a sun period may expand to.
inline constexpr std::size_t max_sun_instants = 1'000'000;

/// Checks a sun period: latitude in [-90, 90], longitude in [-180, 180], elevation in
/// [-1000, 100000] metres, pressure in [0, 5000] millibars (0: no refraction), temperature in (-273.15, 1000] C, utc_offset in [-14, 14] and a whole number of minutes,
/// valid `start` <= `end` dates and a step dividing 1440 (or strictly increasing `times`, not
/// both), at most max_sun_instants instants, finite north_axis and delta_t, min_elevation in
/// [-90, 90].
/// @throws InputError naming `file` and the place, `place.step_minutes` say (`place` is the
/// block's JSON path, `sun` in a scene file).
void check_sun_period(const SunPeriod& period, const std::string& file = {},
                      const std::string& place = "sun");

/// Every instant of `period` in time order with its sun's position: for a period, one instant per
/// step of each local standard day from `start` to `end` inclusive, at the step's start (or, with
/// `energyplus_times`, its end, or its middle for steps of an hour or more) (UTC = local -
/// utc_offset); or the `times`. light_id is left SunInstant::none. The positions are computed on
/// `threads` threads (0: every hardware thread; the instants are the same on any count): a year
/// at one-minute steps is half a million positions, seconds of one thread.
/// @throws InputError (check_sun_period, with an empty file name)
std::vector<SunInstant> expand_sun_period(const SunPeriod& period, unsigned threads);
/// expand_sun_period on one thread.
std::vector<SunInstant> expand_sun_period(const SunPeriod& period);

/// The name of the directional light of the sun at `time`: `sun 2026-06-21T12:00:00Z`.
std::string sun_light_name(UtcSeconds time);

/// Appends a directional light (intensity 1, white) to `scene.lights` for each instant of
/// `period` whose sun is above `period.min_elevation`, and sets Scene::sun and
/// Scene::sun_instants (light_id set for those, SunInstant::none for the others). The instants
/// below are those with light_id == none. When no sun is above, a Scene::warnings entry says so.
/// Call it once per scene: a second call would append the suns again.
/// The positions are computed on `threads` threads, as expand_sun_period's.
/// @throws InputError (check_sun_period with the scene's source as file; a light name taken)
void add_sun_lights(Scene& scene, const SunPeriod& period, unsigned threads);
/// add_sun_lights on one thread.
void add_sun_lights(Scene& scene, const SunPeriod& period);

/// Replaces the scene's sun period: removes the directional lights an earlier add_sun_lights
/// appended (the lights named by Scene::sun_instants; other lights keep their order), then
/// add_sun_lights(scene, period). `shadow series --from/--to/--step` uses it to run a model's
/// own site over another period.
/// @throws InputError like add_sun_lights
void replace_sun_lights(Scene& scene, const SunPeriod& period, unsigned threads);
/// replace_sun_lights on one thread.
void replace_sun_lights(Scene& scene, const SunPeriod& period);

}  // namespace shadow
