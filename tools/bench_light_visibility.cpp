// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench light-visibility: the exact visible fraction of extended lights
// (shadow/area_lights.hpp) at seeded ground points of a generated city: a 0.53-degree sun disk
// at 35 degrees of elevation, a disk lamp and a rectangular area light above the city, timed
// with each thread count, with how many points are in a penumbra (docs/area-light-visibility.md).
#include "bench_light_visibility.hpp"

#include <shadow/shadow.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace bench {

int run_light_visibility(std::size_t boxes, std::size_t point_count, unsigned max_threads) {
  const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
  const shadow::Scene scene = shadow::make_city(boxes, extent, 20261126);
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> on_ground(-0.5 * extent, 0.5 * extent);
  std::vector<shadow::SurfacePoint> points;
  for (std::size_t i = 0; i < point_count; ++i) points.push_back({0, {on_ground(rng), on_ground(rng), 0.0}});

  std::vector<std::pair<std::string, shadow::Light>> lights;
  shadow::Light sun;
  sun.type = shadow::LightType::Directional;
  sun.to_light = shadow::sun_direction(35.0, 200.0);
  sun.angular_diameter = 0.53;
  lights.emplace_back("sun disk 0.53 deg", sun);
  shadow::Light disk;
  disk.type = shadow::LightType::Disk;
  disk.position = {0.0, 0.0, 60.0};
  disk.normal = {0.0, 0.0, -1.0};
  disk.radius = 10.0;
  lights.emplace_back("disk r 10 m at 60 m", disk);
  shadow::Light area;
  area.type = shadow::LightType::Area;
  area.polygon = {{-15, -5, 60}, {-15, 5, 60}, {15, 5, 60}, {15, -5, 60}};  // facing down
  lights.emplace_back("area 30 x 10 m at 60 m", area);

  std::printf("city of %zu boxes (%zu faces), %zu ground points\n", boxes, scene.faces.size(), point_count);
  std::printf("%-24s %8s %8s %10s %12s %10s %10s\n", "light", "threads", "what", "wall_s", "points/s", "penumbra",
              "mean_vis");
  for (const auto& [name, light] : lights) {
    for (unsigned threads = 1; threads <= max_threads; threads *= 2) {
      for (int what = 0; what < 2; ++what) {
        const auto start = std::chrono::steady_clock::now();
        const std::vector<double> values = what == 0 ? shadow::light_visibility(scene, light, points, threads)
                                                     : shadow::light_irradiance(scene, light, points, threads);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::size_t penumbra = 0;
        double mean = 0.0;
        if (what == 0) {
          for (double v : values) {
            penumbra += v > 0.0 && v < 1.0;
            mean += v;
          }
          mean /= static_cast<double>(values.size());
        }
        std::printf("%-24s %8u %8s %10.3f %12.0f %10zu %10.4f\n", name.c_str(), threads,
                    what == 0 ? "fraction" : "irrad.", wall, static_cast<double>(values.size()) / wall, penumbra, mean);
      }
    }
  }
  return 0;
}

}  // namespace bench
