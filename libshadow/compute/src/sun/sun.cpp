// SPDX-License-Identifier: GPL-3.0-or-later
// The sun's position in model coordinates, ISO 8601 times (days-from-civil arithmetic: no
// timegm, no TZ environment, so thread-safe and portable), and sun periods expanded into
// instants and directional lights.
#include "common/format.hpp"
#include "runtime/parallel.hpp"
#include "sun/spa.hpp"

#include <shadow/error.hpp>
#include <shadow/scene.hpp>
#include <shadow/sun.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

namespace shadow {

using detail::format_number;  // common/format.hpp

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  std::int64_t q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

/// Reads exactly `n` decimal digits at `pos`; advances `pos`.
bool digits(std::string_view s, std::size_t& pos, std::size_t n, int& value) {
  if (pos + n > s.size()) return false;
  value = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const char c = s[pos + i];
    if (c < '0' || c > '9') return false;
    value = value * 10 + (c - '0');
  }
  pos += n;
  return true;
}

bool take(std::string_view s, std::size_t& pos, char c) {
  if (pos < s.size() && s[pos] == c) {
    ++pos;
    return true;
  }
  return false;
}

/// `YYYY-MM-DD` at `pos`: days since 1970-01-01.
std::optional<std::int64_t> read_date(std::string_view s, std::size_t& pos) {
  int year = 0, month = 0, day = 0;
  if (!digits(s, pos, 4, year) || !take(s, pos, '-') || !digits(s, pos, 2, month) ||
      !take(s, pos, '-') || !digits(s, pos, 2, day))
    return std::nullopt;
  if (!is_valid_date(year, month, day)) return std::nullopt;
  return days_from_civil(year, month, day);
}

/// `+hh:mm`, `-hh:mm`, `+hhmm` or `+hh` at `pos` (the whole rest of `s`): minutes east of UTC.
std::optional<int> read_offset(std::string_view s, std::size_t pos) {
  if (pos >= s.size() || (s[pos] != '+' && s[pos] != '-')) return std::nullopt;
  const int sign = s[pos] == '-' ? -1 : 1;
  ++pos;
  int hours = 0, minutes = 0;
  if (!digits(s, pos, 2, hours)) return std::nullopt;
  if (pos < s.size()) {
    take(s, pos, ':');
    if (!digits(s, pos, 2, minutes)) return std::nullopt;
  }
  if (pos != s.size() || hours > 23 || minutes > 59) return std::nullopt;
  return sign * (hours * 60 + minutes);
}

}  // namespace

// ---- solar position ----------------------------------------------------------------------------

