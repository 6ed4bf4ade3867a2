// SPDX-License-Identifier: GPL-3.0-or-later
// Sun-hours on a courtyard floor: one ShadowEngine, many sun positions over a day. The engine
// prepares the exact face data once; each hour is one compute() call on areas only.
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

  const shadow::ShadowEngine engine(scene);
  shadow::ShadowOptions options;
  options.polygons = false;  // areas only: no work for outputs nobody asked for
  double sun_hours = 0;      // hours of full sun on the whole floor, i.e. integral of lit fraction
  std::printf("hour  elevation  azimuth  lit fraction\n");
  for (int hour = 7; hour <= 17; ++hour) {
    // A simple equinox sun path at 45 degrees latitude: noon elevation 45, azimuth 90..270.
    const double h = (hour - 12) * 15.0 * M_PI / 180.0, lat = 45.0 * M_PI / 180.0;
    const double elevation = std::asin(std::cos(lat) * std::cos(h)) * 180.0 / M_PI;
    const double azimuth = 180.0 + std::atan2(std::sin(h), std::cos(h) * std::sin(lat)) * 180.0 / M_PI;
    if (elevation <= 0) continue;
    const shadow::ShadowResult r =
        engine.compute(shadow::directional_light("sun", shadow::sun_direction(elevation, azimuth)), 0, options);
    const double fraction = r.find(floor, 0)->lit_fraction;
    sun_hours += fraction;
    std::printf("%4d  %9.2f  %7.2f  %.6f\n", hour, elevation, azimuth, fraction);
  }
  std::printf("courtyard floor: %.4f sun-hours (hourly samples)\n", sun_hours);
  return 0;
}
