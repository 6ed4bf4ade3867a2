// SPDX-License-Identifier: GPL-3.0-or-later
// The text files of a sun series: sunlit.csv (per instant, UTC) and energyplus-shading.csv (per
// time step of a whole year, local standard time, as EnergyPlus's Schedule:File:Shading reads
// it). Conventions and their sources: docs/series.md.
#include "writers/series_rows.hpp"

#include <shadow/error.hpp>
#include <shadow/series_files.hpp>
#include <shadow/series.hpp>
#include <shadow/sun.hpp>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unordered_map>

namespace shadow {
namespace {

constexpr std::int64_t kDay = 86400;

// The calendar is shadow/sun.hpp's (days_from_civil, civil_from_days): one implementation.
bool is_leap(std::int64_t y) { return is_valid_date(y, 2, 29); }

/// Days from 1970-01-01 to January 1st of year y.
std::int64_t days_to_year(std::int64_t y) { return days_from_civil(y, 1, 1); }

struct Civil {
  std::int64_t year;
  int month;  // 1..12
  int day;    // 1..31
  int second_of_day;
};

/// The calendar date and time of `t` seconds since 1970-01-01T00:00:00 (no leap seconds).
Civil civil(std::int64_t t) {
  std::int64_t days = t / kDay;
  std::int64_t rest = t % kDay;
  if (rest < 0) {
    rest += kDay;
    --days;
  }
  const CivilDate date = civil_from_days(days);
  return {date.year, date.month, date.day, static_cast<int>(rest)};
}

/// Shortest decimal form that reads back as the same double.
std::string number(double value) {
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (error != std::errc()) return "nan";
  return std::string(buffer, end);
}

/// The longest shortest form of a double ("-2.2250738585072014e-308"), without its comma.
constexpr std::size_t kMostNumberChars = 24;

/// `,value` for each of `values`, as number() writes them, then the line's end, appended to
/// `row` and written to `out` at once. A year's sunlit.csv is some 27 million values: each one
/// through the stream (a sentry, a temporary string) had cost three times as much as the digits.
/// The fractions of faces turned away (0) and unshadowed (1), most of a row, skip the shortest-
/// digits search: to_chars gives "0" and "1" for them too.
void write_values_line(std::ostream& out, std::string& row, const std::vector<double>& values, const char* line_end) {
  const std::size_t start = row.size();
  row.resize(start + values.size() * (1 + kMostNumberChars) + std::strlen(line_end));
  char* p = row.data() + start;
  for (const double f : values) {
    *p++ = ',';
    if (f == 0.0 && !std::signbit(f)) {
      *p++ = '0';
    } else if (f == 1.0) {
      *p++ = '1';
    } else {
      const auto [end, error] = std::to_chars(p, p + kMostNumberChars, f);
      if (error != std::errc()) throw std::logic_error("series CSV row: a value longer than a double's shortest form");
      p = end;
    }
  }
  for (const char* c = line_end; *c != '\0'; ++c) *p++ = *c;
  out.write(row.data(), static_cast<std::streamsize>(p - row.data()));
}

std::int64_t offset_seconds(const SunPeriod& period) {
  return static_cast<std::int64_t>(std::llround(period.utc_offset_hours * 3600.0));
}

/// The time step (row) of the year whose sun EnergyPlus takes at `into` seconds after the year's
/// first local second: the step that ends there when steps are shorter than an hour, the hour
/// whose middle it is with one step an hour (SolarShading.cc, FigureSunCosines); -1 for an
/// instant at no such time, or before the year (SunPeriod::energyplus_times places them there).
std::int64_t energyplus_row(std::int64_t into, std::int64_t step) {
  const std::int64_t at = step < 3600 ? step : step / 2;
  if (into < at || (into - at) % step != 0) return -1;
  return (into - at) / step;
}

}  // namespace


std::string csv_field(const std::string& text) {
  const bool quote = text.find_first_of(",\"\r\n") != std::string::npos ||
                     (!text.empty() && (text.front() == ' ' || text.back() == ' '));
  if (!quote) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

void write_sun_hours_by_object_csv(std::ostream& out, const ObjectSunHours& objects) {
  out << "object,type,faces,area,sun_hours,sunlit_area_hours\r\n";
  for (std::size_t i = 0; i < objects.objects.size(); ++i)
    out << csv_field(objects.objects[i].id) << ',' << csv_field(objects.objects[i].type) << ',' << objects.faces[i]
        << ',' << number(objects.area[i]) << ',' << number(objects.sun_hours[i]) << ','
        << number(objects.sunlit_area_hours[i]) << "\r\n";
}

void write_sunlit_csv(std::ostream& out, const SunSeries& suns, const SurfaceSeries& surfaces) {
  detail::write_sunlit_header(out, surfaces.surfaces);
  std::vector<double> fractions(surfaces.surfaces.size());
  for (std::size_t i = 0; i < surfaces.instants; ++i) {
    for (std::size_t s = 0; s < fractions.size(); ++s) fractions[s] = surfaces.lit_fraction[s * surfaces.instants + i];
    detail::write_sunlit_row(out, suns, i, fractions);
  }
}

namespace detail {

void write_sunlit_header(std::ostream& out, const std::vector<NamedSurface>& surfaces) {
  out << "time";
  for (const NamedSurface& s : surfaces) out << ',' << csv_field(s.label);
  out << "\r\n";
}

void write_sunlit_row(std::ostream& out, const SunSeries& suns, std::size_t i, const std::vector<double>& fractions) {
  thread_local std::string row;  // (its room kept from one row to the next)
  row.clear();
  if (i < suns.times.size()) row += format_iso8601_utc(suns.times[i]);
  write_values_line(out, row, fractions, "\r\n");
}

}  // namespace detail

EnergyPlusSchedule energyplus_schedule(const Scene& scene) {
  EnergyPlusSchedule schedule;
  if (!scene.sun) {
    schedule.reason = "the scene has no sun block";
    return schedule;
  }
  const SunPeriod& period = *scene.sun;
  if (!period.times.empty()) {
    schedule.reason = "the sun is given as explicit times, not a period of regular steps: EnergyPlus needs one value per time step";
    return schedule;
  }
  if (period.step_minutes <= 0 || 60 % period.step_minutes != 0) {
    schedule.reason = "step_minutes " + std::to_string(period.step_minutes) +
                      " does not divide an hour: EnergyPlus's time steps are 60 / (1 to 60) minutes";
    return schedule;
  }
  if (scene.sun_instants.empty()) {
    schedule.reason = "the period has no instants";
    return schedule;
  }
  if (!period.energyplus_times) {
    schedule.reason = "the period's instants start their time steps, but EnergyPlus takes each step's sun at its end "
                      "(mid-hour with one step an hour): set the sun block's \"energyplus_times\" to true "
                      "(SunPeriod::energyplus_times)";
    return schedule;
  }
  {
    // EnergyPlus upper-cases names: two columns that differ only by case would be one surface
    // to it, and it would read only one of them.
    std::unordered_map<std::string, std::string> seen;
    for (const NamedSurface& s : named_surfaces(scene)) {
      const auto [it, inserted] = seen.emplace(energyplus_name(s.label), s.label);
      if (!inserted) {
        schedule.reason = "the surfaces \"" + it->second + "\" and \"" + s.label +
                          "\" differ only by case: EnergyPlus upper-cases names, so they would be one column (rename one)";
        return schedule;
      }
    }
  }
  const std::int64_t offset = offset_seconds(period);
  // (The first instant is at its step's end or middle: never at the year's first second.)
  schedule.year = static_cast<int>(civil(scene.sun_instants.front().time + offset - 1).year);
  schedule.timesteps_per_hour = 60 / period.step_minutes;
  const std::size_t days = is_leap(schedule.year) ? 366 : 365;
  schedule.rows = days * 24 * static_cast<std::size_t>(schedule.timesteps_per_hour);
  const std::int64_t year_start = days_to_year(schedule.year) * kDay;
  const std::int64_t step = static_cast<std::int64_t>(period.step_minutes) * 60;
  std::size_t outside = 0;
  for (const SunInstant& instant : scene.sun_instants) {
    const std::int64_t row = energyplus_row(instant.time + offset - year_start, step);
    if (row < 0 || row >= static_cast<std::int64_t>(schedule.rows))
      ++outside;
    else
      ++schedule.rows_in_period;
  }
  schedule.written = true;
  if (schedule.rows_in_period < schedule.rows)
    schedule.reason = "the period covers " + std::to_string(schedule.rows_in_period) + " of the year's " +
                      std::to_string(schedule.rows) + " time steps; the others are 0, fully shaded (EnergyPlus reads a whole year)";
  if (outside > 0)
    schedule.reason += std::string(schedule.reason.empty() ? "" : "; ") + std::to_string(outside) +
                       " instants after the year " + std::to_string(schedule.year) + " are left out";
  return schedule;
}

bool energyplus_shading_wanted(const Scene& scene) {
  if (scene.energyplus_shading) return *scene.energyplus_shading;
  for (const Mesh& mesh : scene.meshes)
    if (mesh.model == "energyplus") return true;
  return false;
}

std::string energyplus_name(const std::string& name) {
  std::string upper = name;
  for (char& c : upper)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return upper;
}

EnergyPlusSchedule write_energyplus_shading_csv(std::ostream& out, const Scene& scene, const SunSeries& suns,
                                                const SurfaceSeries& surfaces) {
  const EnergyPlusSchedule schedule = energyplus_schedule(scene);
  if (!schedule.written) return schedule;
  detail::EnergyPlusRows rows(scene, suns, surfaces.instants, surfaces.surfaces.size(), schedule);
  rows.header(out, surfaces.surfaces);
  std::vector<double> fractions(surfaces.surfaces.size());
  for (std::size_t i = 0; i < surfaces.instants; ++i) {
    for (std::size_t s = 0; s < fractions.size(); ++s) fractions[s] = surfaces.lit_fraction[s * surfaces.instants + i];
    rows.instant(out, i, fractions);
  }
  return rows.finish(out);
}

namespace detail {

EnergyPlusRows::EnergyPlusRows(const Scene& scene, const SunSeries& suns, std::size_t instants,
                               std::size_t surfaces, EnergyPlusSchedule schedule)
    : schedule_(std::move(schedule)), surfaces_(surfaces) {
  const SunPeriod& period = *scene.sun;
  const std::int64_t offset = offset_seconds(period);
  year_start_ = days_to_year(schedule_.year) * kDay;
  step_ = static_cast<std::int64_t>(period.step_minutes) * 60;
  // Which series column fills each row (rows without one are night or outside the period: 0).
  column_.assign(schedule_.rows, SIZE_MAX);
  for (std::size_t i = 0; i < suns.times.size() && i < instants; ++i) {
    const std::int64_t row = energyplus_row(suns.times[i] + offset - year_start_, step_);
    if (row >= 0 && row < static_cast<std::int64_t>(schedule_.rows)) column_[static_cast<std::size_t>(row)] = i;
  }
  fills_.assign(instants, false);
  for (const std::size_t i : column_)
    if (i != SIZE_MAX) fills_[i] = true;
}

void EnergyPlusRows::header(std::ostream& out, const std::vector<NamedSurface>& surfaces) const {
  out << "Surface Name";
  // EnergyPlus's own spelling of the names (upper case), or its header match finds none.
  for (const NamedSurface& s : surfaces) out << ',' << csv_field(energyplus_name(s.label));
  out << '\n';
}

void EnergyPlusRows::instant(std::ostream& out, std::size_t i, const std::vector<double>& fractions) {
  // Only an instant that fills a row is kept (a later instant in the same step replaces it, as
  // column_ says); it waits until the rows before its own are written.
  if (i >= fills_.size() || !fills_[i]) return;
  waiting_[i] = fractions;
  write_ready(out);
}

void EnergyPlusRows::write_ready(std::ostream& out) {
  char stamp[16];
  for (; next_row_ < schedule_.rows; ++next_row_) {
    const std::size_t i = column_[next_row_];
    const auto found = i == SIZE_MAX ? waiting_.end() : waiting_.find(i);
    if (i != SIZE_MAX && found == waiting_.end()) return;  // its instant has not come yet
    // Stamped at the step's end, EnergyPlus's convention for a time step; midnight is 24:00 of
    // the day that ends.
    const std::int64_t end = year_start_ + static_cast<std::int64_t>(next_row_ + 1) * step_;
    const Civil day = civil(end - 1);
    const int minute = static_cast<int>(((end - year_start_) % kDay) / 60);
    const int shown = minute == 0 ? 24 * 60 : minute;
    std::snprintf(stamp, sizeof stamp, "%02d/%02d %02d:%02d", day.month, day.day, shown / 60, shown % 60);
    row_.assign(stamp);
    if (i == SIZE_MAX) {  // a step without an instant (night, outside the period): zeros
      row_.reserve(row_.size() + 2 * surfaces_ + 1);
      for (std::size_t s = 0; s < surfaces_; ++s) row_ += ",0";
      row_ += '\n';
      out.write(row_.data(), static_cast<std::streamsize>(row_.size()));
    } else {
      write_values_line(out, row_, found->second, "\n");
      waiting_.erase(found);
    }
  }
}

const EnergyPlusSchedule& EnergyPlusRows::finish(std::ostream& out) {
  write_ready(out);
  return schedule_;
}

}  // namespace detail

}  // namespace shadow