glm::dvec3 sun_to_light(double elevation_degrees, double azimuth_degrees, double north_axis_degrees) {
  // The model's +y is `north_axis` clockwise from north, so a sun at true azimuth A is at
  // A - north_axis clockwise from the model's +y.
  const double e = elevation_degrees * kRad, a = (azimuth_degrees - north_axis_degrees) * kRad;
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

SunPosition solar_position(const SolarSite& site, UtcSeconds time, double north_axis_degrees,
                           double delta_t_seconds) {
  // Julian day of a POSIX time: days since 1970-01-01T00Z plus JD 2440587.5 (that instant).
  // Whole days and the second of the day apart, so no digits are lost for far-off years.
  const std::int64_t days = floor_div(time, 86400);
  const double jd = (static_cast<double>(days) + 2440587.5) +
                    static_cast<double>(time - days * 86400) / 86400.0;
  const detail::SpaSteps s = detail::spa(site, jd, delta_t_seconds);
  SunPosition p;
  p.zenith = s.zenith;
  p.elevation = 90.0 - s.zenith;
  p.azimuth = s.azimuth;
  p.to_light = sun_to_light(p.elevation, p.azimuth, north_axis_degrees);
  return p;
}

// ---- times -------------------------------------------------------------------------------------

// Howard Hinnant's days-from-civil arithmetic on 400-year eras (the published algorithm,
// written here for int64 years).
std::int64_t days_from_civil(std::int64_t year, int month, int day) {
  year -= month <= 2 ? 1 : 0;
  const std::int64_t era = floor_div(year, 400);
  const std::int64_t year_of_era = year - era * 400;                                 // [0, 399]
  const std::int64_t day_of_year = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;  // [0, 365]
  const std::int64_t day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;
}

CivilDate civil_from_days(std::int64_t days) {
  days += 719468;
  const std::int64_t era = floor_div(days, 146097);
  const std::int64_t day_of_era = days - era * 146097;  // [0, 146096]
  const std::int64_t year_of_era =
      (day_of_era - day_of_era / 1460 + day_of_era / 36524 - day_of_era / 146096) / 365;  // [0, 399]
  const std::int64_t day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
  const std::int64_t mp = (5 * day_of_year + 2) / 153;  // [0, 11], March first
  CivilDate date;
  date.day = static_cast<int>(day_of_year - (153 * mp + 2) / 5 + 1);
  date.month = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  date.year = year_of_era + era * 400 + (date.month <= 2 ? 1 : 0);
  return date;
}

bool is_valid_date(std::int64_t year, int month, int day) {
  if (month < 1 || month > 12 || day < 1) return false;
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return day <= kDays[month - 1] + (month == 2 && leap ? 1 : 0);
}

std::optional<std::int64_t> parse_iso_date(std::string_view text) {
  std::size_t pos = 0;
  const std::optional<std::int64_t> days = read_date(text, pos);
  if (!days || pos != text.size()) return std::nullopt;
  return days;
}

namespace {

/// The common parser: `local_offset_minutes` is used when the text has no zone designator
/// (nothing: such a text is rejected).
std::optional<UtcSeconds> parse_time(std::string_view s, std::optional<int> local_offset_minutes) {
  std::size_t pos = 0;
  const std::optional<std::int64_t> days = read_date(s, pos);
  if (!days || !take(s, pos, 'T')) return std::nullopt;
  int hour = 0, minute = 0, second = 0;
  if (!digits(s, pos, 2, hour) || !take(s, pos, ':') || !digits(s, pos, 2, minute))
    return std::nullopt;
  if (take(s, pos, ':')) {
    if (!digits(s, pos, 2, second)) return std::nullopt;
    if (take(s, pos, '.') || take(s, pos, ',')) {  // fractional seconds: truncated
      const std::size_t first = pos;
      while (pos < s.size() && s[pos] >= '0' && s[pos] <= '9') ++pos;
      if (pos == first) return std::nullopt;
      if (hour == 24 && s.substr(first, pos - first).find_first_not_of('0') != std::string_view::npos)
        return std::nullopt;
    }
  }
  // 24:00:00 is the end of the day; other hour-24 times, minute 60 and leap seconds are not.
  if (hour > 24 || minute > 59 || second > 59 || (hour == 24 && (minute != 0 || second != 0)))
    return std::nullopt;
  int offset = 0;
  if (pos == s.size()) {
    if (!local_offset_minutes) return std::nullopt;
    offset = *local_offset_minutes;
  } else if (s[pos] == 'Z') {
    if (pos + 1 != s.size()) return std::nullopt;
  } else {
    const std::optional<int> o = read_offset(s, pos);
    if (!o) return std::nullopt;
    offset = *o;
  }
  return *days * 86400 + hour * 3600 + minute * 60 + second - std::int64_t{offset} * 60;
}

}  // namespace

std::optional<UtcSeconds> parse_iso8601(std::string_view text) { return parse_time(text, std::nullopt); }

std::optional<UtcSeconds> parse_iso8601(std::string_view text, int local_offset_minutes) {
  return parse_time(text, local_offset_minutes);
}

std::string format_iso8601_utc(UtcSeconds time) {
  const std::int64_t days = floor_div(time, 86400);
  const std::int64_t second_of_day = time - days * 86400;
  const CivilDate date = civil_from_days(days);
  char buffer[64];
  const bool plain_year = date.year >= 0 && date.year <= 9999;
  std::snprintf(buffer, sizeof buffer, plain_year ? "%04lld-%02d-%02dT%02d:%02d:%02dZ" : "%+05lld-%02d-%02dT%02d:%02d:%02dZ",
                static_cast<long long>(date.year), date.month, date.day,
                static_cast<int>(second_of_day / 3600), static_cast<int>(second_of_day / 60 % 60),
                static_cast<int>(second_of_day % 60));
  return buffer;
}

std::optional<int> parse_utc_offset(std::string_view zone) {
  if (zone == "Z" || zone == "UTC" || zone == "GMT") return 0;
  std::string_view rest;
  if (zone.substr(0, 3) == "UTC" || zone.substr(0, 3) == "GMT") rest = zone.substr(3);
  else return std::nullopt;
  if (rest.empty() || (rest[0] != '+' && rest[0] != '-')) return std::nullopt;
  const int sign = rest[0] == '-' ? -1 : 1;
  std::size_t pos = 1;
  int hours = 0, minutes = 0;
  // One or two hour digits (UTC+5, UTC+05), then optionally :mm or mm.
  if (pos >= rest.size() || rest[pos] < '0' || rest[pos] > '9') return std::nullopt;
  hours = rest[pos++] - '0';
  if (pos < rest.size() && rest[pos] >= '0' && rest[pos] <= '9') hours = hours * 10 + (rest[pos++] - '0');
  if (pos < rest.size()) {
    take(rest, pos, ':');
    if (!digits(rest, pos, 2, minutes)) return std::nullopt;
  }
  if (pos != rest.size() || hours > 14 || minutes > 59 || hours * 60 + minutes > 14 * 60) return std::nullopt;
  return sign * (hours * 60 + minutes);
}

// ---- sun periods -------------------------------------------------------------------------------

void check_sun_period(const SunPeriod& p, const std::string& file, const std::string& place) {
  auto fail = [&](const std::string& key, const std::string& problem) {
    throw InputError({file, key.empty() ? place : place + "." + key}, problem);
  };
  auto finite = [&](double x, const char* key) {
    if (!std::isfinite(x)) fail(key, "expected a finite number, got " + format_number(x));
  };
  finite(p.site.latitude, "latitude");
  if (p.site.latitude < -90 || p.site.latitude > 90)
    fail("latitude", "latitude must be in [-90, 90] degrees (north positive), got " + format_number(p.site.latitude));
  finite(p.site.longitude, "longitude");
  if (p.site.longitude < -180 || p.site.longitude > 180)
    fail("longitude", "longitude must be in [-180, 180] degrees (east positive), got " +
                          format_number(p.site.longitude));
  finite(p.site.elevation, "elevation");
  if (p.site.elevation < -1000 || p.site.elevation > 100000)
    fail("elevation", "elevation must be in [-1000, 100000] metres above sea level, got " +
                          format_number(p.site.elevation));
  finite(p.site.pressure, "pressure");
  // 0 is NREL SPA's lower end too: no air, no refraction, the geometric position.
  if (!(p.site.pressure >= 0) || p.site.pressure > 5000)
    fail("pressure", "pressure must be in [0, 5000] millibars (0: no refraction), got " +
                         format_number(p.site.pressure));
  finite(p.site.temperature, "temperature");
  if (!(p.site.temperature > -273.15) || p.site.temperature > 1000)
    fail("temperature", "temperature must be in (-273.15, 1000] degrees Celsius, got " +
                            format_number(p.site.temperature));
  finite(p.utc_offset_hours, "utc_offset");
  if (p.utc_offset_hours < -14 || p.utc_offset_hours > 14)
    fail("utc_offset", "utc_offset must be in [-14, 14] hours, got " + format_number(p.utc_offset_hours));
  const double offset_minutes = p.utc_offset_hours * 60.0;
  if (std::abs(offset_minutes - std::round(offset_minutes)) > 1e-9)
    fail("utc_offset", "utc_offset must be a whole number of minutes (5.5 for UTC+05:30), got " +
                           format_number(p.utc_offset_hours));
  finite(p.north_axis, "north_axis");
  finite(p.delta_t, "delta_t");
  if (std::abs(p.delta_t) > 1e6)
    fail("delta_t", "delta_t (TT - UT, seconds) must be within +-1e6, got " + format_number(p.delta_t));
  finite(p.angular_diameter, "angular_diameter");
  // The bound of core/lights.hpp's max_angular_diameter (sun/ does not include core/).
  if (p.angular_diameter < 0 || p.angular_diameter > 60)
    fail("angular_diameter", "angular_diameter must be in [0, 60] degrees (0: point suns; the sun's disk is about "
                             "0.53), got " + format_number(p.angular_diameter));
  finite(p.min_elevation, "min_elevation");
  if (p.min_elevation < -90 || p.min_elevation > 90)
    fail("min_elevation", "min_elevation must be in [-90, 90] degrees, got " + format_number(p.min_elevation));

  const bool period = !p.start.empty() || !p.end.empty();
  if (period && !p.times.empty())
    fail("", "give either a period (\"start\", \"end\", \"step_minutes\") or \"times\", not both");
  if (!period) {
    if (p.times.empty()) fail("", "missing \"start\" and \"end\" (a period of local dates) or \"times\"");
    if (p.times.size() > max_sun_instants)
      fail("times", std::to_string(p.times.size()) + " times; at most " + std::to_string(max_sun_instants) +
                        " instants are allowed");
    for (std::size_t i = 1; i < p.times.size(); ++i)
      if (p.times[i] <= p.times[i - 1])
        throw InputError({file, place + ".times[" + std::to_string(i) + "]"},
                         format_iso8601_utc(p.times[i]) + " is not after the time before it (" +
                             format_iso8601_utc(p.times[i - 1]) + "); times must be strictly increasing");
    return;
  }
  if (p.start.empty()) fail("", "missing \"start\" (the first local date, YYYY-MM-DD)");
  if (p.end.empty()) fail("", "missing \"end\" (the last local date, YYYY-MM-DD, inclusive)");
  const std::optional<std::int64_t> start = parse_iso_date(p.start);
  if (!start) fail("start", "expected a date YYYY-MM-DD that exists, got \"" + escape_control(p.start) + "\"");
  const std::optional<std::int64_t> end = parse_iso_date(p.end);
  if (!end) fail("end", "expected a date YYYY-MM-DD that exists, got \"" + escape_control(p.end) + "\"");
  if (*end < *start) fail("end", "end " + p.end + " is before start " + p.start);
  if (p.step_minutes <= 0 || 1440 % p.step_minutes != 0)
    fail("step_minutes", "step_minutes must divide a day (1440 minutes: 1, 5, 10, 15, 30, 60, 120, ...), got " +
                             std::to_string(p.step_minutes));
  const std::int64_t count = (*end - *start + 1) * (1440 / p.step_minutes);
  if (count > static_cast<std::int64_t>(max_sun_instants))
    fail("", "the period has " + std::to_string(count) + " instants; at most " +
                 std::to_string(max_sun_instants) + " are allowed (a longer step or a shorter period)");
}

std::vector<SunInstant> expand_sun_period(const SunPeriod& p, unsigned threads) {
  check_sun_period(p);
  std::vector<UtcSeconds> times = p.times;
  if (times.empty()) {
    const std::int64_t start = *parse_iso_date(p.start), end = *parse_iso_date(p.end);
    const std::int64_t offset_seconds = std::llround(p.utc_offset_hours * 3600.0);
    const std::int64_t step = std::int64_t{p.step_minutes} * 60;
    // (SunPeriod::energyplus_times: EnergyPlus's sun of each step, at its end or its middle)
    const std::int64_t first = !p.energyplus_times ? 0 : step < 3600 ? step : step / 2;
    times.reserve(static_cast<std::size_t>((end - start + 1) * (86400 / step)));
    for (std::int64_t day = start; day <= end; ++day)
      for (std::int64_t local = first; local < first + 86400; local += step)
        times.push_back(day * 86400 + local - offset_seconds);
  }
  // Each position on its own (the solar position algorithm's periodic terms: some 35,000
  // instructions an instant), in blocks on every thread asked for.
  std::vector<SunInstant> instants(times.size());
  constexpr std::size_t kBlock = 256;
  // (Clamped like the readers' counts: validation names a count above the limit as the error.)
  const unsigned workers = times.size() < 2 * kBlock ? 1u : std::min(runtime::resolve_threads(threads), runtime::kMaxThreads);
  runtime::parallel_for_blocks(times.size(), kBlock, workers, [&](unsigned, std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      instants[i].time = times[i];
      instants[i].position = solar_position(p.site, times[i], p.north_axis, p.delta_t);
    }
  });
  return instants;
}

