// SPDX-License-Identifier: GPL-3.0-or-later
// shadow-bench light-visibility: the exact visible fraction of extended lights
// (shadow/area_lights.hpp) at seeded ground points of a generated city: a 0.53-degree sun disk
// at 35 degrees of elevation, a disk lamp and a rectangular area light above the city, timed
// with each thread count, with how many points are in a penumbra (docs/area-light-visibility.md).
#include "bench_light_visibility.hpp"

#include <shadow/shadow.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
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

namespace {

/// FNV-1a over the bits of the values.
struct Checksum {
  std::uint64_t h = 1469598103934665603ull;
  void add(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int i = 0; i < 8; ++i) h = (h ^ ((bits >> (8 * i)) & 0xffu)) * 1099511628211ull;
  }
};

}  // namespace

int run_area_city(std::size_t boxes, double diameter, unsigned threads) {
  const double extent = 500.0 * std::sqrt(static_cast<double>(boxes) / 1000.0);
  shadow::Scene scene = shadow::make_city(boxes, extent, 2026);
  shadow::Light sun;
  sun.type = shadow::LightType::Directional;
  sun.name = "sun";
  sun.to_light = shadow::sun_direction(35.0, 200.0);
  sun.angular_diameter = diameter;
  scene.lights = {sun};
  shadow::ShadowOptions options;
  options.threads = threads;
  const auto start = std::chrono::steady_clock::now();
  const shadow::ShadowEngine engine(scene, threads);
  const shadow::ShadowResult result = engine.compute(options);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<shadow::Fragment> fragments = result.fragments;
  const auto start_vis = std::chrono::steady_clock::now();
  shadow::fill_fragment_visibility(scene, scene.lights[0], fragments, threads);
  const double vis = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_vis).count();
  Checksum areas, cells;
  std::size_t vertices = 0;
  for (const shadow::FaceLighting& f : result.lighting)
    for (double v : {f.lit_area, f.shadow_area, f.fully_lit_area, f.penumbra_area, f.umbra_area}) areas.add(v);
  for (const shadow::Fragment& f : result.fragments) {
    cells.add(static_cast<double>(f.region));
    for (const glm::dvec3& p : f.polygon) cells.add(p.x), cells.add(p.y), cells.add(p.z);
    for (double v : f.visibility) cells.add(v);
    vertices += f.polygon.size();
  }
  std::printf("city of %zu boxes (%zu faces), sun disk %.2f deg at 35 deg, %u threads: %zu fragments, %zu vertices\n",
              boxes, scene.faces.size(), diameter, threads, result.fragments.size(), vertices);
  std::printf("compute %.3f s = regions %.3f s + fragment visibility %.3f s\n", total, total - vis, vis);
  std::printf("checksum areas %016llx cells %016llx\n", static_cast<unsigned long long>(areas.h),
              static_cast<unsigned long long>(cells.h));
  return 0;
}

}  // namespace bench
