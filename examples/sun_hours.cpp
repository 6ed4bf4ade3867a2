// SPDX-License-Identifier: GPL-3.0-or-later
// Sun-hours on a courtyard floor: one ShadowEngine, many sun positions over a day. The engine
// prepares the exact face data once; each hour is one compute() call on areas only. The suns
// come from NREL's Solar Position Algorithm (shadow/sun.hpp) for Bordeaux on the March equinox.
// Then the exact sun-hours map of the floor (shadow/sun_hours.hpp): where on it each number of
// hours falls.
#include <shadow/shadow.hpp>

#include <cstdio>
#include <map>
#include <vector>

int main() {
  shadow::Scene scene;
  // A 12 x 12 m courtyard floor enclosed by 8 m high blocks on three sides (+y is north).
  const std::size_t floor = shadow::add_mesh(scene, "courtyard", {shadow::rectangle_z(0, 0, 12, 12, 0)});
  std::vector<shadow::Polygon3> blocks;
  for (const auto& b : {shadow::box_faces({-6, 0, 0}, {0, 12, 8}), shadow::box_faces({12, 0, 0}, {18, 12, 8}),
                        shadow::box_faces({-6, 12, 0}, {18, 18, 8})})
    blocks.insert(blocks.end(), b.begin(), b.end());
  shadow::add_mesh(scene, "blocks", blocks, /*receiver=*/false);
  shadow::validate_scene(scene);

  // Bordeaux, 44.84 N 0.58 W, local standard time UTC+01:00, one sun at the start of each hour.
  shadow::SunPeriod day;
  day.site.latitude = 44.84;
  day.site.longitude = -0.58;
  day.utc_offset_hours = 1.0;
  day.start = day.end = "2026-03-20";
  day.step_minutes = 60;

  const shadow::ShadowEngine engine(scene);
  shadow::ShadowOptions options;
  options.polygons = false;  // areas only: no work for outputs nobody asked for
  double sun_hours = 0;      // hours of full sun on the whole floor: each hourly sun stands for its hour
  std::vector<shadow::SunHoursInstant> instants;  // each sun stands for one hour
  std::printf("time (UTC)            elevation  azimuth  lit fraction\n");
  for (const shadow::SunInstant& instant : shadow::expand_sun_period(day)) {
    if (instant.position.elevation <= 0) continue;
    const shadow::Light sun = shadow::directional_light("sun", instant.position.to_light);
    instants.push_back({sun, 1.0});
    const shadow::ShadowResult r = engine.compute(sun, 0, options);
    const double fraction = r.find(floor, 0)->lit_fraction;
    sun_hours += fraction;
    std::printf("%s  %9.2f  %7.2f  %.6f\n", shadow::format_iso8601_utc(instant.time).c_str(),
                instant.position.elevation, instant.position.azimuth, fraction);
  }
  std::printf("courtyard floor: %.4f sun-hours (hourly samples)\n", sun_hours);

  // The map: the floor cut along every sun's exact shadow edge, each cell with its hours.
  const shadow::SunHoursMap map = shadow::compute_sun_hours_map(engine, {floor}, instants);
  std::map<double, double> area_by_hours;
  for (const shadow::SunHoursCell& cell : map.cells) area_by_hours[cell.sun_hours] += cell.area;
  std::printf("hours  floor area (m2)\n");
  for (const auto& [hours, area] : area_by_hours) std::printf("%5.0f  %15.4f\n", hours, area);
  // The map's mean over the floor is the same number as above: the integral of hours.
  std::printf("courtyard floor: %.4f sun-hours (mean of the exact map, %zu cells)\n",
              map.faces[0].hour_area / map.faces[0].area, map.cells.size());
  return 0;
}