std::vector<SunInstant> expand_sun_period(const SunPeriod& period) { return expand_sun_period(period, 1); }

std::string sun_light_name(UtcSeconds time) { return "sun " + format_iso8601_utc(time); }

void add_sun_lights(Scene& scene, const SunPeriod& period, unsigned threads) {
  const std::string file = scene.source.string();
  check_sun_period(period, file);
  std::vector<SunInstant> instants = expand_sun_period(period, threads);
  std::set<std::string> taken;
  for (const Light& light : scene.lights) taken.insert(light.name);
  std::size_t above = 0;
  for (SunInstant& instant : instants) {
    if (!(instant.position.elevation > period.min_elevation)) continue;
    Light light;
    light.name = sun_light_name(instant.time);
    if (!taken.insert(light.name).second)
      throw InputError({file, "sun"}, "the light name \"" + light.name +
                                          "\" of a sun is already taken by another light; rename that light");
    light.type = LightType::Directional;
    light.to_light = instant.position.to_light;
    light.angular_diameter = period.angular_diameter;
    light.intensity = 1.0;
    light.color = {1.0, 1.0, 1.0};
    instant.light_id = scene.lights.size();
    scene.lights.push_back(std::move(light));
    ++above;
  }
  // Not an error (a winter night is a fair question), but nothing will be lit by the sun.
  if (above == 0)
    scene.warnings.push_back({{file, "sun"}, "the sun is at or below min_elevation (" +
                                                 format_number(period.min_elevation) + " degrees) at every one of the " +
                                                 std::to_string(instants.size()) +
                                                 " instants: no sun lights were added"});
  scene.sun = period;
  scene.sun_instants = std::move(instants);
}

