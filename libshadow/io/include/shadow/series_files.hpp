// SPDX-License-Identifier: GPL-3.0-or-later
/// @file series_files.hpp
/// @brief The CSV files of a sun series (io component): sunlit.csv, sun_hours_by_object.csv and
/// EnergyPlus's Schedule:File:Shading table. The series itself is computed by shadow/series.hpp.
/// See docs/series.md.
#pragma once

#include <shadow/scene.hpp>
#include <shadow/series.hpp>
#include <shadow/sun.hpp>

#include <cstddef>
#include <ostream>
#include <string>

namespace shadow {

/// `sun_hours_by_object.csv`: header `object,type,faces,area,sun_hours,sunlit_area_hours`, one
/// row per object in scene order; numbers in shortest round-trip form, names quoted as
/// csv_field() does, CRLF line ends (RFC 4180).
void write_sun_hours_by_object_csv(std::ostream& out, const ObjectSunHours& objects);

/// One CSV field as RFC 4180 writes it: quoted (quotes doubled) when it holds a comma, a quote,
/// a carriage return or a line feed, or starts or ends with a space; as is otherwise.
std::string csv_field(const std::string& text);

/// `sunlit.csv`: header `time,<surface>,...`, one row per instant of the series (ISO 8601 UTC),
/// each surface's lit fraction in shortest round-trip form. CRLF line ends (RFC 4180).
void write_sunlit_csv(std::ostream& out, const SunSeries& suns, const SurfaceSeries& surfaces);

/// How energyplus-shading.csv covers the year (see docs/series.md).
struct EnergyPlusSchedule {
  bool written = false;          ///< false when the series cannot be one (reason says why)
  std::string reason;            ///< why not written, or a note on what was written
  int year = 0;                  ///< the calendar year (local standard time) of the first instant
  int timesteps_per_hour = 0;    ///< 60 / step_minutes
  std::size_t rows = 0;          ///< 24 x timesteps_per_hour x (365 or 366)
  std::size_t rows_in_period = 0;  ///< rows that an instant of the period fills (the rest are 0)
};

/// Whether and how `scene.sun` maps onto EnergyPlus's year of time steps: a period (not
/// explicit times) whose step divides an hour, in one calendar year, and receiving surfaces
/// whose names stay distinct in upper case (EnergyPlus's own names: energyplus_name()).
EnergyPlusSchedule energyplus_schedule(const Scene& scene);

/// Whether a sun series of `scene` should write energyplus-shading.csv unasked: the scene
/// file's `energyplus_shading` when given, else whether a mesh comes from an EnergyPlus model
/// (Mesh::model "energyplus"). A CityJSON city or an OBJ scene gets none unless asked.
bool energyplus_shading_wanted(const Scene& scene);

/// A surface name as EnergyPlus holds it, and writes it in its own eplusshading.csv: upper
/// case (ASCII letters; other bytes as they are). EnergyPlus 9.6 upper-cases every object name
/// on input and matches a Schedule:File:Shading header against those names case-sensitively,
/// so a header column in the IDF's mixed case would match nothing.
std::string energyplus_name(const std::string& name);

/// `energyplus-shading.csv` for Schedule:File:Shading: header `Surface Name,<SURFACE>,...`
/// (names upper-cased by energyplus_name()),
/// one row per time step of the whole year, stamped `MM/DD hh:mm` at the step's end (local
/// standard time; the last is `12/31 24:00`); a row holds the lit fraction of the instant that
/// starts its step, 0 at night and outside the period.
/// @returns the schedule written (written = false, nothing written, when it cannot be one)
EnergyPlusSchedule write_energyplus_shading_csv(std::ostream& out, const Scene& scene, const SunSeries& suns,
                                                const SurfaceSeries& surfaces);

}  // namespace shadow
