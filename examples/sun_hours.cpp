// SPDX-License-Identifier: GPL-3.0-or-later
// Sun-hours on a courtyard floor: one ShadowEngine, many sun positions over a day. The engine
// prepares the exact face data once; compute_series computes every hour's sun in one call
// (areas only; docs/series.md).
#include <shadow/shadow.hpp>

#include <cmath>
#include <cstdio>

int main() {
  shadow::Scene scene;
  // A 12 x 12 m courtyard floor enclosed by 8 m high blocks on three sides.
  const std::size_t floor = shadow::add_mesh(scene, "courtyard", {shadow::rectangle_z(0, 0, 12, 12, 0)});
  std::vector<shadow::Polygon3> blocks;
  for (const auto& b : {shadow::box_faces({-6, 0, 0}, {0, 12, 8}), shadow::box_faces({12, 0, 0}, {18, 12, 8}),
                        shadow::box_faces({-6, 12, 0}, {18, 18, 8})})
    blocks.insert(blocks.end(), b.begin(), b.end());
  shadow::add_mesh(scene, "blocks", blocks, /*receiver=*/false);
  shadow::validate_scene(scene);

  // The suns of the day, then one compute_series call: every sun on every receiving face, areas
  // only, without a result per sun (the same values as one compute(light) per sun, bit for bit).
  std::vector<shadow::Light> suns;
  std::vector<int> hours;
  std::vector<double> elevations, azimuths;
  for (int hour = 7; hour <= 17; ++hour) {
    // A simple equinox sun path at 45 degrees latitude: noon elevation 45, azimuth 90..270.
    const double h = (hour - 12) * 15.0 * M_PI / 180.0, lat = 45.0 * M_PI / 180.0;
    const double elevation = std::asin(std::cos(lat) * std::cos(h)) * 180.0 / M_PI;
    const double azimuth = 180.0 + std::atan2(std::sin(h), std::cos(h) * std::sin(lat)) * 180.0 / M_PI;
    if (elevation <= 0) continue;
    suns.push_back(shadow::directional_light("sun", shadow::sun_direction(elevation, azimuth)));
    hours.push_back(hour);
    elevations.push_back(elevation);
    azimuths.push_back(azimuth);
  }
  const shadow::ShadowEngine engine(scene);
  const shadow::SeriesResult series = engine.compute_series(suns);
  // Each hourly sample stands for its hour: sun hours = sum of lit fractions x 1 h.
  const std::vector<double> sun_hours = shadow::sun_hours(series, 1.0);
  std::printf("hour  elevation  azimuth  lit fraction\n");
  for (std::size_t i = 0; i < suns.size(); ++i)
    std::printf("%4d  %9.2f  %7.2f  %.6f\n", hours[i], elevations[i], azimuths[i],
                series.lit_fraction[series.at(0, i)]);  // row 0: the floor, the only receiver
  std::printf("courtyard floor (face %zu): %.4f sun-hours (hourly samples)\n", floor, sun_hours[0]);
  return 0;
}