void add_sun_lights(Scene& scene, const SunPeriod& period) { add_sun_lights(scene, period, 1); }

void replace_sun_lights(Scene& scene, const SunPeriod& period, unsigned threads) {
  // Checked before anything changes: on an error the scene keeps its period and lights.
  check_sun_period(period, scene.source.string());
  std::vector<char> is_sun(scene.lights.size(), 0);
  for (const SunInstant& instant : scene.sun_instants)
    if (instant.light_id < scene.lights.size()) is_sun[instant.light_id] = 1;
  std::vector<Light> kept;
  for (std::size_t l = 0; l < scene.lights.size(); ++l)
    if (!is_sun[l]) kept.push_back(std::move(scene.lights[l]));
  scene.lights = std::move(kept);
  scene.sun.reset();
  scene.sun_instants.clear();
  // The old period's own warning goes with it (add_sun_lights says it again where it holds).
  const std::string night = "the sun is at or below min_elevation";
  scene.warnings.erase(std::remove_if(scene.warnings.begin(), scene.warnings.end(),
                                      [&](const Warning& w) {
                                        return w.where.place == "sun" && w.message.rfind(night, 0) == 0;
                                      }),
                       scene.warnings.end());
  add_sun_lights(scene, period, threads);
}

void replace_sun_lights(Scene& scene, const SunPeriod& period) { replace_sun_lights(scene, period, 1); }

}  // namespace shadow
